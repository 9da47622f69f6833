#include "scenario.hpp"

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

namespace bmssim {
namespace {

Step step(uint32_t t, std::string action, std::vector<double> args = {}, std::string text = {}) {
  return Step{t, std::move(action), std::move(args), std::move(text)};
}

// Arguments each action takes: numbers, then an optional word (on/off).
const std::map<std::string, std::pair<int, bool>>& actions() {
  static const std::map<std::string, std::pair<int, bool>> table = {
      {"current", {1, false}},     {"cell", {3, false}},     {"ramp-cell", {3, false}},
      {"all-cells", {1, false}},   {"ramp-all", {1, false}}, {"temp", {3, false}},
      {"ramp-temp", {3, false}},   {"comm-loss", {0, true}}, {"open-wire", {2, false}},
      {"intermittent", {0, true}}, {"bus-off", {0, false}},  {"onset", {0, false}},
  };
  return table;
}

}  // namespace

std::vector<std::string> builtinNames() {
  return {"idle", "charge", "discharge", "ov-cell", "ot", "open-wire", "comm-loss", "bus-off", "stale"};
}

std::optional<Scenario> builtinScenario(const std::string& name) {
  Scenario s;
  s.name = name;
  if (name == "idle") {
    s.description = "a resting pack at 3.70 V per cell, 25 degC";
  } else if (name == "charge") {
    s.description = "charging at 10 A: cells rise 20 mV/s from 3.70 V";
    s.steps = {step(0, "current", {10000}), step(0, "ramp-all", {20})};
  } else if (name == "discharge") {
    s.description = "discharging at 15 A: cells fall 20 mV/s from 3.70 V";
    s.steps = {step(0, "current", {-15000}), step(0, "ramp-all", {-20})};
  } else if (name == "ov-cell") {
    s.description = "cell 2 of board 0 drifts up 40 mV/s from 4.20 V past the 4.25 V over-voltage limit";
    s.steps = {step(0, "current", {5000}), step(0, "cell", {0, 2, 4200}),
               step(1000, "ramp-cell", {0, 2, 40})};
    s.watchKind = "cell-above";
    s.threshold = 4250;
  } else if (name == "ot") {
    s.description = "sensor 1 of board 0 heats 5 degC/s from 25 degC past the 60 degC limit";
    s.steps = {step(1000, "ramp-temp", {0, 1, 50})};
    s.watchKind = "temp-above";
    s.threshold = 3332;
  } else if (name == "open-wire") {
    s.description = "the sense wire between cells 2 and 3 of board 0 opens at 2 s";
    s.steps = {step(2000, "open-wire", {0, 3}), step(2000, "onset")};
    s.watchKind = "step";
  } else if (name == "comm-loss") {
    s.description = "the battery monitor stops answering at 2 s";
    s.steps = {step(2000, "comm-loss", {}, "on"), step(2000, "onset")};
    s.watchKind = "step";
  } else if (name == "bus-off") {
    s.description = "the CAN controller goes bus-off at 2 s and recovers";
    s.steps = {step(2000, "bus-off"), step(2000, "onset")};
    s.watchKind = "step";
  } else if (name == "stale") {
    s.description = "from 2 s to 6 s most monitor transactions are corrupted, then the link heals";
    s.steps = {step(2000, "intermittent", {}, "on"), step(2000, "onset"),
               step(6000, "intermittent", {}, "off")};
    s.watchKind = "step";
  } else {
    return std::nullopt;
  }
  return s;
}

std::optional<Scenario> loadScenario(const std::string& path, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = path + ": error: cannot read the scenario file";
    return std::nullopt;
  }
  Scenario s;
  s.name = path;
  s.watchKind = "step";
  std::string line;
  for (int lineNo = 1; std::getline(in, line); ++lineNo) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::vector<std::pair<std::string, size_t>> tokens;  // word and its column
    std::string w;
    size_t pos = 0;
    while (words >> w) {
      pos = line.find(w, pos);
      tokens.emplace_back(w, pos + 1);
      pos += w.size();
    }
    if (tokens.empty()) continue;
    auto fail = [&](size_t col, const std::string& msg) {
      error = path + ":" + std::to_string(lineNo) + ":" + std::to_string(col) + ": error: " + msg;
      return std::nullopt;
    };
    char* end = nullptr;
    const unsigned long t = std::strtoul(tokens[0].first.c_str(), &end, 10);
    if (*end != '\0') return fail(tokens[0].second, "expected a time in ms, got '" + tokens[0].first + "'");
    if (tokens.size() < 2) return fail(tokens[0].second, "expected an action after the time");
    const auto it = actions().find(tokens[1].first);
    if (it == actions().end()) return fail(tokens[1].second, "unknown action '" + tokens[1].first + "'");
    const auto [numbers, word] = it->second;
    const size_t expected = 2 + static_cast<size_t>(numbers) + (word ? 1 : 0);
    if (tokens.size() != expected) {
      return fail(tokens[1].second, "'" + tokens[1].first + "' takes " + std::to_string(expected - 2) +
                                        " argument(s), got " + std::to_string(tokens.size() - 2));
    }
    Step st{static_cast<uint32_t>(t), tokens[1].first, {}, {}};
    for (int i = 0; i < numbers; ++i) {
      const auto& tok = tokens[2 + static_cast<size_t>(i)];
      const double v = std::strtod(tok.first.c_str(), &end);
      if (*end != '\0') return fail(tok.second, "expected a number, got '" + tok.first + "'");
      st.args.push_back(v);
    }
    if (word) {
      const auto& tok = tokens.back();
      if (tok.first != "on" && tok.first != "off") return fail(tok.second, "expected on or off");
      st.text = tok.first;
    }
    s.steps.push_back(st);
  }
  return s;
}

}  // namespace bmssim
