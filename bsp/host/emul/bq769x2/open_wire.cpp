// Bq769xEmulator, a detached cell sense wire and the BQ769x2's own cell open-wire check.
//
// SLUUBY2B "Cell Open Wire" (BQ76952 TRM; SLUUCW9 for the BQ76972 says the same): without the check, a
// detached cell input keeps its voltage on the board capacitor for some time, so the readings stay as they
// were. With Settings:Cell Open-Wire:Check Time non-zero (seconds, 0 = off, default 5; SLUUCG7 the same
// entry), once every Check Time the device enables a current sink (55 uA typical) from each cell input to
// VSS for one ADC measurement (3 ms): a floating node drains, its cell reads low (Cell Undervoltage on that
// cell) and the cell above it reads high (Cell Overvoltage on the cell above). How far one check moves the
// node is Timing::openWireDrainMv (the board's capacitance is not TI's).
// What TI does not say, and the side taken here:
// - VC0: the sink runs "from each cell to VSS"; the BQ76922 data sheet lists I(OW) for VC1..VC5 only, so
//   VC0 has none. A detached VC0 holds VSS's potential on its filter capacitor: cell 1 reads true, the
//   device sees nothing (regmaps/README.md, open questions).
// - How low a drained node goes: it stops at the input below it (the cell reads 0 mV, the one above both
//   cells); the balancing FET's body diode between the two inputs is taken to clamp it there.
// - SLEEP: the check is modelled as running there too (SLUUBY2B's SLEEP sentence was not retrieved); the
//   readings move only at SLEEP's measurement ticks, as every other reading.
// - Which cell the sink runs on during a given measurement (SLUUBY2B: on the cell above the one being
//   measured, so it does not corrupt that measurement) is not modelled: the readings show the node only.
#include <algorithm>

#include "bq769x2/emulator.hpp"
#include "regmap/bq769x2.hpp"

namespace bsp::host {

namespace {
namespace m2 = fw::regmap::bq769x2;
}  // namespace

// Cell input VC`pin`'s voltage above VSS as the cells hold it: the sum of the cells below it.
int32_t Bq769xEmulator::inputMv(int pin) {
  int32_t mv = 0;
  for (int c = 1; c <= pin; ++c)
    mv += cellNowMv(static_cast<uint8_t>(c));
  return mv;
}

void Bq769xEmulator::setOpenWire(int pin, bool open) {
  if (bq7690x() || pin < 0 || pin > cellCount()) return;
  if (!open) {
    if (pin == openPin_) openPin_ = -1;
  } else {
    openPin_ = pin;
    openNodeMv_ = inputMv(pin);  // the node keeps the voltage it had
    scheduleOpenWireCheck();
  }
  update();
}

// The readings with the detached node in place of its input: cell `pin` = node - input below, cell
// `pin` + 1 = input above - node (a cell is the difference of its two inputs).
void Bq769xEmulator::applyOpenWire(std::array<int16_t, 16>& cells) {
  if (openPin_ < 0) return;
  const size_t n = cellCount();
  const int32_t below = inputMv(openPin_ - 1);
  const auto p = static_cast<size_t>(openPin_);
  if (p >= 1) {
    const int32_t above = below + cellNowMv(static_cast<uint8_t>(p));  // the input as the cell holds it
    cells[p - 1] = static_cast<int16_t>(openNodeMv_ - below);
    if (p < n) cells[p] = static_cast<int16_t>(cells[p] + above - openNodeMv_);
  }
}

// The next check on the device's Check Time grid (a fresh read of the setting each time: the host may write
// it). With the check off the event polls once a second, so a later write takes effect.
void Bq769xEmulator::scheduleOpenWireCheck() {
  if (openWireEvent_ != 0) return;
  const uint32_t seconds = static_cast<uint32_t>(dataMemory(m2::dm::CheckTime.address, 1));
  const uint64_t period = fw::s(std::max<uint32_t>(seconds, 1)).us;
  const uint64_t now = clock_.nowUs();
  openWireEvent_ = clock_.schedule((now / period + 1) * period, [this] {
    openWireEvent_ = 0;
    openWireCheck();
  });
}

void Bq769xEmulator::openWireCheck() {
  if (openPin_ < 0) return;
  // VC1 and up have the sink (SLUUBY2B); the node drains until it reaches the input below (see above).
  if (openPin_ >= 1 && dataMemory(m2::dm::CheckTime.address, 1) != 0 && !cfgUpdate_) {
    openNodeMv_ = std::max(inputMv(openPin_ - 1), openNodeMv_ - timing_.openWireDrainMv);
  }
  scheduleOpenWireCheck();
  update();
}

}  // namespace bsp::host
