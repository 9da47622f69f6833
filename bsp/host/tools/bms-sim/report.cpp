#include "report.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <string_view>

#include "app/protection/protection.hpp"
#include "can/bms.hpp"
#include "can/bms_table.hpp"
#include "storage_view.hpp"

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

const char* unitOf(Watch w) {
  switch (w) {
    case Watch::CellAbove:
    case Watch::CellBelow:
      return "mV";
    case Watch::CurrentAbove:
    case Watch::CurrentBelow:
      return "mA";
    case Watch::TempAbove:
    case Watch::TempBelow:
      return "0.1 K";
    case Watch::None:
      break;
  }
  return "";
}

// "cell_ov 4250" or "comm_loss": the expect as written.
std::string expectText(const Step& st) {
  return st.fault + (st.hasLimit ? " " + std::to_string(st.value) : "");
}

// A bus-off as a reader of the bus sees it: the first frame after it began, and how far PackSummary.Counter
// jumped across it (bms.yaml: each cycle's summary counts one; a gap is a summary that never went out).
struct BusOffView {
  BusOffSpan span;
  std::optional<uint64_t> firstFrameUs;
  std::optional<unsigned> counterSkipped;
};

std::vector<BusOffView> busOffViews(const std::vector<BusOffSpan>& spans,
                                    const std::vector<SentFrame>& frames) {
  namespace bms = fw::can::bms;
  std::vector<BusOffView> out;
  for (const BusOffSpan& span : spans) {
    BusOffView v{span, std::nullopt, std::nullopt};
    std::optional<uint8_t> before, after;
    for (const SentFrame& f : frames) {
      const bool summary = !f.extended && f.id == bms::PackSummary::kId && f.data.size() == 8;
      fw::hal::CanFrame c{f.id, f.extended, static_cast<uint8_t>(f.data.size()), {}};
      std::copy(f.data.begin(), f.data.end(), c.data.begin());
      if (f.timeUs <= span.startUs) {
        if (summary) before = bms::PackSummary::unpack(c).counter;
        continue;
      }
      if (!v.firstFrameUs) v.firstFrameUs = f.timeUs;
      if (summary) {
        after = bms::PackSummary::unpack(c).counter;
        break;
      }
    }
    if (before && after) v.counterSkipped = static_cast<unsigned>((*after - *before - 1) & 0x0F);
    out.push_back(v);
  }
  return out;
}

}  // namespace

std::vector<ExpectVerdict> judgeExpects(const Scenario& scenario, const Onsets& onsets,
                                        const std::vector<fw::app::ProtectionRecord>& log,
                                        uint32_t durationMs) {
  std::vector<ExpectVerdict> out;
  for (const Step& st : scenario.steps) {
    if (st.action != Action::Expect) continue;
    ExpectVerdict v;
    v.step = &st;
    if (const auto o = onsets.find(st.fault); o != onsets.end()) v.onsetMs = o->second;
    if (!v.onsetMs) {
      v.missed = st.timeMs > durationMs
                     ? "the run ended (" + std::to_string(durationMs) + " ms) before the step at " +
                           std::to_string(st.timeMs) + " ms"
                     : "the pack never reached " + std::to_string(st.value) + " " + unitOf(st.watch);
      out.push_back(std::move(v));
      continue;
    }
    const uint64_t onsetUs = static_cast<uint64_t>(*v.onsetMs) * 1000;
    std::optional<uint64_t> before;  // an event of the fault detected before the onset
    for (const auto& e : log) {
      if (st.fault != "any" && st.fault != fw::app::faultName(e.fault)) continue;
      if (e.detected.us >= onsetUs) {
        v.event = e;
        break;
      }
      before = e.detected.us;
    }
    if (!v.event) {
      v.missed =
          "no " + (st.fault == "any" ? std::string("protection") : st.fault) + " event at or after the onset";
      if (before) v.missed += " (one was detected before it, at " + ms(*before) + " ms)";
    }
    out.push_back(std::move(v));
  }
  return out;
}

