#include "app/monitors/bq79616_app.hpp"

#include "app/protection/default_limits.hpp"

namespace fw::app {

namespace b616 = drivers::bq79616;

// Bring-up or recovery ended: run with the devices that answer (CommFault names the missing one); otherwise
// try again after retryAfterFailure.
inline void Bq79616Device::setupFinished(Status result) {
  using b616::RecoveryLevel;
  const bool wasRecovery = flags_->broughtUp;
  if (result == Status::Ok || (result == Status::CommFault && driver_.devices() > 0)) {
    setRunning(view_, true);
    flags_->broughtUp = true;
    loop_->scanDue = true;  // (failedInRow is 0: the loop cleared it before recover())
    // If the scans fail again before one validates, this rung was not enough: the next recovery starts one
    // higher (a chain that answers but whose ADC was never restarted needs the full bring-up).
    const RecoveryLevel reached = driver_.lastRecovery();
    if (wasRecovery) {
      flags_->from = reached == RecoveryLevel::HardwareReset
                         ? reached
                         : static_cast<RecoveryLevel>(static_cast<uint8_t>(reached) + 1);
    }
    return;
  }
  // A failed ladder has sent a WAKE at least (its last rungs are full bring-ups), so the registers are reset:
  // only a full bring-up can bring the chain back, whatever a lighter rung's probe would say.
  if (wasRecovery && flags_->from < RecoveryLevel::Rewake) flags_->from = RecoveryLevel::Rewake;
  scheduler_.startTimer(records_->retryTimer, kMonitorTask, monitor_event::kRetry, config_.retryAfterFailure);
}

inline ScanVerdict Bq79616Device::scanFinished(Status result, Instant now) {
  if (kStats) records_->stats.lastScan = elapsed(records_->summary.started, now);
  bool anyValid = false;
  bool deviceFault = false;
  // Walked with pointers: the three per-device arrays have different strides.
  const b616::DeviceRecord* r = store_.records;
  BoardSample* s = store_.samples;
  int16_t* raw = store_.raw[0];
  const uint8_t cells = config_.chain.activeCells;
  for (uint16_t d = view_.boardCount(); d != 0; --d, ++r, ++s, raw += b616::kCellsPerDevice) {
    s->last = r->status != Status::Ok ? r->status
                                      : ((r->valid & b616::kValidCells) ? Status::Ok : Status::NotReady);
    if (s->last != Status::Ok) continue;
    for (uint8_t c = 0; c < cells; ++c) {
      // 190.73 uV per code = 12 500 / 65 536 mV within 0.003 %: a multiply and a shift instead of a division
      // per cell, exact to the millivolt over the whole range (+-1 mV rounding).
      const int16_t code = r->cellRaw[c];
      s->cellMv[c] = static_cast<int16_t>((code * 12500 + 32768) >> 16);
      raw[c] = code;
    }
    const bool temps = (r->valid & b616::kValidDieTemp) != 0;  // a failed temperature read is no reading
    s->tempDeciK[0] = temps ? r->dieTemp[0] : kNoReading;
    s->tempDeciK[1] = temps ? r->dieTemp[1] : kNoReading;
    deviceFault = deviceFault || ((r->valid & b616::kValidFaults) != 0 && r->faultSummary != 0);
    s->takenAt = r->takenAt;
    s->valid = anyValid = true;
  }
  // A BQ79616 fault has no direction (its image has no FETs): both paths, which the fault output stands for.
  view_.deviceBlocks = deviceFault ? static_cast<uint8_t>(Action::AllOff) : 0;
  // Every device in use validated (all of them, or all a degraded chain still has): whatever failed before is
  // over, and the next recovery may start at the lightest rung again.
  if (driver_.devices() != 0 && records_->summary.validDevices == driver_.devices())
    flags_->from = b616::RecoveryLevel{};
  return {.newData = anyValid, .failed = result != Status::Ok};
}

// The image's monitor task: its code (the loop with the chain's part folded in) is compiled here once.
template class MonitorTask<Bq79616Device>;

}  // namespace fw::app
