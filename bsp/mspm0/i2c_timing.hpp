// I2C controller timing for the MSPM0: the functional-clock divider, the SCL period (MTPR) and the SCL-low
// timeout (TIMEOUT_CTL.TCNTLA), computed at compile time from the bus clock, the bit rate and the stretch
// limit so a board's choice is checked before it runs.
//
// Facts:
//   SCL period = (1 + TPR) * 10 / f_func, f_func = bus clock / (CLKDIV.RATIO + 1) (mspm0*.tsv "I2C SCL
//   formula" note; SLAU847D 21.2.1.1, SLAU846B 20.2.1.1).
//   Timeout A: TCNTLA is the upper 8 bits of a 12-bit counter whose low 4 bits start at 0, and the counter
//   steps every (1 + TPR) * 12 functional clocks, so the timeout is TCNTLA * 16 * (1 + TPR) * 12 / f_func
//   (SLAU847D 21.2 / SLAU846B 20.2 "clock low timeout", worked example 0xDA at TPR 19 from 20 MHz =
//   41.856 ms; TI's Zephyr driver msp-zephyr drivers/i2c/i2c_mspm0.c i2c_mspm0_configure_timeout counts the
//   same way; TI's SMBus example configurations program 135 for the SMBus 25 ms at 100 kHz from 32 MHz,
//   25.9 ms under it). hw_i2c.h / dl_i2c.h describe the count as 520 functional clocks instead; no TI code
//   uses that reading (bsp/mspm0/README.md, open questions). TCNTLA must be 2..255.
// The count is the smallest that is not shorter than the stretch limit (TI's Zephyr driver truncates; a
// timeout shorter than the device may legally stretch would abort good transfers), so the timeout lies
// within one count (16 * (1 + TPR) * 12 clocks: 48 us at 400 kHz, 192 us at 100 kHz) above the limit. The
// smallest divider for which SCL comes out exact and the count fits is chosen (finest SCL timing).
#pragma once

#include <cstdint>

namespace bsp::mspm0 {

struct I2cTiming {
  uint8_t clkdivRatio = 0;   // CLKDIV.RATIO: divide by ratio + 1
  uint8_t tpr = 0;           // MTPR.TPR
  uint8_t timeoutCount = 0;  // TIMEOUT_CTL.TCNTLA
  bool valid = false;
};

// Functional clocks per TCNTLA count: 16 counter steps of (1 + TPR) * 12 clocks.
constexpr uint64_t i2cClocksPerTimeoutCount(uint32_t tpr) {
  return 16ULL * (1 + tpr) * 12;
}

// ceil(limitUs * f / (clocksPerCount * 1e6)), in 64 bits (32 MHz * 35 ms does not fit 32).
constexpr uint64_t i2cTimeoutCounts(uint32_t stretchLimitUs, uint32_t functionalHz, uint64_t clocksPerCount) {
  const uint64_t perCountUnits = clocksPerCount * 1000000ULL;
  return (uint64_t{stretchLimitUs} * functionalHz + perCountUnits - 1) / perCountUnits;
}

// The SCL-low time after which timeout A fires, in microseconds (truncated).
constexpr uint64_t i2cTimeoutUs(const I2cTiming& t, uint32_t busClockHz) {
  const uint64_t functionalHz = busClockHz / (t.clkdivRatio + 1U);
  return uint64_t{t.timeoutCount} * i2cClocksPerTimeoutCount(t.tpr) * 1000000ULL / functionalHz;
}

constexpr I2cTiming i2cTiming(uint32_t busClockHz, uint32_t bitRate, uint32_t stretchLimitUs) {
  for (uint32_t div = 1; div <= 8; ++div) {
    const uint32_t f = busClockHz / div;
    if (f % (10 * bitRate) != 0) continue;  // SCL must come out exact
    const uint32_t tpr = f / (10 * bitRate) - 1;
    const uint64_t counts = i2cTimeoutCounts(stretchLimitUs, f, i2cClocksPerTimeoutCount(tpr));
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
// The TRM's worked example: TCNTLA 0xDA at TPR 19 from 20 MHz is 41.856 ms.
static_assert(i2cTimeoutUs(I2cTiming{0, 19, 0xDA, true}, 20000000) == 41856);
// SMBus: 25 ms at 100 kHz from 32 MHz is 131 counts (25.15 ms), inside the SMBus tTIMEOUT of
// 25..35 ms (SMBus specification, AC characteristics); TI's SMBus examples program 135 (25.9 ms).
static_assert(i2cTiming(32000000, 100000, 25000).timeoutCount == 131);
static_assert(i2cTimeoutUs(i2cTiming(32000000, 100000, 25000), 32000000) == 25152);

}  // namespace bsp::mspm0
