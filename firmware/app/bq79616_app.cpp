#include "app/bq79616_app.hpp"

#include "app/default_limits.hpp"

namespace fw::app {

namespace b616 = drivers::bq79616;

Bq79616Monitor::Bq79616Monitor(sched::Scheduler& scheduler, hal::Uart& uart, hal::EdgeInput& nfault,
                               const Bq79616AppConfig& config, std::span<BoardSample> samples,
                               int16_t (*raw)[16], PackView& view, sched::TaskId protection,
                               sched::TaskId publisher)
    : scheduler_(scheduler),
      config_(config),
      chain_(uart, scheduler.clock(), drivers::DriverContext{scheduler, kId, kBus, kTimer}, config.chain),
      nfault_(nfault),
      samples_(samples),
      raw_(raw),
      view_(view),
      protection_(protection),
      publisher_(publisher) {}

void Bq79616Monitor::start() {
  scheduler_.addTask(kId, *this, {}, true);
  chain_.attachFaultLine(nfault_, kFault);
  scheduler_.startTimer(scanTimer_, kId, kScanTick, config_.scanPeriod, config_.scanPeriod);
  scheduler_.post(kId, kRetry);
}

void Bq79616Monitor::run(sched::EventMask events) {
  const Instant now = scheduler_.clock().now();
  if ((events & chain_.events()) != 0 && chain_.onEvent(events) == drivers::Progress::Done) finished(now);
  if ((events & kFault) != 0 && phase_ == Phase::Running) {
    // nFAULT: a device reports a fault. Protection acts on the line itself at once; the next scan (started
    // now) reads FAULT_SUMMARY to say which device and what. During bring-up and recovery the line is
    // expected to be low (devices leave reset with their faults latched until the fault reset), so it is
    // only a fault signal once the chain runs.
    scheduler_.post(protection_, ProtectionTask::kFaultLine);
    scanDue_ = true;
    early_ = true;
  }
  if ((events & kScanTick) != 0) {
    if (op_ == Op::Scan) ++stats_.scanOverruns;
    scanDue_ = true;
    scheduler_.checkIn(kId);  // the monitor is alive and on schedule, whatever the chain's state
  }
  if ((events & kRetry) != 0) retryDue_ = true;
  if (!chain_.busy()) startNext(now);
}

void Bq79616Monitor::startNext(Instant now) {
  Status s = Status::Busy;
  switch (phase_) {
    case Phase::BringUp:
      if (!retryDue_) return;
      retryDue_ = false;
      s = chain_.startBringUp();
      op_ = Op::BringUp;
      ++stats_.bringUps;
      break;
    case Phase::Running:
      if (!scanDue_) return;
      scanDue_ = false;
      s = chain_.startScan(std::span<b616::DeviceRecord>(records_, config_.chain.devices), summary_);
      op_ = Op::Scan;
      if (early_) ++stats_.earlyScans;
      early_ = false;
      break;
    case Phase::Waiting:
      if (scanDue_) {
        // Between recovery attempts the pack is still unmeasured: tell protection (comm loss, stale data).
        scanDue_ = false;
        scheduler_.post(protection_, ProtectionTask::kScanFailed);
      }
      if (!retryDue_) return;
      retryDue_ = false;
      s = chain_.startRecovery();
      op_ = Op::Recovery;
      phase_ = Phase::Recovering;
      lastRecovery_ = now;
      recoveredOnce_ = true;
      ++stats_.recoveries;
      break;
    case Phase::Recovering:
      return;
  }
  if (s == Status::Ok) {
    opStarted_ = now;
  } else {
    op_ = Op::None;  // could not start (a programming error would have asserted): try again next event
  }
}

void Bq79616Monitor::finished(Instant now) {
  const Status result = chain_.result();
  const Op op = op_;
  op_ = Op::None;
  switch (op) {
    case Op::BringUp:
    case Op::Recovery:
      if (result == Status::Ok || (result == Status::CommFault && chain_.devices() > 0)) {
        phase_ = Phase::Running;
        failedInRow_ = 0;
        scanDue_ = true;
      } else {
        phase_ = op == Op::BringUp ? Phase::BringUp : Phase::Waiting;
        scheduler_.startTimer(retryTimer_, kId, kRetry, config_.recoveryInterval);
        scheduler_.post(protection_, ProtectionTask::kScanFailed);
      }
      return;
    case Op::Scan: {
      ++stats_.scans;
      stats_.lastScan = elapsed(opStarted_, now);
      if (stats_.lastScan > stats_.worstScan) stats_.worstScan = stats_.lastScan;
      publishScan();
      if (result == Status::Ok) {
        failedInRow_ = 0;
        return;
      }
      ++stats_.scanFailures;
      if (++failedInRow_ >= 3) {
        // Repeated failures: climb the recovery ladder, at most once per recoveryInterval.
        phase_ = Phase::Waiting;
        const Duration since = elapsed(lastRecovery_, now);
        if (!recoveredOnce_ || since >= config_.recoveryInterval) {
          retryDue_ = true;
        } else {
          scheduler_.startTimer(retryTimer_, kId, kRetry, config_.recoveryInterval - since);
        }
      }
      return;
    }
    case Op::None:
      return;
  }
}

void Bq79616Monitor::publishScan() {
  bool anyValid = false;
  bool deviceFault = false;
  for (size_t d = 0; d < samples_.size(); ++d) {
    const b616::DeviceRecord& r = records_[d];
    BoardSample& s = samples_[d];
    const bool cells = (r.valid & b616::kValidCells) != 0;
    s.last = (cells && r.status == Status::Ok) ? Status::Ok
                                               : (r.status == Status::Ok ? Status::NotReady : r.status);
    if (s.last != Status::Ok) continue;
    for (uint8_t c = 0; c < config_.chain.activeCells; ++c) {
      const int32_t uv = b616::cellMicrovolts(r.cellRaw[c]);
      s.cellMv[c] = static_cast<int16_t>(uv >= 0 ? (uv + 500) / 1000 : (uv - 500) / 1000);
      raw_[d][c] = r.cellRaw[c];
    }
    const bool temps = (r.valid & b616::kValidDieTemp) != 0;
    s.tempDeciK[0] = temps ? r.dieTemp[0] : 0;
    s.tempDeciK[1] = temps ? r.dieTemp[1] : 0;
    if ((r.valid & b616::kValidFaults) != 0 && r.faultSummary != 0) deviceFault = true;
    s.takenAt = r.takenAt;
    s.valid = true;
    anyValid = true;
  }
  view_.deviceFault = deviceFault;
  scheduler_.post(protection_, anyValid ? ProtectionTask::kNewData : ProtectionTask::kScanFailed);
  scheduler_.post(publisher_, CanPublisher::kScanDone);
}

Bq79616App::Bq79616App(sched::Scheduler& scheduler, const Io& io, const Bq79616AppConfig& config)
    : config_(config),
      limits_(defaultLimits(config.scanPeriod)),
      view_{std::span<const BoardSample>(samples_, config.chain.devices), config.chain.activeCells, 2},
      plan_(view_, status_, limits_.staleAfter),
      actuator_(io.faultOut, true),
      protection_(scheduler, kProtectionId, limits_, view_, status_, actuator_, config.scanPeriod),
      monitor_(scheduler, io.uart, io.nfault, config_, std::span<BoardSample>(samples_, config.chain.devices),
               raw_, view_, kProtectionId, kPublisherId),
      publisher_(scheduler, kPublisherId, io.can, plan_, config.layout, ms(100), 10) {
  view_.rawCells = &raw_[0][0];
}

void Bq79616App::start() {
  protection_.start();
  monitor_.start();
  publisher_.start();
}

}  // namespace fw::app
