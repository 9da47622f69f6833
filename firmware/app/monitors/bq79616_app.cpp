#include "app/monitors/bq79616_app.hpp"

#include "app/protection/default_limits.hpp"

namespace fw::app {

namespace b616 = drivers::bq79616;

void Bq79616Monitor::run(sched::EventMask events) {
  const Instant now = scheduler_.now();
  if ((events & chain_.events()) != 0 && chain_.onEvent(events) == drivers::Progress::Done) finished(now);
  if ((events & kFault) != 0 && flags_.phase == Phase::Running) {
    // nFAULT: a device reports a fault. Protection acts on the line itself at once; the next scan (started
    // now) reads FAULT_SUMMARY to say which device and what. During bring-up and recovery the line is
    // expected to be low (devices leave reset with their faults latched until the fault reset), so it is
    // only a fault signal once the chain runs.
    scheduler_.post(protection_, ProtectionTask::kFaultLine);
    flags_.scanDue = flags_.early = true;
  }
  if ((events & kScanTick) != 0) {
    if (flags_.scanning) ++records_.stats.scanOverruns;
    flags_.scanDue = true;
    scheduler_.checkIn(kId);  // the monitor is alive and on schedule, whatever the chain's state
  }
  if ((events & kRetry) != 0) flags_.retryDue = true;
  if (!chain_.busy()) startNext(now);
}

inline void Bq79616Monitor::startNext(Instant now) {
  if (flags_.phase != Phase::Running) {
    if (flags_.scanDue) {
      // Nothing is measured until the chain is back: tell protection every period (comm loss, stale data).
      flags_.scanDue = false;
      scheduler_.post(protection_, ProtectionTask::kScanFailed);
    }
    if (!flags_.retryDue) return;
    flags_.retryDue = false;
    ++records_.stats.recoveries;
    // Bring-up the first time; afterwards the recovery ladder (which ends in a full bring-up if it must).
    if ((flags_.phase == Phase::BringUp ? chain_.startBringUp() : chain_.startRecovery(flags_.from)) ==
        Status::Ok)
      records_.opStarted = now;
    return;
  }
  if (!flags_.scanDue) return;
  flags_.scanDue = false;
  if (chain_.startScan(std::span<b616::DeviceRecord>(store_.records, config_.chain.devices),
                       records_.summary) != Status::Ok) {
    return;
  }
  flags_.scanning = true;
  records_.opStarted = now;
  if (flags_.early) ++records_.stats.earlyScans;
  flags_.early = false;
}

// Bring-up or recovery ended: run with the devices that answer (CommFault names the missing one); otherwise
// try again.
inline void Bq79616Monitor::recovered(Status result) {
  using b616::RecoveryLevel;
  const bool wasRecovery = flags_.phase == Phase::Recovering;
  if (result == Status::Ok || (result == Status::CommFault && chain_.devices() > 0)) {
    flags_.phase = Phase::Running;
    flags_.failedInRow = 0;
    flags_.scanDue = true;
    // If the scans fail again before one validates, this rung was not enough: the next recovery starts one
    // higher (a chain that answers but whose ADC was never restarted needs the full bring-up).
    const RecoveryLevel reached = chain_.lastRecovery();
    if (wasRecovery) {
      flags_.from = reached == RecoveryLevel::HardwareReset
                        ? reached
                        : static_cast<RecoveryLevel>(static_cast<uint8_t>(reached) + 1);
    }
    return;
  }
  // A failed ladder has sent a WAKE at least (its last rungs are full bring-ups), so the registers are reset:
  // only a full bring-up can bring the chain back, whatever a lighter rung's probe would say.
  if (wasRecovery && flags_.from < RecoveryLevel::Rewake) flags_.from = RecoveryLevel::Rewake;
}

[[gnu::always_inline]] inline void Bq79616Monitor::finished(Instant now) {
  const Status result = chain_.result();
  if (!flags_.scanning) {
    recovered(result);
    if (flags_.phase != Phase::Running)
      scheduler_.startTimer(records_.retryTimer, kId, kRetry, config_.retryAfterFailure);
    return;
  }
  flags_.scanning = false;
  ++records_.stats.scans;
  records_.stats.lastScan = elapsed(records_.opStarted, now);
  publishScan(now);
  // Every device in use validated (all of them, or all a degraded chain still has): whatever failed before is
  // over, and the next recovery may start at the lightest rung again.
  if (chain_.devices() != 0 && records_.summary.validDevices == chain_.devices())
    flags_.from = b616::RecoveryLevel{};
  if (result == Status::Ok) {
    flags_.failedInRow = 0;
  } else {
    ++records_.stats.scanFailures;
    if (++flags_.failedInRow >= 3) {
      // Repeated failures: climb the recovery ladder; at once when scans validated since the last recovery,
      // otherwise at most once per recoveryInterval.
      flags_.phase = Phase::Recovering;
      scheduler_.startTimer(records_.retryTimer, kId, kRetry,
                            flags_.from == b616::RecoveryLevel{} ? Duration{} : config_.recoveryInterval);
    }
  }
}

void Bq79616Monitor::publishScan(Instant now) {
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
  view_.deviceFault = deviceFault;
  summarize(view_, now);
  scheduler_.post(protection_, anyValid ? ProtectionTask::kNewData : ProtectionTask::kScanFailed);
  scheduler_.post(publisher_, CanPublisher::kScanDone);
}

}  // namespace fw::app
