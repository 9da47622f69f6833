#include "scenario.hpp"

#include "scenario_command.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdio>

#include "input_file.hpp"

namespace bmssim {
namespace {

// What an argument is: its name in messages and its range. The ranges are what the scenario.hpp header
// promises; why each is what it is:
//   cell mV 0..5000: inside every monitor's cell input range (BQ76905 differential cell input -0.2..5.5 V,
//     SLUSE97 6.12, the same in the BQ76972's ADC table, SLUSFC9; BQ79616 VCELL 16-bit two's complement at
//     190.73 uV per LSB, +-6.25 V, SLUSE81 register map) and the sum of two cells (an open sense wire) still
//     fits the 16-bit mV registers;
//   current mA: CC2 Current (0x3A) is 16-bit signed in userA, 1 mA by default (SLUUBY2B direct commands),
//     and the BQ4050's Current() (0x0A) 16-bit signed mA (SBS 1.1): a larger value could only wrap;
//   temperature 0.1 K: -55..+150 degC, past the firmware's limits (-20 and 60 degC) with margin and within
//     every emulated sensor register (BQ7690x whole degC, BQ79616 DIETEMP 0.025 degC per LSB in 16 bits);
//   board 0..63: the longest BQ79616 chain --devices accepts; cell 1..16 (BQ76952, BQ79616); sensor 1..3
//     (BQ76952: internal, TS1, TS3), the most any image models.
enum class Arg : uint8_t {
  Board,
  Cell,
  Sensor,
  CellMv,
  CurrentMa,
  TempDeciK,
  CellRate,
  TempRate,
  OnOff,
  Fault,
  Tap,
  CapacityMah,
  SpreadMv,
  StretchUs,
  Ppm,
  Count,
};

struct ArgSpec {
  const char* name;  // in the usage text
  const char* what;  // in messages
  ValueRange range;
};

const ArgSpec& spec(Arg a) {
  static const std::array<ArgSpec, 16> specs = {{
      {"<board>", "a board number", {0, 63}},
      {"<cell>", "a cell number", {1, 16}},
      {"<sensor>", "a sensor number", {1, 3}},
      {"<mV>", "a cell voltage in mV", kCellMvRange},
      {"<mA>", "a current in mA", kCurrentMaRange},
      {"<deciK>", "a temperature in 0.1 K", kTempDeciKRange},
      {"<mV_per_s>", "a cell drift in mV/s", {-5000, 5000}},
      {"<deciK_per_s>", "a temperature drift in 0.1 K/s", {-2050, 2050}},
      {"on|off", "on or off", {0, 1}},
      {"<fault>|any", "a fault name", {0, 0}},
      {"<cell>", "a sense wire number", {1, 17}},  // the wire below that cell; cells + 1: above the top
      {"<mAh>", "a cell capacity in mAh", {1, 100000}},
      {"<spread_mV>", "a spread in mV", {0, 500}},
      {"<us>", "a stretch in us", {0, 100000}},
      {"<ppm>", "a bit error rate in ppm", {0, 1000000}},
      {"<count>", "a number of frames", {1, 1000}},
  }};
  return specs[static_cast<size_t>(a)];
}

struct ActionSpec {
  const char* name;
  Action action;
  std::array<Arg, 3> args;
  uint8_t count;
};

constexpr std::array<ActionSpec, 22> kActions = {{
    {"current", Action::Current, {Arg::CurrentMa}, 1},
    {"cell", Action::Cell, {Arg::Board, Arg::Cell, Arg::CellMv}, 3},
    {"all-cells", Action::AllCells, {Arg::CellMv}, 1},
    {"ramp-cell", Action::RampCell, {Arg::Board, Arg::Cell, Arg::CellRate}, 3},
    {"ramp-all", Action::RampAll, {Arg::CellRate}, 1},
    {"temp", Action::Temp, {Arg::Board, Arg::Sensor, Arg::TempDeciK}, 3},
    {"ramp-temp", Action::RampTemp, {Arg::Board, Arg::Sensor, Arg::TempRate}, 3},
    {"comm-loss", Action::CommLoss, {Arg::OnOff}, 1},
    {"open-wire", Action::OpenWire, {Arg::Board, Arg::Tap}, 2},
    {"intermittent", Action::Intermittent, {Arg::OnOff}, 1},
    {"bus-off", Action::BusOff, {}, 0},
    {"expect", Action::Expect, {Arg::Fault}, 1},  // and an optional limit
    {"cell-capacity", Action::CellCapacity, {Arg::CapacityMah}, 1},
    {"spread-cells", Action::SpreadCells, {Arg::CellMv, Arg::SpreadMv}, 2},
    {"send", Action::Send, {}, 0},    // <Message> [<Signal>=<value> ...]
    {"flood", Action::Flood, {}, 0},  // <ms> <Message> [<Signal>=<value> ...]
    {"stretch", Action::Stretch, {Arg::StretchUs}, 1},
    {"stuck-scl", Action::StuckScl, {}, 0},
    {"stuck-sda", Action::StuckSda, {}, 0},
    {"uart-noise", Action::UartNoise, {Arg::Ppm}, 1},
    {"can-error-frames", Action::CanErrorFrames, {Arg::Count}, 1},
    {"expect-storage", Action::ExpectStorage, {Arg::OnOff}, 1},
}};

// The faults of fw::app::FaultId by their faultName(), and what a limit on each watches (tests check the
// names against the firmware's).
struct FaultSpec {
  const char* name;
  Watch watch;
};
constexpr std::array<FaultSpec, 14> kFaults = {{
    {"cell_ov", Watch::CellAbove},
    {"cell_uv", Watch::CellBelow},
    {"occ", Watch::CurrentAbove},
    {"ocd", Watch::CurrentBelow},
    {"otd", Watch::TempAbove},
    {"utd", Watch::TempBelow},
    {"device_safety", Watch::None},
    {"stale_data", Watch::None},
    {"comm_loss", Watch::None},
    {"open_wire", Watch::None},
    {"otc", Watch::TempAbove},
    {"utc", Watch::TempBelow},
    {"comm_rate", Watch::None},
    {"any", Watch::None},
}};

Arg limitArg(Watch w) {
  switch (w) {
    case Watch::CellAbove:
    case Watch::CellBelow:
      return Arg::CellMv;
    case Watch::CurrentAbove:
    case Watch::CurrentBelow:
      return Arg::CurrentMa;
    default:
      return Arg::TempDeciK;
  }
}

struct Builtin {
  const char* name;
  const char* description;
  const char* text;
};
constexpr std::array<Builtin, 13> kBuiltins = {{
    {"idle", "a resting pack at 3.70 V per cell, 25 degC", ""},
    {"charge", "charging at 10 A: cells rise 20 mV/s from 3.70 V", "0 current 10000\n0 ramp-all 20\n"},
    {"discharge", "discharging at 15 A: cells fall 20 mV/s from 3.70 V",
     "0 current -15000\n0 ramp-all -20\n"},
    {"ov-cell", "cell 2 of board 0 drifts up 40 mV/s from 4.20 V past the 4.25 V over-voltage limit",
     "0 current 5000\n0 cell 0 2 4200\n1000 ramp-cell 0 2 40\n1000 expect cell_ov 4250\n"},
    {"ot",
     "sensor 1 of board 0 heats 5 degC/s from 25 degC past the 45 degC charge and 60 degC discharge limits",
     "1000 ramp-temp 0 1 50\n1000 expect otc 3182\n1000 expect otd 3332\n"},
    {"open-wire", "the sense wire between cells 2 and 3 of board 0 opens at 2 s",
     "2000 open-wire 0 3\n2000 expect any\n"},
    {"comm-loss", "the battery monitor stops answering at 2 s", "2000 comm-loss on\n2000 expect any\n"},
    // Bus-off is no protection fault: the summary's bus-off section reports it (no expect).
    {"bus-off", "the CAN controller goes bus-off at 2 s and recovers", "2000 bus-off\n"},
    {"stale", "from 2 s to 6 s most monitor transactions are corrupted, then the link heals",
     "2000 intermittent on\n2000 expect any\n6000 intermittent off\n"},
    // Balancing (firmware/app/balancing): 4 mAh cells, so the bleed of the balancing path moves a cell by
    // millivolts a second and the run converges in a minute or two of simulated time (a real 2.5 Ah cell
    // takes hours: README.md's figure). Charging at 2 A for 30 s, then at rest (balancing again after the
    // policy's 60 s rest time).
    {"imbalance",
     "every board: cell 1 at 3.90 V, the others 20..80 mV above it; 4 mAh cells; charging at 2 A for 30 s, "
     "then at rest",
     "0 cell-capacity 4\n0 spread-cells 3900 80\n0 current 2000\n30000 current 0\n"},
    // State of charge (the EVM packs: 2.5 Ah): full at rest, so the first scans set 100 % from the
    // open-circuit table, then 1C with the cells at 3.70 V under load (no full, empty or rest correction):
    // the count alone moves it, 1 % every 36 s. Run with --duration 3600000 for the whole hour.
    {"soc-discharge",
     "full at rest (4.19 V per cell), then 1C (2.5 A) from 2 s: the state of charge counts down",
     "0 all-cells 4190\n0 current 0\n2000 all-cells 3700\n2000 current -2500\n"},
    // A charge from the pack's 50 % rest voltage: the open-circuit table sets 50 % at the first scans, then
    // 0.5C counts up 1 % every 72 s.
    {"soc-charge", "at rest at 3.74 V per cell (50 %), then charging at 0.5C (1.25 A) from 2 s",
     "0 all-cells 3740\n0 current 0\n2000 current 1250\n"},
    // Pack storage (firmware/app/monitors/storage_mode.hpp): the StorageMode command at 1 s, then at rest
    // (the pack file's storage scan period, the device's SLEEP where allowed); a 2 A load at 31 s wakes the
    // device and the next storage scan ends storage. --duration 30000 stays in storage to the end (the
    // current figure, README "Figures").
    {"storage",
     "at rest: StorageMode enter at 1 s (the pack's storage scans, device SLEEP), a 2 A load at 31 s ends it",
     "1000 send StorageMode Mode=enter\n1000 expect-storage on\n31000 current -2000\n31000 expect-storage "
     "off\n"},
}};

// A token as the message quotes it: printable ASCII, at most 40 characters.
std::string quoted(std::string_view token) {
  std::string out = "'";
  for (size_t i = 0; i < token.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7F) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", c);
      out += hex;
    }
  }
  return out + (token.size() > 40 ? "...'" : "'");
}

