// I2C controller timing for the MSPM0: the functional-clock divider, the SCL period (MTPR) and the SCL-low
// timeout (TIMEOUT_CTL.TCNTLA), computed at compile time from the bus clock, the bit rate and the stretch
// limit so a board's choice is checked before it runs.
//
// Facts:
//   SCL period = (1 + TPR) * 10 / f_func, f_func = bus clock / (CLKDIV.RATIO + 1) (mspm0*.tsv "I2C SCL
//   formula" note; SLAU847D 21.2.1.1, SLAU846B 20.2.1.1).
//   Timeout A: TI gives two different units for TCNTLA (bsp/mspm0/README.md, open questions):
//     TRM    (SLAU847D 21.2 / SLAU846B 20.2, clock low timeout): TCNTLA is the upper 8 bits of a 12-bit
//            count that steps every (1 + TPR) * 12 functional clocks: TCNTLA * 16 * (1 + TPR) * 12 / f_func.
//            TI's SMBus examples (SysConfig timeoutACount 135 with the default BUSCLK /1 = 32 MHz and
//            100 kHz, TPR 31) program 25.9 ms under it, the SMBus tTIMEOUT, against 2.2 ms under the
//            header's; the TRM's reading is taken as the model's (tests/bsp_mspm0/i2c_model.hpp).
//     header (hw_i2c.h TIMEOUT_CTL.TCNTLA, dl_i2c.h DL_I2C_setTimeoutACount): TCNTLA * 520 / f_func.
//   TCNTLA must be 2..255.
// The timeout must never be shorter than the device may stretch SCL, whichever reading the silicon follows:
// the count is the larger of the two readings' counts for the stretch limit. The smallest divider for which
// that count fits (and SCL comes out exact) is chosen (finest SCL timing).
#pragma once

#include <cstdint>

namespace bsp::mspm0 {

struct I2cTiming {
  uint8_t clkdivRatio = 0;   // CLKDIV.RATIO: divide by ratio + 1
  uint8_t tpr = 0;           // MTPR.TPR
  uint8_t timeoutCount = 0;  // TIMEOUT_CTL.TCNTLA
  bool valid = false;
};

// ceil(limitUs * f / (clocksPerCount * 1e6)), in 64 bits (32 MHz * 35 ms does not fit 32).
constexpr uint64_t i2cTimeoutCounts(uint32_t stretchLimitUs, uint32_t functionalHz, uint64_t clocksPerCount) {
  const uint64_t perCountUnits = clocksPerCount * 1000000ULL;
  return (uint64_t{stretchLimitUs} * functionalHz + perCountUnits - 1) / perCountUnits;
}

constexpr I2cTiming i2cTiming(uint32_t busClockHz, uint32_t bitRate, uint32_t stretchLimitUs) {
  for (uint32_t div = 1; div <= 8; ++div) {
    const uint32_t f = busClockHz / div;
    if (f % (10 * bitRate) != 0) continue;  // SCL must come out exact
    const uint32_t tpr = f / (10 * bitRate) - 1;
    const uint64_t header = i2cTimeoutCounts(stretchLimitUs, f, 520);
    const uint64_t trm = i2cTimeoutCounts(stretchLimitUs, f, 16ULL * (1 + tpr) * 12);
    const uint64_t counts = header > trm ? header : trm;
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
// Under the TRM's reading 25 ms at 100 kHz from 32 MHz (TPR 31: 16 steps of 12 us per count) needs 131
// counts; TI's SMBus examples program 135.
static_assert(i2cTimeoutCounts(25000, 32000000, 16ULL * 32 * 12) == 131);

}  // namespace bsp::mspm0
