#include "app/bq4050_app.hpp"

#include "app/default_limits.hpp"

namespace fw::app {

void Bq4050Monitor::run(sched::EventMask events) {
  const Instant now = scheduler_.now();
  if ((events & gauge_.events()) != 0 && gauge_.onEvent(events) == drivers::Progress::Done) finished(now);
  if ((events & kScanTick) != 0) {
    f_.scanDue = true;
    scheduler_.checkIn(kId);
  }
  if ((events & kRetry) != 0) f_.retryDue = true;
  if (gauge_.busy()) return;
  if (!f_.probed) {
    if (f_.scanDue) {
      f_.scanDue = false;  // nothing measured until the gauge answers: protection counts the period as failed
      scheduler_.post(protection_, ProtectionTask::kScanFailed);
    }
    if (f_.retryDue && gauge_.startProbe(r_.info) == Status::Ok) {
      f_.retryDue = false;
      ++r_.stats.probes;
    }
  } else if (f_.scanDue && gauge_.startScan(r_.measurement) == Status::Ok) {
    f_.scanDue = false;
    f_.scanning = true;
  }
}

inline void Bq4050Monitor::finished(Instant now) {
  const Status result = gauge_.result();
  if (!f_.scanning) {
    f_.probed = result == Status::Ok;
    if (f_.probed) {
      f_.scanDue = true;
    } else {
      scheduler_.startTimer(r_.retryTimer, kId, kRetry, config_.retryInterval);
    }
    return;
  }
  f_.scanning = false;
  ++r_.stats.scans;
  sample_.last = result;
  // Implausible: the gauge answered (PEC-checked, or read twice alike) with a value its inputs cannot give
  // (drivers/bq4050/limits.hpp): a cell above 5 V, what the cell below an open sense wire reads, or a
  // temperature an open thermistor line gives. An open sense line, not a lost link: open_wire, no re-probe.
  const bool openWire = result == Status::Implausible;
  if (result == Status::Ok) {
    const auto cells = r_.measurement.cells();
    for (size_t c = 0; c < cells.size(); ++c)
      sample_.cellMv[c] = cells[c];
    sample_.tempDeciK[0] = r_.measurement.temperatureDeciK;
    sample_.takenAt = r_.measurement.takenAt;
    sample_.valid = true;
    view_.hasCurrent = true;
    view_.currentMa = r_.measurement.currentMa;
    view_.stateOfCharge = r_.measurement.rsocPercent;
    view_.deviceFault = r_.measurement.deviceFault();
    f_.failedInRow = 0;
  } else {
    ++r_.stats.scanFailures;
    if (!openWire && ++f_.failedInRow >= 3) {
      // Three failed scans in a row: the gauge may have reset or gone; probe it again now, then every
      // interval.
      f_.probed = false;
      f_.failedInRow = 0;
      f_.retryDue = true;
    }
  }
  summarize(view_, now);
  view_.totals.openWire = openWire;  // the readings cannot show it: the gauge's words were refused
  scheduler_.post(protection_,
                  result == Status::Ok || openWire ? ProtectionTask::kNewData : ProtectionTask::kScanFailed);
  scheduler_.post(publisher_, CanPublisher::kScanDone);
}

}  // namespace fw::app