template <class Table>
std::string namesOf(const Table& table) {
  std::string out;
  for (const auto& entry : table)
    out += std::string(out.empty() ? "" : ", ") + entry.name;
  return out;
}

std::string rangeText(ValueRange r) {
  return std::to_string(r.lo) + ".." + std::to_string(r.hi);
}

struct Token {
  std::string_view text;
  uint32_t column;  // from 1
};

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// The words of a line up to its comment.
std::vector<Token> tokens(std::string_view line) {
  std::vector<Token> out;
  size_t i = 0;
  while (i < line.size() && line[i] != '#') {
    if (isSpace(line[i])) {
      ++i;
      continue;
    }
    const size_t start = i;
    while (i < line.size() && !isSpace(line[i]) && line[i] != '#')
      ++i;
    out.push_back({line.substr(start, i - start), static_cast<uint32_t>(start + 1)});
  }
  return out;
}

// A whole token as a decimal integer with an optional sign, without going through floating point. An
// integer too large for 64 bits counts as out of range, not as malformed.
enum class Parsed { Ok, NotInteger, OutOfRange };
Parsed parseInteger(std::string_view text, ValueRange range, int32_t& out) {
  if (text.size() > 1 && text[0] == '+' && text[1] != '-') text.remove_prefix(1);
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (end != text.data() + text.size() || (ec != std::errc{} && ec != std::errc::result_out_of_range) ||
      text.empty()) {
    return Parsed::NotInteger;
  }
  if (ec == std::errc::result_out_of_range || v < range.lo || v > range.hi) return Parsed::OutOfRange;
  out = static_cast<int32_t>(v);
  return Parsed::Ok;
}

