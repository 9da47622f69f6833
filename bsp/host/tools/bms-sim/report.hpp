// Output of a bms-sim run: the live view, the --json summary and the candump log.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

#include "image_sim.hpp"
#include "scenario.hpp"
#include "sim/peripherals.hpp"

namespace bmssim {

// A protection event's latency, from the onset of the condition it answers (its fault's expect, else the
// `any` expect) to the FET-off / fault output. Never negative: without an onset, with the fault detected
// before the onset, or with the action still pending there is no latency and `note` says which.
struct EventLatency {
  std::optional<uint64_t> onsetUs;
  std::optional<uint64_t> latencyUs;
  const char* note = nullptr;  // "no expected onset", "fault before onset", "action pending"
};
EventLatency latencyOf(const fw::app::ProtectionRecord& event, const Onsets& onsets);

class Report {
 public:
  Report(ImageSim& sim, const SimOptions& options, const Scenario& scenario, bool json)
      : sim_(sim), options_(options), scenario_(scenario), json_(json) {}

  // Where the live view goes (flushed line by line, so a slow run shows its progress); nullptr: nowhere.
  void setLiveOutput(FILE* out) { live_ = out; }
  // Called after every millisecond of simulated time; prints the live view every 500 ms of simulated time.
  void tick(uint64_t nowUs);
  // Prints the JSON summary (with --json) or the final view and the protection events.
  void finish(const Onsets& onsets, bool busOffUnsupported, const bsp::host::SimWatchdog& watchdog);
  // candump -l format: "(seconds.micros) can0 ID#DATA", one frame per line.
  bool writeCandump(const std::string& path) const;

 private:
  ImageSim& sim_;
  const SimOptions& options_;
  const Scenario& scenario_;
  bool json_;
  FILE* live_ = nullptr;
  uint64_t nextView_ = 0;
};

}  // namespace bmssim
