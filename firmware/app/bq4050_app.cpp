#include "app/bq4050_app.hpp"

#include "app/default_limits.hpp"

namespace fw::app {

Bq4050Monitor::Bq4050Monitor(sched::Scheduler& scheduler, hal::I2cBus& bus, const Bq4050AppConfig& config,
                             BoardSample& sample, PackView& view, sched::TaskId protection,
                             sched::TaskId publisher)
    : scheduler_(scheduler),
      config_(config),
      gauge_(bus, scheduler.clock(), drivers::DriverContext{scheduler, kId, kBus, kTimer}, config.gauge),
      sample_(sample),
      view_(view),
      protection_(protection),
      publisher_(publisher) {}

void Bq4050Monitor::start() {
  scheduler_.addTask(kId, *this, {}, true);
  scheduler_.startTimer(scanTimer_, kId, kScanTick, config_.scanPeriod, config_.scanPeriod);
  scheduler_.post(kId, kRetry);
}

void Bq4050Monitor::run(sched::EventMask events) {
  const Instant now = scheduler_.clock().now();
  if ((events & gauge_.events()) != 0 && gauge_.onEvent(events) == drivers::Progress::Done) finished(now);
  if ((events & kScanTick) != 0) {
    scanDue_ = true;
    scheduler_.checkIn(kId);
  }
  if ((events & kRetry) != 0) retryDue_ = true;
  if (gauge_.busy()) return;
  if (!probed_) {
    if (scanDue_) {
      scanDue_ = false;  // nothing measured until the gauge answers: protection counts the period as failed
      scheduler_.post(protection_, ProtectionTask::kScanFailed);
    }
    if (retryDue_ && gauge_.startProbe(info_) == Status::Ok) {
      retryDue_ = false;
      ++stats_.probes;
    }
  } else if (scanDue_ && gauge_.startScan(measurement_) == Status::Ok) {
    scanDue_ = false;
    scanning_ = true;
  }
}

void Bq4050Monitor::finished(Instant now) {
  const Status result = gauge_.result();
  if (!scanning_) {
    probed_ = result == Status::Ok;
    if (probed_) {
      scanDue_ = true;
    } else {
      scheduler_.startTimer(retryTimer_, kId, kRetry, config_.retryInterval);
    }
    return;
  }
  scanning_ = false;
  ++stats_.scans;
  sample_.attempted = true;
  sample_.last = result;
  if (result == Status::Ok) {
    const auto cells = measurement_.cells();
    for (size_t c = 0; c < cells.size(); ++c)
      sample_.cellMv[c] = cells[c];
    sample_.tempDeciK[0] = measurement_.temperatureDeciK;
    sample_.takenAt = measurement_.takenAt;
    sample_.valid = true;
    view_.hasCurrent = true;
    view_.currentMa = measurement_.currentMa;
    view_.stateOfCharge = measurement_.rsocPercent;
    view_.deviceFault = measurement_.deviceFault();
    failedInRow_ = 0;
  } else {
    ++stats_.scanFailures;
    if (++failedInRow_ >= 3) {
      // Three failed scans in a row: the gauge may have reset or gone; probe it again after the interval.
      probed_ = false;
      failedInRow_ = 0;
      scheduler_.startTimer(retryTimer_, kId, kRetry, config_.retryInterval);
    }
  }
  summarize(view_, now);
  scheduler_.post(protection_, result == Status::Ok ? ProtectionTask::kNewData : ProtectionTask::kScanFailed);
  scheduler_.post(publisher_, CanPublisher::kScanDone);
}

Bq4050App::Bq4050App(sched::Scheduler& scheduler, const Io& io, const Bq4050AppConfig& config)
    : view_{std::span<const BoardSample>(&sample_, 1), config.gauge.cells, 1},
      plan_(view_, status_, kDefaultLimits.staleAfter),
      actuator_(io.faultOut, true),
      protection_(scheduler, kProtectionId, kDefaultLimits, view_, status_, actuator_, config.scanPeriod),
      monitor_(scheduler, io.bus, config, sample_, view_, kProtectionId, kPublisherId),
      publisher_(scheduler, kPublisherId, io.can, plan_, CanLayout::Native, ms(100), 10) {}

void Bq4050App::start() {
  protection_.start();
  monitor_.start();
  publisher_.start();
}

}  // namespace fw::app