class Parser {
 public:
  Parser(const std::string& source, Diagnostics& diag) : source_(source), diag_(diag) {}

  std::optional<Scenario> parse(std::string_view text) {
    Scenario s;
    s.name = source_;
    uint32_t lineNo = 0;
    while (!text.empty()) {
      ++lineNo;
      const size_t eol = text.find('\n');
      const std::string_view line = text.substr(0, eol);
      text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
      const auto words = tokens(line);
      if (words.empty()) continue;
      Step st;
      st.line = lineNo;
      if (!parseStep(words, st)) return std::nullopt;
      s.steps.push_back(std::move(st));
    }
    sortByTime(s.steps);
    return s;
  }

 private:
  bool fail(uint32_t line, uint32_t column, const std::string& message) {
    diag_.error = source_ + ":" + std::to_string(line) + ":" + std::to_string(column) + ": error: " + message;
    return false;
  }

  bool number(const Step& st, const Token& t, const char* what, ValueRange range, int32_t& out) {
    switch (parseInteger(t.text, range, out)) {
      case Parsed::Ok:
        return true;
      case Parsed::NotInteger:
        return fail(st.line, t.column,
                    std::string("expected ") + what + " (an integer in " + rangeText(range) + "), got " +
                        quoted(t.text));
      case Parsed::OutOfRange:
        break;
    }
    return fail(st.line, t.column,
                std::string(what) + " must be in " + rangeText(range) + ", got " + quoted(t.text));
  }

