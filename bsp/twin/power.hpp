// The MCU's average supply current over a run, COMPUTED (not measured) from the twin's residency in each
// power mode and TI's typical data-sheet currents at 25 degC. It answers "what would the MCU draw with this
// image", for comparing images and power policies; a board's real figure also has the pins' loads, the
// LaunchPad's debugger and regulator, and part-to-part spread, none of which are here.
//
// Residency: the core executes (RUN) or waits in WFI (SLEEP: the firmware's idle never sets SCR.SLEEPDEEP,
// so neither STOP nor STANDBY is ever entered today; their rows are in the table for the power policy).
// Peripheral currents while the core sleeps (a UART or I2C transfer, the timer) are not added: the data
// sheets give them per peripheral and per clock, not as one figure (bsp/twin/README.md "Power").
#pragma once

#include <cstdint>

#include "mspm0.hpp"

namespace twin {

// Typical supply currents in uA at 32 MHz MCLK from SYSOSC, 3.3 V, 25 degC.
struct PowerTable {
  uint32_t runUa;    // RUN, executing (CoreMark: the data sheets' busiest code, the safe side for firmware)
  uint32_t sleepUa;  // SLEEP (SLEEP0: CPU halted, MCLK on)
  uint32_t stop2Ua;  // STOP2 (SYSOSC off, ULPCLK = LFCLK), for the power policy
  uint32_t standby1Ua;
};

// MSPM0L1306: RUN 72 uA/MHz CoreMark at 32 MHz = 2 300 uA, SLEEP 978 uA at 32 MHz (MSPM0L130x data sheet
// SLASEX0D section 7.5.1, "Supply current characteristics"). STOP2 44 uA, STANDBY1 1.0 uA from the
// MSPM0L110x data sheet SLASEX5C section 7.5.2 (the L1306 table was not retrieved: open question).
inline constexpr PowerTable kL1306Power{2300, 978, 44, 1};
// MSPM0G3507: RUN 3 400 uA CoreMark at 32 MHz SYSOSC, SLEEP 1 399 uA at 32 MHz (MSPM0G350x data sheet
// SLASEX6B section 7.5.1). STOP2 47 uA, STANDBY1 1.5 uA (rounded up to 2) from the MSPM0G3507-Q1 data sheet
// SLASF88B section 7.5.2 (open question, as above).
inline constexpr PowerTable kG3507Power{3400, 1399, 47, 2};

constexpr const PowerTable& powerTable(Part part) {
  return part == Part::L1306 ? kL1306Power : kG3507Power;
}

// Average current over a run of `totalCycles`, `busyCycles` of them executing and the rest in SLEEP, in uA
// (rounded to nearest). 0 for an empty run.
constexpr uint32_t averageCurrentUa(const PowerTable& t, uint64_t busyCycles, uint64_t totalCycles) {
  if (totalCycles == 0) return 0;
  const uint64_t busy = busyCycles < totalCycles ? busyCycles : totalCycles;
  const uint64_t charge = busy * t.runUa + (totalCycles - busy) * t.sleepUa;  // uA x cycles
  return static_cast<uint32_t>((charge + totalCycles / 2) / totalCycles);
}

static_assert(averageCurrentUa(kL1306Power, 0, 100) == 978);
static_assert(averageCurrentUa(kL1306Power, 100, 100) == 2300);
static_assert(averageCurrentUa(kL1306Power, 0, 0) == 0);

}  // namespace twin
