// Scenarios: what happens to the emulated pack over time.
//
// A scenario is a list of timed steps. Built-in names: idle, charge, discharge, ov-cell, ot, open-wire,
// comm-loss, bus-off, stale. A file holds one step per line:
//   <time_ms> current <mA>
//   <time_ms> cell <board> <cell> <mV>                 cells are numbered from 1
//   <time_ms> ramp-cell <board> <cell> <mV_per_s>      drift from the current value
//   <time_ms> all-cells <mV>
//   <time_ms> temp <board> <sensor> <deciK>
//   <time_ms> ramp-temp <board> <sensor> <deciK_per_s>
//   <time_ms> comm-loss on|off
//   <time_ms> open-wire <board> <cell>
//   <time_ms> intermittent on|off
//   <time_ms> bus-off
//   <time_ms> expect <fault-name> <onset-description>  marks the onset of the condition a fault should catch
// '#' starts a comment. Errors name the file, line and column.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bmssim {

struct Step {
  uint32_t timeMs = 0;
  std::string action;
  std::vector<double> args;
  std::string text;  // on|off, fault names
};

struct Scenario {
  std::string name;
  std::string description;
  std::vector<Step> steps;
  // A limit the scenario's condition crosses, so its onset time can be found: onset is when the emulated
  // value first reaches `threshold` (a cell in mV or a temperature in 0.1 K), for the fault named.
  std::string watchFault;
  std::string watchKind;  // "cell-above", "cell-below", "temp-above", "step" (onset = a step's time)
  double threshold = 0;
};

std::optional<Scenario> builtinScenario(const std::string& name);
std::vector<std::string> builtinNames();
// Parses a scenario file; on error returns nullopt and sets `error` to "file:line:col: error: ...".
std::optional<Scenario> loadScenario(const std::string& path, std::string& error);

}  // namespace bmssim
