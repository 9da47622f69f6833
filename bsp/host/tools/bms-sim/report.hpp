// Output of a bms-sim run: the live view, the --json summary, the candump log and the SLCAN text.
#pragma once

#include <string>

#include "image_sim.hpp"
#include "scenario.hpp"
#include "sim/peripherals.hpp"
#include "slcan_output.hpp"

namespace bmssim {

class Report {
 public:
  Report(ImageSim& sim, const SimOptions& options, const Scenario& scenario, bool json)
      : sim_(sim), options_(options), scenario_(scenario), json_(json) {}

  // --slcan: the SLCAN output the run feeds (the image must have an SLCAN UART).
  void attachSlcan(SlcanOutput& out) { slcan_ = &out; }
  // Called after every millisecond of simulated time: feeds the SLCAN output, prints the live view every
  // 500 ms unless --json.
  void tick(uint64_t nowUs);
  // Prints the JSON summary (with --json) or the final view and the protection events.
  void finish(double onsetMs, bool busOffUnsupported, const bsp::host::SimWatchdog& watchdog);
  // candump -l format: "(seconds.micros) can0 ID#DATA", one frame per line. Times are absolute, as candump
  // writes them: the run starts at kEpochSeconds (so can-utils' log2asc sees one start, not "time 0").
  bool writeCandump(const std::string& path) const;
  static constexpr uint64_t kEpochSeconds = 1735689600;  // 2025-01-01 00:00:00 UTC, the scenario's start

 private:
  ImageSim& sim_;
  const SimOptions& options_;
  const Scenario& scenario_;
  bool json_;
  uint64_t nextView_ = 0;
  SlcanOutput* slcan_ = nullptr;
};

}  // namespace bmssim