std::vector<StorageVerdict> judgeStorageExpects(const Scenario& scenario,
                                                const std::vector<SentFrame>& frames, uint32_t durationMs) {
  namespace bms = fw::can::bms;
  std::vector<StorageVerdict> out;
  for (const Step& st : scenario.steps) {
    if (st.action != Action::ExpectStorage) continue;
    StorageVerdict v{&st, std::nullopt, ""};
    const uint64_t from = uint64_t{st.timeMs} * 1000, to = from + 2'000'000;
    bool any = false;
    for (const SentFrame& f : frames) {
      if (f.id != bms::StorageStatus::kId || f.extended || f.data.size() != 8 || f.timeUs < from) continue;
      if (f.timeUs > to) break;
      any = true;
      fw::hal::CanFrame c{f.id, false, 8, {}};
      std::copy(f.data.begin(), f.data.end(), c.data.begin());
      if ((bms::StorageStatus::unpack(c).mode == 1) == st.on) {
        v.seenUs = f.timeUs;
        break;
      }
    }
    if (!v.seenUs) {
      v.missed = st.timeMs > durationMs ? "the run ended (" + std::to_string(durationMs) +
                                              " ms) before the step at " + std::to_string(st.timeMs) + " ms"
                 : any ? std::string("StorageStatus said ") + (st.on ? "normal" : "storage") +
                             " for 2 s after the step"
                       : std::string("no StorageStatus within 2 s of the step (an image without storage?)");
    }
    out.push_back(std::move(v));
  }
  return out;
}

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

namespace {

// The StateOfCharge message's basis by name (bms.yaml's values), "" when not available.
const char* basisName(int raw) {
  for (const auto& v : fw::can::bms::table::kStateOfChargeBasisValues)
    if (v.raw == raw && std::string_view(v.name) != "not_available") return v.name;
  return "";
}

// The live view's SOC column: "43.7 % 1092/2500 mAh ocv", or "--" while not available.
std::string socText(const SimFigures& f) {
  if (f.socPermille < 0)
    return f.stateOfChargePercent < 0 ? "--" : std::to_string(f.stateOfChargePercent) + " %";
  char buf[80];
  std::snprintf(buf, sizeof buf, "%d.%d %% %lld/%lld mAh %s", f.socPermille / 10, f.socPermille % 10,
                static_cast<long long>(f.remainingMah), static_cast<long long>(f.fullChargeMah),
                basisName(f.socBasis));
  return buf;
}

}  // namespace

void Report::tick(uint64_t nowUs) {
  if (slcan_ != nullptr) slcan_->step(*sim_.slcanText(), nowUs);
  if (live_ == nullptr || nowUs < nextView_) return;
  nextView_ = nowUs + 500000;
  const SimFigures f = sim_.figures();
  int balancing = 0;  // cells the devices balance now
  for (uint16_t m : f.balancingCells)
    balancing += __builtin_popcount(m);
  std::fprintf(
      live_,
      "t=%7.2fs  scans %5u  boards %d/%d  cells %4d..%4d mV  I=%+8.2f A  %s %s  faults: %-22s %s %llu  "
      "spread %3d mV, balancing %d cells  SOC %s\n",
      static_cast<double>(nowUs) / 1e6, f.scans, f.validBoards, f.boards, f.minCellMv, f.maxCellMv,
      f.currentMa / 1000.0,
      !f.pathsKnown ? "CHG:?  "
      : f.chargeOn  ? "CHG:on "
                    : "CHG:off",
      !f.pathsKnown   ? "DSG:?  "
      : f.dischargeOn ? "DSG:on "
                      : "DSG:off",
      faultsText(f.activeFaults).c_str(), f.output == "can" ? "CAN frames" : "SLCAN lines",
      static_cast<unsigned long long>(f.outputFrames), f.cellSpreadMv, balancing, socText(f).c_str());
  std::fflush(live_);
}

