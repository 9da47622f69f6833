// Output of a bms-sim run: the live view, the --json summary and the candump log.
#pragma once

#include <string>

#include "image_sim.hpp"
#include "scenario.hpp"
#include "sim/peripherals.hpp"

namespace bmssim {

class Report {
 public:
  Report(ImageSim& sim, const SimOptions& options, const Scenario& scenario, bool json)
      : sim_(sim), options_(options), scenario_(scenario), json_(json) {}

  // Called after every millisecond of simulated time; prints the live view every 500 ms unless --json.
  void tick(uint64_t nowUs);
  // Prints the JSON summary (with --json) or the final view and the protection events.
  void finish(double onsetMs, bool busOffUnsupported, const bsp::host::SimWatchdog& watchdog);
  // candump -l format: "(seconds.micros) can0 ID#DATA", one frame per line.
  bool writeCandump(const std::string& path) const;

 private:
  ImageSim& sim_;
  const SimOptions& options_;
  const Scenario& scenario_;
  bool json_;
  uint64_t nextView_ = 0;
};

}  // namespace bmssim