  bool parseStep(const std::vector<Token>& words, Step& st) {
    int32_t time = 0;
    if (!number(st, words[0], "a time in ms", {0, static_cast<int32_t>(kMaxTimeMs)}, time)) return false;
    st.timeMs = static_cast<uint32_t>(time);
    if (words.size() < 2) return fail(st.line, words[0].column, "expected an action after the time");
    const Token& name = words[1];
    const auto* action = std::find_if(kActions.begin(), kActions.end(),
                                      [&](const ActionSpec& a) { return name.text == a.name; });
    if (action == kActions.end()) {
      return fail(st.line, name.column,
                  "unknown action " + quoted(name.text) + " (known: " + namesOf(kActions) + ")");
    }
    st.action = action->action;
    if (st.action == Action::Send || st.action == Action::Flood) return parseCommand(words, st);
    const size_t given = words.size() - 2;
    const bool optionalLimit = action->action == Action::Expect;
    if (given != action->count && !(optionalLimit && given == action->count + 1U)) {
      std::string usage;
      for (uint8_t i = 0; i < action->count; ++i)
        usage += std::string(" ") + spec(action->args[i]).name;
      if (optionalLimit) usage += " [<limit>]";
      return fail(st.line, name.column,
                  std::string("'") + action->name + "' takes" + (usage.empty() ? " no arguments" : usage) +
                      ", got " + std::to_string(given) + " argument(s)");
    }
    for (uint8_t i = 0; i < action->count; ++i) {
      if (!parseArg(action->args[i], words[2 + i], st)) return false;
    }
    if (given > action->count) return parseLimit(words.back(), st);
    return true;
  }

  // send <Message> [words], flood <ms> <Message> [words]: checked against the catalogue now
  // (scenario_command).
  bool parseCommand(const std::vector<Token>& words, Step& st) {
    size_t at = 2;
    if (st.action == Action::Flood) {
      if (words.size() < 3)
        return fail(st.line, words[1].column, "'flood' takes <ms> <Message> [<Signal>=<value> ...]");
      if (!number(st, words[2], "a flood duration in ms", {1, 600000}, st.value)) return false;
      at = 3;
    }
    if (words.size() <= at)
      return fail(st.line, words[1].column,
                  std::string("'") + (st.action == Action::Flood ? "flood" : "send") +
                      "' needs a message of the CAN catalogue");
    st.message = std::string(words[at].text);
    for (size_t i = at + 1; i < words.size(); ++i)
      st.words.emplace_back(words[i].text);
    size_t bad = 0;
    const std::string error = checkCommand(st.message, st.words, bad);
    if (error.empty()) return true;
    return fail(st.line, words[bad == 0 ? at : at + bad].column, error);
  }