size_t Report::finish(const RunEnd& end, const bsp::host::SimWatchdog& watchdog) {
  const SimFigures f = sim_.figures();
  const auto log = sim_.protectionLog();
  const uint64_t now = sim_.harness().nowUs();
  const Onsets& onsets = end.onsets;
  const auto verdicts = judgeExpects(scenario_, onsets, log, options_.durationMs);
  const auto storageVerdicts = judgeStorageExpects(scenario_, sim_.frames(), options_.durationMs);
  const size_t missed =
      static_cast<size_t>(std::count_if(verdicts.begin(), verdicts.end(),
                                        [](const ExpectVerdict& v) { return !v.missed.empty(); })) +
      static_cast<size_t>(std::count_if(storageVerdicts.begin(), storageVerdicts.end(),
                                        [](const StorageVerdict& v) { return !v.missed.empty(); }));
  const auto busOffs = busOffViews(sim_.busOffLog(), sim_.frames());
  if (!json_) {
    std::printf("\nscenario %s: %s\n", scenario_.name.c_str(), scenario_.description.c_str());
    if (end.busOffUnsupported) std::printf("(this image has no CAN bus: the bus-off step did nothing)\n");
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
    for (const BusOffView& b : busOffs) {
      std::printf("bus-off at %s ms: %s, next frame %s, PackSummary.Counter %s\n", ms(b.span.startUs).c_str(),
                  b.span.recoveredUs ? ("error active again at " + ms(*b.span.recoveredUs) + " ms (after " +
                                        ms(*b.span.recoveredUs - b.span.startUs) + " ms)")
                                           .c_str()
                                     : "not recovered by the end of the run",
                  b.firstFrameUs ? ("at " + ms(*b.firstFrameUs) + " ms").c_str() : "none",
                  b.counterSkipped ? ("skips " + std::to_string(*b.counterSkipped)).c_str() : "-");
    }
    std::printf("load %+.3f A asked, %+.3f A flowing (charge path %s, discharge path %s)\n",
                end.loadDemandMa / 1000.0, end.loadFlowingMa / 1000.0, end.paths.charge ? "closed" : "open",
                end.paths.discharge ? "closed" : "open");
    for (const ExpectVerdict& v : verdicts) {
      const Step& st = *v.step;
      if (v.missed.empty()) {
        std::printf("expect %s (%s:%u): met, onset %s ms, %s detected %s ms\n", expectText(st).c_str(),
                    scenario_.name.c_str(), st.line, ms(static_cast<uint64_t>(*v.onsetMs) * 1000).c_str(),
                    fw::app::faultName(v.event->fault), ms(v.event->detected.us).c_str());
      } else {
        std::printf("expect %s (%s:%u): MISSED: %s\n", expectText(st).c_str(), scenario_.name.c_str(),
                    st.line, v.missed.c_str());
      }
    }
    for (const StorageVerdict& v : storageVerdicts) {
      const Step& st = *v.step;
      if (v.missed.empty()) {
        std::printf("expect-storage %s (%s:%u): met, StorageStatus at %s ms\n", st.on ? "on" : "off",
                    scenario_.name.c_str(), st.line, ms(*v.seenUs).c_str());
      } else {
        std::printf("expect-storage %s (%s:%u): MISSED: %s\n", st.on ? "on" : "off", scenario_.name.c_str(),
                    st.line, v.missed.c_str());
      }
    }
    if (missed != 0) std::printf("%zu expect(s) missed\n", missed);
    return missed;
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
  std::printf("  \"bus_off_applicable\": %s,\n", end.busOffUnsupported ? "false" : "true");
  // Each bus-off: when, when the controller was error active again, the first frame after it, and how far
  // PackSummary.Counter jumped across it.
  std::printf("  \"bus_off\": [");
  for (size_t i = 0; i < busOffs.size(); ++i) {
    const BusOffView& b = busOffs[i];
    std::printf(
        "%s\n    {\"at_ms\": %s, \"recovered_ms\": %s, \"recovery_ms\": %s, \"first_frame_ms\": %s, "
        "\"pack_summary_counter_skipped\": %s}",
        i == 0 ? "" : ",", ms(b.span.startUs).c_str(),
        b.span.recoveredUs ? ms(*b.span.recoveredUs).c_str() : "null",
        b.span.recoveredUs ? ms(*b.span.recoveredUs - b.span.startUs).c_str() : "null",
        b.firstFrameUs ? ms(*b.firstFrameUs).c_str() : "null",
        b.counterSkipped ? std::to_string(*b.counterSkipped).c_str() : "null");
  }
  std::printf("%s],\n", busOffs.empty() ? "" : "\n  ");
  // The emulated load or charger: what it asks for, what flows through the device's paths.
  std::printf("  \"load_demand_ma\": %d,\n  \"load_current_ma\": %d,\n", end.loadDemandMa, end.loadFlowingMa);
  std::printf("  \"charge_path_closed\": %s,\n  \"discharge_path_closed\": %s,\n",
              end.paths.charge ? "true" : "false", end.paths.discharge ? "true" : "false");
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
  // PackSummary.StateOfCharge as the board published it (null: not available, e.g. the BQ79616 image, or not
  // known yet).
  if (f.stateOfChargePercent < 0) {
    std::printf("  \"state_of_charge_percent\": null,\n");
  } else {
    std::printf("  \"state_of_charge_percent\": %d,\n", f.stateOfChargePercent);
  }
  // The StateOfCharge message as the board published it (null: not available), and the charge the emulated
  // device let flow since the start (null where the emulator does not count it): a user checks the one
  // against the other.
  auto optionalInt = [](const char* key, int64_t v) {
    if (v < 0) {
      std::printf("  \"%s\": null,\n", key);
    } else {
      std::printf("  \"%s\": %lld,\n", key, static_cast<long long>(v));
    }
  };
  optionalInt("state_of_charge_permille", f.socPermille);
  optionalInt("remaining_capacity_mah", f.remainingMah);
  optionalInt("full_charge_capacity_mah", f.fullChargeMah);
  if (f.socBasis < 0) {
    std::printf("  \"soc_basis\": null,\n");
  } else {
    std::printf("  \"soc_basis\": \"%s\",\n", basisName(f.socBasis));
  }
  if (f.emulatorChargeMah) {
    std::printf("  \"emulator_charge_mah\": %.3f,\n", *f.emulatorChargeMah);
  } else {
    std::printf("  \"emulator_charge_mah\": null,\n");
  }
  // Balancing as the emulated devices do it now: per board the cells (numbered from 1) they balance, and the
  // spread of the emulated cells (ImageSim::balancingCells(), cellSpreadMv()).
  std::printf("  \"balancing_cells\": [");
  for (size_t b = 0; b < f.balancingCells.size(); ++b) {
    std::printf("%s[", b == 0 ? "" : ", ");
    bool firstCell = true;
    for (int c = 0; c < 16; ++c) {
      if (((f.balancingCells[b] >> c) & 1U) == 0) continue;
      std::printf("%s%d", firstCell ? "" : ", ", c + 1);
      firstCell = false;
    }
    std::printf("]");
  }
  std::printf("],\n  \"cell_spread_mv\": %d,\n", f.cellSpreadMv);
  // Pack storage as the board published it (StorageStatus; null where the image sends none).
  const StorageSummary st = storageSummary(sim_.frames());
  if (!st.sent) {
    std::printf("  \"storage_mode\": null,\n");
  } else {
    std::printf("  \"storage_mode\": \"%s\",\n  \"storage_scan_period_ms\": %u,\n",
                st.on ? "storage" : "normal", st.scanPeriodMs);
    std::printf("  \"storage_entered_ms\": %s,\n  \"storage_left_ms\": %s,\n",
                st.enteredUs ? ms(*st.enteredUs).c_str() : "null",
                st.leftUs ? ms(*st.leftUs).c_str() : "null");
    optionalInt("measurement_age_ms", st.ageMs ? static_cast<int64_t>(*st.ageMs) : -1);
    std::printf("  \"measurement_age_max_ms\": %u,\n", st.maxAgeMs);
  }
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
  std::printf("%s],\n", first ? "" : "\n  ");
  // What became of each expect (scenario.hpp): a missed one makes the run exit with status 3.
  std::printf("  \"expects\": [");
  for (size_t i = 0; i < verdicts.size(); ++i) {
    const ExpectVerdict& v = verdicts[i];
    const Step& st = *v.step;
    std::printf(
        "%s\n    {\"fault\": \"%s\", \"limit\": %s, \"line\": %u, \"onset_ms\": %s, \"detected_ms\": %s, "
        "\"met\": %s, \"missed\": %s}",
        i == 0 ? "" : ",", st.fault.c_str(), st.hasLimit ? std::to_string(st.value).c_str() : "null", st.line,
        v.onsetMs ? ms(static_cast<uint64_t>(*v.onsetMs) * 1000).c_str() : "null",
        v.event ? ms(v.event->detected.us).c_str() : "null", v.missed.empty() ? "true" : "false",
        v.missed.empty() ? "null" : ("\"" + v.missed + "\"").c_str());
  }
  std::printf("%s],\n", verdicts.empty() ? "" : "\n  ");
  std::printf("  \"storage_expects\": [");
  for (size_t i = 0; i < storageVerdicts.size(); ++i) {
    const StorageVerdict& v = storageVerdicts[i];
    std::printf("%s\n    {\"mode\": \"%s\", \"line\": %u, \"at_ms\": %u, \"seen_ms\": %s, \"met\": %s}",
                i == 0 ? "" : ",", v.step->on ? "storage" : "normal", v.step->line, v.step->timeMs,
                v.seenUs ? ms(*v.seenUs).c_str() : "null", v.missed.empty() ? "true" : "false");
  }
  std::printf("%s],\n", storageVerdicts.empty() ? "" : "\n  ");
  std::printf("  \"expects_missed\": %zu\n}\n", missed);
  return missed;
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
