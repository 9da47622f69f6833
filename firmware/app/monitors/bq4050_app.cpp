#include "app/monitors/bq4050_app.hpp"

#include "app/protection/default_limits.hpp"

namespace fw::app {

void Bq4050Monitor::run(sched::EventMask events) {
  const Instant now = scheduler_.now();
  if ((events & gauge_.events()) != 0 && gauge_.onEvent(events) == drivers::Progress::Done) finished(now);
  if ((events & kScanTick) != 0) {
    flags_.scanDue = true;
    scheduler_.checkIn(kId);
  }
  if ((events & kRetry) != 0) flags_.retryDue = true;
  if (gauge_.busy()) return;
  if (!flags_.probed) {
    if (flags_.scanDue) {
      flags_.scanDue =
          false;  // nothing measured until the gauge answers: protection counts the period as failed
      scheduler_.post(protection_, ProtectionTask::kScanFailed);
    }
    if (flags_.retryDue && gauge_.startProbe(records_.info) == Status::Ok) {
      flags_.retryDue = false;
      ++records_.stats.probes;
    }
  } else if (flags_.scanDue && gauge_.startScan(records_.measurement) == Status::Ok) {
    flags_.scanDue = false;
    flags_.scanning = true;
  }
}

inline void Bq4050Monitor::finished(Instant now) {
  const Status result = gauge_.result();
  if (!flags_.scanning) {
    flags_.probed = result == Status::Ok;
    if (flags_.probed) {
      flags_.scanDue = true;
    } else {
      scheduler_.startTimer(records_.retryTimer, kId, kRetry, config_.retryInterval);
    }
    return;
  }
  flags_.scanning = false;
  ++records_.stats.scans;
  sample_.last = result;
  // Implausible: the gauge answered (PEC-checked, or read twice alike) with a value its inputs cannot give
  // (drivers/bq4050/limits.hpp): a cell above 5 V, what the cell below an open sense wire reads, or a
  // temperature an open thermistor line gives. An open sense line, not a lost link: open_wire, no re-probe.
  const bool openWire = result == Status::Implausible;
  if (result == Status::Ok) {
    const auto cells = records_.measurement.cells();
    for (size_t c = 0; c < cells.size(); ++c)
      sample_.cellMv[c] = cells[c];
    sample_.tempDeciK[0] = records_.measurement.temperatureDeciK;
    sample_.takenAt = records_.measurement.takenAt;
    sample_.valid = true;
    view_.hasCurrent = true;
    view_.currentMa = records_.measurement.currentMa;
    view_.stateOfCharge = records_.measurement.rsocPercent;
    view_.deviceFault = records_.measurement.deviceFault();
    flags_.failedInRow = 0;
  } else {
    ++records_.stats.scanFailures;
    if (!openWire && ++flags_.failedInRow >= 3) {
      // Three failed scans in a row: the gauge may have reset or gone; probe it again now, then every
      // interval.
      flags_.probed = false;
      flags_.failedInRow = 0;
      flags_.retryDue = true;
    }
  }
  summarize(view_, now);
  view_.totals.openWire = openWire;  // the readings cannot show it: the gauge's words were refused
  scheduler_.post(protection_,
                  result == Status::Ok || openWire ? ProtectionTask::kNewData : ProtectionTask::kScanFailed);
  scheduler_.post(publisher_, CanPublisher::kScanDone);
}

}  // namespace fw::app