  bool parseArg(Arg arg, const Token& t, Step& st) {
    const ArgSpec& sp = spec(arg);
    switch (arg) {
      case Arg::OnOff:
        if (t.text != "on" && t.text != "off")
          return fail(st.line, t.column, "expected on or off, got " + quoted(t.text));
        st.on = t.text == "on";
        return true;
      case Arg::Fault:
        return parseFault(t, st);
      case Arg::Board:
        st.boardColumn = t.column;
        return number(st, t, sp.what, sp.range, st.board);
      case Arg::Cell:
      case Arg::Tap:
      case Arg::Sensor:
        st.indexColumn = t.column;
        return number(st, t, sp.what, sp.range, st.index);
      case Arg::SpreadMv:
        return number(st, t, sp.what, sp.range, st.spread);
      default:
        return number(st, t, sp.what, sp.range, st.value);
    }
  }

  bool parseFault(const Token& t, Step& st) {
    const auto* f =
        std::find_if(kFaults.begin(), kFaults.end(), [&](const FaultSpec& fs) { return t.text == fs.name; });
    if (f == kFaults.end()) {
      return fail(st.line, t.column,
                  "unknown fault " + quoted(t.text) + " (known: " + namesOf(kFaults) + ")");
    }
    const auto seen = expected_.find(f->name);
    if (seen != expected_.end()) {
      return fail(st.line, t.column,
                  std::string("'") + f->name + "' is already expected on line " +
                      std::to_string(seen->second) + " (one expect per fault)");
    }
    expected_[f->name] = st.line;
    st.fault = f->name;
    st.watch = f->watch;
    return true;
  }

  bool parseLimit(const Token& t, Step& st) {
    if (st.watch == Watch::None) {
      return fail(
          st.line, t.column,
          "'" + st.fault +
              "' takes no limit (only cell_ov, cell_uv, occ, ocd, otc, otd, utc and utd watch a value)");
    }
    const ArgSpec& sp = spec(limitArg(st.watch));
    st.hasLimit = true;
    return number(st, t, sp.what, sp.range, st.value);
  }

  // Steps run in time order; same-time steps keep their file order. Each step written after a later one is
  // named, so the user sees what moved.
  void sortByTime(std::vector<Step>& steps) {
    uint32_t latest = 0, latestLine = 0;
    size_t moved = 0;
    for (const Step& st : steps) {
      if (st.timeMs < latest) {
        if (++moved <= 10) {
          diag_.warnings.push_back(source_ + ":" + std::to_string(st.line) + ":1: warning: the step at " +
                                   std::to_string(st.timeMs) + " ms is written after one at " +
                                   std::to_string(latest) + " ms (line " + std::to_string(latestLine) +
                                   "): steps run in time order, so it runs first");
        }
      } else {
        latest = st.timeMs, latestLine = st.line;
      }
    }
    if (moved > 10) {
      diag_.warnings.push_back(source_ + ": warning: " + std::to_string(moved - 10) +
                               " more steps are out of time order and run in time order");
    }
    std::stable_sort(steps.begin(), steps.end(),
                     [](const Step& a, const Step& b) { return a.timeMs < b.timeMs; });
  }

  const std::string& source_;
  Diagnostics& diag_;
  std::map<std::string, uint32_t> expected_;  // fault -> line of its expect
};

}  // namespace

std::vector<std::string> builtinNames() {
  std::vector<std::string> out;
  for (const auto& b : kBuiltins)
    out.emplace_back(b.name);
  return out;
}

std::string_view builtinText(const std::string& name) {
  for (const auto& b : kBuiltins) {
    if (name == b.name) return b.text;
  }
  return {};
}

std::optional<Scenario> builtinScenario(const std::string& name) {
  for (const auto& b : kBuiltins) {
    if (name != b.name) continue;
    Diagnostics diag;
    auto s = parseScenario(b.text, name, diag);  // the built-ins are checked by the tests
    if (s) s->description = b.description;
    return s;
  }
  return std::nullopt;
}

