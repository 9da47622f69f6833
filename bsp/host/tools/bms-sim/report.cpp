#include "report.hpp"

#include <cstdio>
#include <map>

#include "app/protection/protection.hpp"

namespace bmssim {
namespace {

std::string faultsText(uint16_t mask) {
  if (mask == 0) return "-";
  std::string s;
  for (uint8_t i = 0; i < fw::app::kFaultCount; ++i) {
    if ((mask & (1U << i)) == 0) continue;
    if (!s.empty()) s += ",";
    s += fw::app::faultName(static_cast<fw::app::FaultId>(i));
  }
  return s;
}

std::string ms(uint64_t us) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", static_cast<double>(us) / 1000.0);
  return buf;
}

}  // namespace

EventLatency latencyOf(const fw::app::ProtectionRecord& e, const Onsets& onsets) {
  EventLatency out;
  auto onset = onsets.find(fw::app::faultName(e.fault));
  if (onset == onsets.end()) onset = onsets.find("any");
  if (onset == onsets.end()) {
    out.note = "no expected onset";
    return out;
  }
  const uint64_t onsetUs = static_cast<uint64_t>(onset->second) * 1000;
  out.onsetUs = onsetUs;
  // A fault already present at the onset (found by a scan before it, e.g. stale data while a long chain
  // comes up) is not the scenario's doing: it has no latency rather than a negative one.
  if (e.detected.us < onsetUs || (e.actionDone && e.acted.us < onsetUs)) {
    out.note = "fault before onset";
  } else if (!e.actionDone) {
    out.note = "action pending";
  } else {
    out.latencyUs = e.acted.us - onsetUs;
  }
  return out;
}

void Report::tick(uint64_t nowUs) {
  if (slcan_ != nullptr) slcan_->step(*sim_.slcanText(), nowUs);
  if (live_ == nullptr || nowUs < nextView_) return;
  nextView_ = nowUs + 500000;
  const SimFigures f = sim_.figures();
  std::fprintf(
      live_,
      "t=%7.2fs  scans %5u  boards %d/%d  cells %4d..%4d mV  I=%+8.2f A  %s %s  faults: %-22s %s %llu\n",
      static_cast<double>(nowUs) / 1e6, f.scans, f.validBoards, f.boards, f.minCellMv, f.maxCellMv,
      f.currentMa / 1000.0,
      !f.pathsKnown ? "CHG:?  "
      : f.chargeOn  ? "CHG:on "
                    : "CHG:off",
      !f.pathsKnown   ? "DSG:?  "
      : f.dischargeOn ? "DSG:on "
                      : "DSG:off",
      faultsText(f.activeFaults).c_str(), f.output == "can" ? "CAN frames" : "SLCAN lines",
      static_cast<unsigned long long>(f.outputFrames));
  std::fflush(live_);
}

