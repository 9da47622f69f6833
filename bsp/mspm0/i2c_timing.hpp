// I2C controller timing for the MSPM0: the functional-clock divider, the SCL period (MTPR) and the SCL-low
// timeout (TIMEOUT_CTL.TCNTLA), computed at compile time from the bus clock, the bit rate and the stretch
// limit so a board's choice is checked before it runs.
//
// Facts (mspm0*.tsv "I2C SCL formula" note; i2c_v1 TIMEOUT_CTL description, SLAU846A 19.2.4):
//   SCL period   = (1 + TPR) * 10 / f_func,  f_func = bus clock / (CLKDIV.RATIO + 1)
//   timeout A    = TCNTLA * 520 / f_func (TCNTLA 2..255)
// The smallest divider whose timeout range covers the stretch limit is chosen (finest SCL timing).
#pragma once

#include <cstdint>

namespace bsp::mspm0 {

struct I2cTiming {
  uint8_t clkdivRatio = 0;   // CLKDIV.RATIO: divide by ratio + 1
  uint8_t tpr = 0;           // MTPR.TPR
  uint8_t timeoutCount = 0;  // TIMEOUT_CTL.TCNTLA
  bool valid = false;
};

constexpr I2cTiming i2cTiming(uint32_t busClockHz, uint32_t bitRate, uint32_t stretchLimitUs) {
  for (uint32_t div = 1; div <= 8; ++div) {
    const uint32_t f = busClockHz / div;
    if (f % (10 * bitRate) != 0) continue;  // SCL must come out exact
    const uint32_t tpr = f / (10 * bitRate) - 1;
    // ceil(limit * f / 520 / 1e6), in 64-bit to keep 32 MHz * 35 ms in range.
    const uint64_t counts = (uint64_t{stretchLimitUs} * f + 520ULL * 1000000ULL - 1) / (520ULL * 1000000ULL);
    if (tpr >= 1 && tpr <= 127 && counts >= 2 && counts <= 255) {
      return I2cTiming{static_cast<uint8_t>(div - 1), static_cast<uint8_t>(tpr), static_cast<uint8_t>(counts),
                       true};
    }
  }
  return I2cTiming{};
}

// The TI example's 100 kHz from 32 MHz is TPR 31 (tsv "I2C0 MTPR.TPR"); 400 kHz is TPR 7.
static_assert(i2cTiming(32000000, 100000, 2000).tpr == 31);
static_assert(i2cTiming(32000000, 400000, 2000).tpr == 7);

}  // namespace bsp::mspm0
