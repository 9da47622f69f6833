// Bq769xEmulator, host-controlled cell balancing (the bus face is emulator.cpp, the rest of the device's own
// behaviour device.cpp): which CB_ACTIVE_CELLS writes the device takes, how long it balances after one, when
// it stops by itself, and the charge each balanced cell loses. Every rule cites the TI document it follows;
// where TI's documents are silent the rule takes the side that makes a careless host fail a test, and says
// so.
#include <algorithm>

#include "bq769x2/emulator.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq769x2.hpp"

namespace bsp::host {

namespace {
namespace m2 = fw::regmap::bq769x2;
namespace m7 = fw::regmap::bq7690x;

int popcount(uint32_t v) {
  int n = 0;
  for (; v != 0; v &= v - 1)
    ++n;
  return n;
}
}  // namespace

// A CB_ACTIVE_CELLS write whose checksum and length were right (emulator.cpp: a write without them is
// refused before it gets here, SLUAA81A "it is necessary to write the checksum and length to registers
// 0x60/0x61 for the values to be written successfully").
void Bq769xEmulator::writeBalancing(uint16_t mask) {
  settleBleed();
  // Balancing Configuration[CB_NO_CMD]: host balancing commands are ignored (BQ769x2 bit 4, SLUUBY2B; BQ7690x
  // bit 0, SLUUCI8: "writes to CB_ACTIVE_CELLS() are ignored"). Balancing goes on as it was.
  const uint8_t config = static_cast<uint8_t>(dataMemory(
      bq7690x() ? m7::dm::BalancingConfiguration.address : m2::dm::BalancingConfiguration.address, 1));
  const bool noCommands = bq7690x() ? m7::bits::BalancingConfiguration::fromRaw(config).cb_no_cmd()
                                    : m2::bits::BalancingConfiguration::fromRaw(config).cb_no_cmd();
  if (noCommands) {
    ++balanceCounters_.ignored;
    return;
  }
  // Refused masks: nothing balances afterwards, so the host's read-back shows it.
  //   BQ7690x: bit 0 is reserved, "read/write 0 to this bit" (SLUUCJ0 CB_ACTIVE_CELLS; bit 1 is cell 1).
  //   BQ769x2: more cells than Settings:Cell Balancing Config:Cell Balance Max Cells (TI says so of
  //   CB_SET_LVL, E2E 969824; for CB_ACTIVE_CELLS no TI document was found, the safe side is taken:
  //   regmaps/README.md).
  // Accepted but counted: two neighbouring BQ769x2 cells, which the device never balances itself and which
  // double the current through their shared input resistor (E2E 1505209): a host that sends them overheats
  // the input (balanceCounters().adjacent).
  const uint16_t cells = static_cast<uint16_t>(mask & (((1U << cellCount()) - 1) << (bq7690x() ? 1 : 0)));
  bool refused = cells != mask;
  if (bq7690x()) {
    refused = refused || (mask & 1U) != 0;
  } else {
    const auto maxCells = static_cast<int>(dataMemory(m2::dm::CellBalanceMaxCells.address, 1));
    refused = refused || popcount(mask) > maxCells;
    if (!refused && (mask & (mask >> 1)) != 0) ++balanceCounters_.adjacent;
  }
  if (refused) {
    ++balanceCounters_.refused;
    stopBalancing();
    return;
  }
  ++balanceCounters_.accepted;
  cbActive_ = mask;
  if (cbTimeoutEvent_ != 0) clock_.cancel(cbTimeoutEvent_);
  cbTimeoutEvent_ = 0;
  if (mask == 0) return;  // "Write 0x00 to turn balancing off" (SLUUCJ0, SLUAA81A)
  // The device balances for a limited time after each write and the timer restarts with every new write
  // (BQ7690x: "up to 20 seconds", SLUAAP7 section 3; BQ769x2: Timing::hostBalanceTimeout769x2).
  const fw::Duration timeout = bq7690x() ? timing_.hostBalanceTimeout7690x : timing_.hostBalanceTimeout769x2;
  cbTimeoutEvent_ = clock_.scheduleIn(timeout, [this] {
    cbTimeoutEvent_ = 0;
    ++balanceCounters_.timeouts;
    stopBalancing();
    update();
  });
  checkBalanceTemperatures();
}

void Bq769xEmulator::stopBalancing() {
  settleBleed();
  cbActive_ = 0;
  if (cbTimeoutEvent_ != 0) clock_.cancel(cbTimeoutEvent_);
  cbTimeoutEvent_ = 0;
}

// The device disables balancing outside its temperature limits. BQ769x2: internal temperature above Max
// Internal Temp, or a thermistor (TS1..TS3) below Min Cell Temp or above Max Cell Temp (Settings:Cell
// Balancing Config, SLUUBY2B; the limits apply to the device's balancing, SLUAA81A). BQ7690x: the same with
// its Min/Max Temp Threshold and Max Internal Temp (SLUAAP7 section 3), whose units and defaults the map does
// not have yet (`unverified`): not modelled. A thermistor reading of 0 is an unconfigured input.
void Bq769xEmulator::checkBalanceTemperatures() {
  if (cbActive_ == 0 || bq7690x()) return;
  const auto minCell = static_cast<int8_t>(dataMemory(m2::dm::MinCellTemp.address, 1));
  const auto maxCell = static_cast<int8_t>(dataMemory(m2::dm::MaxCellTemp.address, 1));
  const auto maxInternal = static_cast<int8_t>(dataMemory(m2::dm::MaxInternalTemp.address, 1));
  auto degC = [](int deciK) { return (deciK - 2732) / 10; };  // whole degC, toward zero
  bool out = degC(measured_.intTemp) > maxInternal;
  for (int16_t ts : measured_.ts) {
    if (ts != 0) out = out || degC(ts) < minCell || degC(ts) > maxCell;
  }
  if (!out) return;
  ++balanceCounters_.tempStops;
  stopBalancing();
}

// The charge the balanced cells lost since the last call: each loses its voltage over the balancing path
// (cell_model.hpp), in mA x us.
void Bq769xEmulator::settleBleed() {
  const uint64_t now = clock_.nowUs();
  const uint64_t dt = now > bledUntilUs_ ? now - bledUntilUs_ : 0;
  bledUntilUs_ = now;
  const uint16_t cells = balancing();
  if (cells == 0 || dt == 0 || cellModel_.balanceOhms == 0) return;
  for (uint8_t c = 0; c < cellCount(); ++c) {
    if (((cells >> c) & 1U) == 0) continue;
    const int64_t mv = std::max<int64_t>(0, cellNowMv(static_cast<uint8_t>(c + 1)));
    bled_[c] += mv * static_cast<int64_t>(dt) / cellModel_.balanceOhms;
  }
}

int16_t Bq769xEmulator::cellNowMv(uint8_t cell) {
  const size_t i = cell - 1U;
  const int64_t dropMv = bleedDropMv(bled_.at(i), cellModel_);
  return static_cast<int16_t>(std::clamp<int64_t>(cells_.at(i) - dropMv, INT16_MIN, INT16_MAX));
}

int64_t Bq769xEmulator::bledChargeMaUs(uint8_t cell) {
  settleBleed();
  return bled_.at(cell - 1U);
}

void Bq769xEmulator::setCellModel(const CellModel& model) {
  settleBleed();
  cellModel_ = model;
}

}  // namespace bsp::host