void Report::finish(const Onsets& onsets, bool busOffUnsupported, const bsp::host::SimWatchdog& watchdog) {
  const SimFigures f = sim_.figures();
  const auto log = sim_.protectionLog();
  const uint64_t now = sim_.harness().nowUs();
  if (!json_) {
    std::printf("\nscenario %s: %s\n", scenario_.name.c_str(), scenario_.description.c_str());
    if (busOffUnsupported) std::printf("(this image has no CAN bus: the bus-off step did nothing)\n");
    std::printf("scans %u (%u failed), scan period %u ms, bus %.0f us and %.1f transactions per scan\n",
                f.scans, f.scanFailures, f.scanPeriodMs, f.scanBusUs, f.scanTransactions);
    std::printf("%s %llu, comm errors %llu, recoveries %u, watchdog fed %zu times (longest gap %.0f ms)\n",
                f.output == "can" ? "CAN frames" : "SLCAN lines",
                static_cast<unsigned long long>(f.outputFrames),
                static_cast<unsigned long long>(f.commErrors), f.recoveries, watchdog.feeds().size(),
                static_cast<double>(watchdog.longestGapUs(0)) / 1000.0);
    if (log.empty()) std::printf("protection events: none\n");
    for (const auto& e : log) {
      const EventLatency l = latencyOf(e, onsets);
      // "off at" only what was confirmed (the device's FET read-back, or the pin); a command the device took
      // but no scan has shown in effect yet, or none at all, says so.
      const bool pin = f.output == "can" && !sim_.hasCurrent();
      std::string when = e.confirmedOff ? ms(e.confirmed.us) + " ms"
                         : e.actionDone ? "(not confirmed; command done at " + ms(e.acted.us) + " ms)"
                                        : std::string("(not confirmed)");
      std::printf("protection event %-13s onset %s, detected %s ms, %s %s: %s\n", fw::app::faultName(e.fault),
                  l.onsetUs ? (ms(*l.onsetUs) + " ms").c_str() : "-", ms(e.detected.us).c_str(),
                  pin ? "fault output at" : "paths off at", when.c_str(),
                  l.latencyUs ? (ms(*l.latencyUs) + " ms after the onset").c_str() : l.note);
    }
    return;
  }
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", v);
    return std::string(buf);
  };
  std::printf("{\n");
  std::printf("  \"image\": \"%s\",\n", options_.image.c_str());
  std::printf("  \"scenario\": \"%s\",\n", scenario_.name.c_str());
  std::printf("  \"sim_time_ms\": %s,\n", num(static_cast<double>(now) / 1000.0).c_str());
  std::printf("  \"devices\": %d,\n", f.boards);
  std::printf("  \"scans\": %u,\n", f.scans);
  std::printf("  \"scan_failures\": %u,\n", f.scanFailures);
  std::printf("  \"scan_period_ms\": %u,\n", f.scanPeriodMs);
  std::printf("  \"scan_bus_us\": %s,\n", num(f.scanBusUs).c_str());
  std::printf("  \"scan_transactions\": %s,\n", num(f.scanTransactions).c_str());
  std::printf("  \"output\": \"%s\",\n", f.output.c_str());
  std::printf("  \"can_frames\": %llu,\n", static_cast<unsigned long long>(f.outputFrames));
  // The frames per identifier (CAN, or the SLCAN lines decoded), for tools that check what a reader saw.
  std::map<uint32_t, unsigned> byId;
  for (const auto& fr : sim_.frames())
    ++byId[fr.id];
  std::printf("  \"frames_by_id\": {");
  for (auto it = byId.begin(); it != byId.end(); ++it)
    std::printf("%s\"0x%03X\": %u", it == byId.begin() ? "" : ", ", it->first, it->second);
  std::printf("},\n");
  std::printf("  \"comm_errors\": %llu,\n", static_cast<unsigned long long>(f.commErrors));
  std::printf("  \"recoveries\": %u,\n", f.recoveries);
  std::printf("  \"bus_off_applicable\": %s,\n", busOffUnsupported ? "false" : "true");
  std::printf("  \"watchdog_feeds\": %zu,\n", watchdog.feeds().size());
  std::printf("  \"watchdog_longest_gap_ms\": %s,\n",
              num(static_cast<double>(watchdog.longestGapUs(0)) / 1000.0).c_str());
  // The paths as confirmed; null while nothing confirms them (PackSummary says not available).
  std::printf("  \"charge_on\": %s,\n", !f.pathsKnown ? "null" : f.chargeOn ? "true" : "false");
  std::printf("  \"discharge_on\": %s,\n", !f.pathsKnown ? "null" : f.dischargeOn ? "true" : "false");
  std::printf("  \"fault_output\": %s,\n", f.faultOutput ? "true" : "false");
  std::printf("  \"active_faults\": [");
  bool first = true;
  for (uint8_t i = 0; i < fw::app::kFaultCount; ++i) {
    if ((f.activeFaults & (1U << i)) == 0) continue;
    std::printf("%s\"%s\"", first ? "" : ", ", fw::app::faultName(static_cast<fw::app::FaultId>(i)));
    first = false;
  }
  std::printf("],\n");
  std::printf("  \"min_cell_mv\": %d,\n  \"max_cell_mv\": %d,\n", f.minCellMv, f.maxCellMv);
  for (const auto& [key, value] : f.extra)
    std::printf("  \"%s\": %s,\n", key.c_str(), value.c_str());
  std::printf("  \"protection_events\": [");
  first = true;
  for (const auto& e : log) {
    const EventLatency l = latencyOf(e, onsets);
    std::printf(
        "%s\n    {\"fault\": \"%s\", \"onset_ms\": %s, \"detected_ms\": %s, \"command_done_ms\": %s, "
        "\"fets_off_ms\": %s, \"latency_ms\": %s, \"latency_note\": %s}",
        first ? "" : ",", fw::app::faultName(e.fault), l.onsetUs ? ms(*l.onsetUs).c_str() : "null",
        ms(e.detected.us).c_str(), e.actionDone ? ms(e.acted.us).c_str() : "null",
        e.confirmedOff ? ms(e.confirmed.us).c_str() : "null", l.latencyUs ? ms(*l.latencyUs).c_str() : "null",
        l.note ? ("\"" + std::string(l.note) + "\"").c_str() : "null");
    first = false;
  }
  std::printf("%s]\n}\n", first ? "" : "\n  ");
}

bool Report::writeCandump(const std::string& path) const {
  FILE* out = std::fopen(path.c_str(), "w");
  if (out == nullptr) return false;
  for (const auto& fr : sim_.frames()) {
    std::fprintf(out, "(%llu.%06llu) can0 ",
                 static_cast<unsigned long long>(kEpochSeconds + fr.timeUs / 1000000),
                 static_cast<unsigned long long>(fr.timeUs % 1000000));
    if (fr.extended) {
      std::fprintf(out, "%08X#", fr.id);
    } else {
      std::fprintf(out, "%03X#", fr.id);
    }
    for (uint8_t b : fr.data)
      std::fprintf(out, "%02X", b);
    std::fprintf(out, "\n");
  }
  return std::fclose(out) == 0;
}

}  // namespace bmssim
