#include "app/bq79616_app.hpp"

#include "app/default_limits.hpp"

namespace fw::app {

namespace b616 = drivers::bq79616;

Bq79616Monitor::Bq79616Monitor(sched::Scheduler& scheduler, hal::Uart& uart, hal::EdgeInput& nfault,
                               const Bq79616AppConfig& config, Bq79616Storage& storage, PackView& view,
                               sched::TaskId protection, sched::TaskId publisher)
    : scheduler_(scheduler),
      config_(config),
      chain_(uart, scheduler.clock(), drivers::DriverContext{scheduler, kId, kBus, kTimer}, config.chain),
      nfault_(nfault),
      store_(storage),
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
    scanDue_ = early_ = true;
  }
  if ((events & kScanTick) != 0) {
    if (scanning_) ++stats_.scanOverruns;
    scanDue_ = true;
    scheduler_.checkIn(kId);  // the monitor is alive and on schedule, whatever the chain's state
  }
  if ((events & kRetry) != 0) retryDue_ = true;
  if (!chain_.busy()) startNext(now);
}

void Bq79616Monitor::startNext(Instant now) {
  if (phase_ != Phase::Running) {
    if (scanDue_) {
      // Nothing is measured until the chain is back: tell protection every period (comm loss, stale data).
      scanDue_ = false;
      scheduler_.post(protection_, ProtectionTask::kScanFailed);
    }
    if (!retryDue_) return;
    retryDue_ = false;
    ++stats_.recoveries;
    // Bring-up the first time; afterwards the recovery ladder (which ends in a full bring-up if it must).
    if ((phase_ == Phase::BringUp ? chain_.startBringUp() : chain_.startRecovery()) == Status::Ok)
      opStarted_ = now;
    return;
  }
  if (!scanDue_) return;
  scanDue_ = false;
  if (chain_.startScan(std::span<b616::DeviceRecord>(store_.records, config_.chain.devices), summary_) !=
      Status::Ok) {
    return;
  }
  scanning_ = true;
  opStarted_ = now;
  if (early_) ++stats_.earlyScans;
  early_ = false;
}

void Bq79616Monitor::finished(Instant now) {
  const Status result = chain_.result();
  if (!scanning_) {
    // Bring-up or recovery: run with the devices that answer (CommFault names the missing one); otherwise
    // try again after the interval.
    if (result == Status::Ok || (result == Status::CommFault && chain_.devices() > 0)) {
      phase_ = Phase::Running;
      failedInRow_ = 0;
      scanDue_ = true;
    } else {
      scheduler_.startTimer(retryTimer_, kId, kRetry, config_.recoveryInterval);
    }
    return;
  }
  scanning_ = false;
  ++stats_.scans;
  stats_.lastScan = elapsed(opStarted_, now);
  publishScan(now);
  if (result == Status::Ok) {
    failedInRow_ = 0;
  } else {
    ++stats_.scanFailures;
    if (++failedInRow_ >= 3) {
      // Repeated failures: climb the recovery ladder, at most once per recoveryInterval.
      phase_ = Phase::Recovering;
      scheduler_.startTimer(retryTimer_, kId, kRetry,
                            failedInRow_ == 3 ? Duration{} : config_.recoveryInterval);
    }
  }
}

void Bq79616Monitor::publishScan(Instant now) {
  bool anyValid = false;
  bool deviceFault = false;
  for (size_t d = 0; d < view_.boards.size(); ++d) {
    const b616::DeviceRecord& r = store_.records[d];
    BoardSample& s = store_.samples[d];
    s.attempted = true;
    s.last =
        r.status != Status::Ok ? r.status : ((r.valid & b616::kValidCells) ? Status::Ok : Status::NotReady);
    if (s.last != Status::Ok) continue;
    for (uint8_t c = 0; c < config_.chain.activeCells; ++c) {
      // 190.73 uV per code = 12 500 / 65 536 mV within 0.003 %: a multiply and a shift instead of a division
      // per cell, exact to the millivolt over the whole range (+-1 mV rounding).
      s.cellMv[c] = static_cast<int16_t>((r.cellRaw[c] * 12500 + 32768) >> 16);
      store_.raw[d][c] = r.cellRaw[c];
    }
    const bool temps = (r.valid & b616::kValidDieTemp) != 0;
    s.tempDeciK[0] = temps ? r.dieTemp[0] : 0;
    s.tempDeciK[1] = temps ? r.dieTemp[1] : 0;
    deviceFault = deviceFault || ((r.valid & b616::kValidFaults) != 0 && r.faultSummary != 0);
    s.takenAt = r.takenAt;
    s.valid = anyValid = true;
  }
  view_.deviceFault = deviceFault;
  summarize(view_, now);
  scheduler_.post(protection_, anyValid ? ProtectionTask::kNewData : ProtectionTask::kScanFailed);
  scheduler_.post(publisher_, CanPublisher::kScanDone);
}

Bq79616App::Bq79616App(sched::Scheduler& scheduler, const Io& io, const Bq79616AppConfig& config,
                       Bq79616Storage& storage)
    : config_(config),
      limits_(config.limits != nullptr ? *config.limits : kDefaultLimits),
      view_{std::span<const BoardSample>(storage.samples, config.chain.devices), config.chain.activeCells, 2},
      plan_(view_, status_, limits_.staleAfter),
      actuator_(io.faultOut, true),
      protection_(scheduler, kProtectionId, limits_, view_, status_, actuator_, config.scanPeriod),
      monitor_(scheduler, io.uart, io.nfault, config_, storage, view_, kProtectionId, kPublisherId),
      publisher_(scheduler, kPublisherId, io.can, plan_, config.layout, ms(100), 10) {
  view_.rawCells = &storage.raw[0][0];
}

void Bq79616App::start() {
  protection_.start();
  monitor_.start();
  publisher_.start();
}

}  // namespace fw::app