std::vector<std::string> expectableFaults() {
  std::vector<std::string> out;
  for (const auto& f : kFaults)
    out.emplace_back(f.name);
  return out;
}

std::optional<Scenario> parseScenario(std::string_view text, const std::string& source, Diagnostics& diag) {
  return Parser(source, diag).parse(text);
}

std::optional<Scenario> loadScenario(const std::string& path, Diagnostics& diag) {
  std::string text, error;
  switch (readInputFile(path, kMaxScenarioBytes, "scenario file", text, error)) {
    case InputError::None:
      break;
    case InputError::Missing:
      diag.unreadable = true;
      diag.error = path + ": error: no such file";
      return std::nullopt;
    case InputError::Unreadable:
      diag.error = path + ": error: " + error;
      return std::nullopt;
  }
  auto s = parseScenario(text, path, diag);
  if (s) s->description = "steps from " + path;
  return s;
}

bool checkScenario(const Scenario& scenario, const PackShape& shape, uint32_t durationMs, Diagnostics& diag) {
  auto where = [&](const Step& st, uint32_t column) {
    return scenario.name + ":" + std::to_string(st.line) + ":" + std::to_string(column);
  };
  for (const Step& st : scenario.steps) {
    const bool cellStep =
        st.action == Action::Cell || st.action == Action::RampCell || st.action == Action::OpenWire;
    const bool tempStep = st.action == Action::Temp || st.action == Action::RampTemp;
    if ((cellStep || tempStep) && st.board >= shape.boards) {
      diag.error = where(st, st.boardColumn) + ": error: board " + std::to_string(st.board) +
                   " does not exist: this image has boards 0.." + std::to_string(shape.boards - 1);
      return false;
    }
    // The sense wires: below each cell, and one above the top cell (open-wire <board> <cells + 1>).
    const int count = st.action == Action::OpenWire ? shape.cellsPerBoard + 1
                      : cellStep                    ? shape.cellsPerBoard
                                                    : shape.tempsPerBoard;
    if (st.action == Action::OpenWire && st.index > count) {
      diag.error = where(st, st.indexColumn) + ": error: sense wire " + std::to_string(st.index) +
                   " does not exist: this image has sense wires 1.." + std::to_string(count) +
                   " per board (n below cell n, " + std::to_string(count) + " above the top cell)";
      return false;
    }
    if ((cellStep || tempStep) && st.index > count) {
      diag.error = where(st, st.indexColumn) + ": error: " + (cellStep ? "cell " : "sensor ") +
                   std::to_string(st.index) + " does not exist: this image has " +
                   (cellStep ? "cells" : "sensors") + " 1.." + std::to_string(count) + " per board";
      return false;
    }
    if (st.timeMs > durationMs) {
      diag.warnings.push_back(where(st, 1) + ": warning: the step at " + std::to_string(st.timeMs) +
                              " ms comes after the end of the run (" + std::to_string(durationMs) +
                              " ms): it does not happen");
    }
    const bool currentStep =
        st.action == Action::Current ||
        (st.action == Action::Expect &&
         (st.watch == Watch::CurrentAbove || st.watch == Watch::CurrentBelow) && st.hasLimit);
    if (currentStep && !shape.hasCurrent) {
      diag.warnings.push_back(where(st, 1) +
                              ": warning: this image measures no current: the step does nothing");
    }
    const bool i2cStep =
        st.action == Action::Stretch || st.action == Action::StuckScl || st.action == Action::StuckSda;
    const char* missing = i2cStep && !shape.i2c                               ? "no I2C device"
                          : st.action == Action::UartNoise && !shape.uart     ? "no UART link to its monitor"
                          : st.action == Action::CanErrorFrames && !shape.can ? "no CAN bus"
                                                                              : nullptr;
    if (missing != nullptr) {
      diag.warnings.push_back(where(st, 1) + ": warning: this image has " + missing +
                              ": the step does nothing");
    }
  }
  return true;
}

}  // namespace bmssim
