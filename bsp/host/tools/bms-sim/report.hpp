// Output of a bms-sim run: the live view, the --json summary, the candump log and the SLCAN text.
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "image_sim.hpp"
#include "scenario.hpp"
#include "sim/peripherals.hpp"
#include "slcan_output.hpp"

namespace bmssim {

// A protection event's latency, from the onset of the condition it answers (its fault's expect, else the
// `any` expect) to the action taking effect: the FET command completed on the bus, or the fault output
// driven (the JSON's command_done_ms). Its fets_off_ms is later and only ever what was confirmed: the scan
// whose FET read-back showed the paths off (ProtectionRecord::confirmed), or the pin. Never negative: without
// an onset, with the fault detected before the onset, or with the action still pending there is no latency
// and `note` says which.
struct EventLatency {
  std::optional<uint64_t> onsetUs;
  std::optional<uint64_t> latencyUs;
  const char* note = nullptr;  // "no expected onset", "fault before onset", "action pending"
};
EventLatency latencyOf(const fw::app::ProtectionRecord& event, const Onsets& onsets);

// What became of an `expect` step: met when a protection event of its fault (any fault for `any`) was
// detected at or after its onset; missed when the onset never came (the run ended before the step, or the
// pack never reached the limit) or no such event followed it. A scenario with a missed expect fails the run
// (exit status 3, scenario.hpp).
struct ExpectVerdict {
  const Step* step = nullptr;
  std::optional<uint32_t> onsetMs;
  std::optional<fw::app::ProtectionRecord> event;  // the first one detected at or after the onset
  std::string missed;                              // why it was missed; empty when met
};
std::vector<ExpectVerdict> judgeExpects(const Scenario& scenario, const Onsets& onsets,
                                        const std::vector<fw::app::ProtectionRecord>& log,
                                        uint32_t durationMs);
// An expect-storage step: met when a StorageStatus frame with its mode went out within 2 s of the step.
struct StorageVerdict {
  const Step* step = nullptr;
  std::optional<uint64_t> seenUs;  // that frame
  std::string missed;              // why it was missed; empty when met
};
std::vector<StorageVerdict> judgeStorageExpects(const Scenario& scenario,
                                                const std::vector<SentFrame>& frames, uint32_t durationMs);

// What the end of a run hands the report: besides the image's own figures, the scenario player's view.
struct RunEnd {
  const Onsets& onsets;
  bool busOffUnsupported;
  int32_t loadDemandMa;   // what the load or charger asks for
  int32_t loadFlowingMa;  // what flows through the pack's paths
  Paths paths;            // the emulated device's paths at the end
};

class Report {
 public:
  Report(ImageSim& sim, const SimOptions& options, const Scenario& scenario, bool json)
      : sim_(sim), options_(options), scenario_(scenario), json_(json) {}

  // --slcan: the SLCAN output the run feeds (the image must have an SLCAN UART).
  void attachSlcan(SlcanOutput& out) { slcan_ = &out; }
  // Where the live view goes (flushed line by line, so a slow run shows its progress); nullptr: nowhere.
  void setLiveOutput(FILE* out) { live_ = out; }
  // Called after every millisecond of simulated time: feeds the SLCAN output, prints the live view every
  // 500 ms of simulated time.
  void tick(uint64_t nowUs);
  // Prints the JSON summary (with --json) or the final view, the protection events, the bus-offs and what
  // became of each expect. Returns the number of expects missed.
  size_t finish(const RunEnd& end, const bsp::host::SimWatchdog& watchdog);
  // candump -l format: "(seconds.micros) can0 ID#DATA", one frame per line. Times are absolute, as candump
  // writes them: the run starts at kEpochSeconds (so can-utils' log2asc sees one start, not "time 0").
  bool writeCandump(const std::string& path) const;
  static constexpr uint64_t kEpochSeconds = 1735689600;  // 2025-01-01 00:00:00 UTC, the scenario's start

 private:
  ImageSim& sim_;
  const SimOptions& options_;
  const Scenario& scenario_;
  bool json_;
  FILE* live_ = nullptr;
  uint64_t nextView_ = 0;
  SlcanOutput* slcan_ = nullptr;
};

}  // namespace bmssim
