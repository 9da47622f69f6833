// The MCU's power modes and its average supply current over a run, COMPUTED (not measured) from the twin's
// residency in each mode and TI's typical data-sheet currents at 25 degC. It answers "what would the MCU draw
// with this image", for comparing images and power policies; a board's real figure also has the pins'
// loads, the LaunchPad's debugger and regulator, and part-to-part spread, none of which are here.
//
// Modes: power_mode.hpp.
// Peripheral currents while the core sleeps (a UART or I2C transfer, the timer) are not added: the data
// sheets give them per peripheral and per clock, not as one figure (bsp/twin/README.md "Power").
#pragma once

#include <array>
#include <cstdint>

#include "mspm0.hpp"
#include "power_mode.hpp"

namespace twin {

// Typical supply currents in tenths of uA per mode (indexed by PowerMode), 32 MHz MCLK from SYSOSC, 3.3 V,
// 25 degC.
using PowerTable = std::array<uint32_t, kPowerModes>;

// MSPM0L1306: RUN 72 uA/MHz CoreMark at 32 MHz = 2 300 uA, SLEEP 978 uA at 32 MHz (MSPM0L130x data sheet
// SLASEX0D section 7.5.1, "Supply current characteristics"). STOP0 320, STOP1 151, STOP2 44, STANDBY0 1.3,
// STANDBY1 1.0 uA from the MSPM0L110x data sheet SLASEX5C section 7.5.2 (the L1306 table was not
// retrieved: open question, bsp/twin/README.md "Power").
inline constexpr PowerTable kL1306Power{23000, 9780, 3200, 1510, 440, 13, 10};
// MSPM0G3507: RUN 3 400 uA CoreMark at 32 MHz SYSOSC, SLEEP 1 399 uA at 32 MHz (MSPM0G350x data sheet
// SLASEX6B section 7.5.1). STOP0 360, STOP1 190, STOP2 47, STANDBY0 2.0, STANDBY1 1.5 uA from the
// MSPM0G3507-Q1 data sheet SLASF88B section 7.5.2 (open question, as above).
inline constexpr PowerTable kG3507Power{34000, 13990, 3600, 1900, 470, 20, 15};

constexpr const PowerTable& powerTable(Part part) {
  return part == Part::L1306 ? kL1306Power : kG3507Power;
}

// Typical wake-up time from each mode to the first instruction, in tenths of us (indexed by PowerMode; RUN
// and SLEEP 0: SLEEP's 2 cycles are within the core's exception entry, which the twin counts).
// MSPM0L1306: tWAKE,STOP 14 us (given for STOP1; taken for STOP0 too), STOP2 13 us, tWAKE,STBY 15 us
// (MSPM0L130x data sheet SLASEX0D 7.8 "Timing characteristics"; the same in MSPM0L110x SLASEX5C 7.8).
using WakeTable = std::array<uint32_t, kPowerModes>;
inline constexpr WakeTable kL1306WakeTenthsUs{0, 0, 140, 140, 130, 150, 150};
// MSPM0G3507: STOP0 12.1, STOP1 13.5, STOP2 12.9, STANDBY0/1 15.2 us from the MSPM0G310x data sheet SLASF12C
// 7.8 (the G350x table was not retrieved: open question, bsp/twin/README.md "Power"; the earlier advance
// data sheet of the G150x, JAJSPX2A, gave 19.7 .. 22.7 us).
inline constexpr WakeTable kG3507WakeTenthsUs{0, 0, 121, 135, 129, 152, 152};

constexpr std::array<uint32_t, kPowerModes> wakeCycles(Part part, uint32_t clockHz) {
  const WakeTable& t = part == Part::L1306 ? kL1306WakeTenthsUs : kG3507WakeTenthsUs;
  std::array<uint32_t, kPowerModes> cycles{};
  for (size_t i = 0; i < kPowerModes; ++i)
    cycles[i] = static_cast<uint32_t>((static_cast<uint64_t>(t[i]) * clockHz + 9999999) / 10000000);
  return cycles;
}
static_assert(wakeCycles(Part::L1306, 32000000)[static_cast<size_t>(PowerMode::Standby1)] == 480);

// Average current over a run with `residency` cycles in each mode, in uA (rounded to nearest). 0 for an
// empty run.
constexpr uint32_t averageCurrentUa(const PowerTable& t, const Residency& residency) {
  uint64_t total = 0, charge = 0;  // charge in uA/10 x cycles
  for (size_t i = 0; i < kPowerModes; ++i) {
    total += residency[i];
    charge += residency[i] * t[i];
  }
  if (total == 0) return 0;
  return static_cast<uint32_t>((charge + total * 5) / (total * 10));
}

static_assert(averageCurrentUa(kL1306Power, Residency{0, 100, 0, 0, 0, 0, 0}) == 978);
static_assert(averageCurrentUa(kL1306Power, Residency{100, 0, 0, 0, 0, 0, 0}) == 2300);
static_assert(averageCurrentUa(kL1306Power, Residency{}) == 0);
static_assert(averageCurrentUa(kL1306Power, Residency{1, 0, 0, 0, 0, 0, 999}) == 3);  // 2.3 + 0.999

}  // namespace twin
