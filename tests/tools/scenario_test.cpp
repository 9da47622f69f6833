// bms-sim scenarios (issue 15): the parser rejects every value outside its range with file:line:col and the
// range, orders out-of-order steps with a warning, and implements the `expect` its header documents; the
// player moves the pack in whole units within the ranges and finds onsets from the values the image got;
// a protection event's latency is never negative.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "app/protection/protection.hpp"
#include "report.hpp"
#include "scenario.hpp"
#include "scenario_player.hpp"

namespace bmssim {
namespace {

std::string errorOf(const std::string& text) {
  Diagnostics diag;
  EXPECT_FALSE(parseScenario(text, "s.txt", diag).has_value()) << text;
  return diag.error;
}

Scenario parsed(const std::string& text, Diagnostics* out = nullptr) {
  Diagnostics diag;
  auto s = parseScenario(text, "s.txt", diag);
  EXPECT_TRUE(s.has_value()) << diag.error;
  if (out != nullptr) *out = diag;
  return s.value_or(Scenario{});
}

// Values that went through strtod: nan and inf reached an int conversion (UBSan abort), 70000 mV wrapped to
// 4464 in a 16-bit register, fractions were truncated.
TEST(ScenarioParser, RejectsNonIntegerNumbersWithPositionAndRange) {
  EXPECT_EQ(errorOf("0 all-cells nan\n"),
            "s.txt:1:13: error: expected a cell voltage in mV (an integer in 0..5000), got 'nan'");
  EXPECT_EQ(errorOf("0 all-cells inf"),
            "s.txt:1:13: error: expected a cell voltage in mV (an integer in 0..5000), got 'inf'");
  EXPECT_EQ(errorOf("0 all-cells 1e308"),
            "s.txt:1:13: error: expected a cell voltage in mV (an integer in 0..5000), got '1e308'");
  EXPECT_EQ(errorOf("0 cell 0 1 4200.5"),
            "s.txt:1:12: error: expected a cell voltage in mV (an integer in 0..5000), got '4200.5'");
  EXPECT_EQ(errorOf("0 current 0x10"),
            "s.txt:1:11: error: expected a current in mA (an integer in -32768..32767), got '0x10'");
  EXPECT_EQ(errorOf("0 ramp-cell 0 1 +-5"),
            "s.txt:1:17: error: expected a cell drift in mV/s (an integer in -5000..5000), got '+-5'");
}

TEST(ScenarioParser, RejectsValuesOutsideTheirPhysicalRange) {
  EXPECT_EQ(errorOf("0 all-cells 70000"),
            "s.txt:1:13: error: a cell voltage in mV must be in 0..5000, got '70000'");
  EXPECT_EQ(errorOf("0 all-cells -1"),
            "s.txt:1:13: error: a cell voltage in mV must be in 0..5000, got '-1'");
  EXPECT_EQ(errorOf("0 current -40000"),
            "s.txt:1:11: error: a current in mA must be in -32768..32767, got '-40000'");
  EXPECT_EQ(errorOf("0 temp 0 1 5000"),
            "s.txt:1:12: error: a temperature in 0.1 K must be in 2182..4232, got '5000'");
  EXPECT_EQ(errorOf("0 ramp-temp 0 1 -3000"),
            "s.txt:1:17: error: a temperature drift in 0.1 K/s must be in -2050..2050, got '-3000'");
  EXPECT_EQ(errorOf("0 ramp-all 99999999999999999999999"),
            "s.txt:1:12: error: a cell drift in mV/s must be in -5000..5000, got '99999999999999999999999'");
  EXPECT_EQ(errorOf("0 cell 64 1 3700"), "s.txt:1:8: error: a board number must be in 0..63, got '64'");
  EXPECT_EQ(errorOf("0 cell 0 0 3700"), "s.txt:1:10: error: a cell number must be in 1..16, got '0'");
  EXPECT_EQ(errorOf("0 open-wire 0 18"), "s.txt:1:15: error: a sense wire number must be in 1..17, got '18'");
  EXPECT_EQ(errorOf("0 temp 0 4 3000"), "s.txt:1:10: error: a sensor number must be in 1..3, got '4'");
}

// strtoul read "-5" as 2^64 - 5 and 4294968296 fired at 1 s once cast to 32 bits.
TEST(ScenarioParser, RejectsNegativeHugeAndMalformedTimes) {
  EXPECT_EQ(errorOf("-5 bus-off"), "s.txt:1:1: error: a time in ms must be in 0..3600000, got '-5'");
  EXPECT_EQ(errorOf("4294968296 bus-off"),
            "s.txt:1:1: error: a time in ms must be in 0..3600000, got '4294968296'");
  EXPECT_EQ(errorOf("3600001 bus-off"),
            "s.txt:1:1: error: a time in ms must be in 0..3600000, got '3600001'");
  EXPECT_EQ(errorOf("\n  # comment\n\t1.5 bus-off"),
            "s.txt:3:2: error: expected a time in ms (an integer in 0..3600000), got '1.5'");
  EXPECT_EQ(parsed("3600000 bus-off").steps.at(0).timeMs, 3600000U);
}

TEST(ScenarioParser, NamesTheArgumentsAnActionTakes) {
  EXPECT_EQ(errorOf("0 cell 0 2"), "s.txt:1:3: error: 'cell' takes <board> <cell> <mV>, got 2 argument(s)");
  EXPECT_EQ(errorOf("0 bus-off now"), "s.txt:1:3: error: 'bus-off' takes no arguments, got 1 argument(s)");
  EXPECT_EQ(errorOf("0 comm-loss maybe"), "s.txt:1:13: error: expected on or off, got 'maybe'");
  EXPECT_EQ(errorOf("0"), "s.txt:1:1: error: expected an action after the time");
  EXPECT_EQ(errorOf("0 expect"), "s.txt:1:3: error: 'expect' takes <fault>|any [<limit>], got 0 argument(s)");
  EXPECT_NE(errorOf("0 fly").find("s.txt:1:3: error: unknown action 'fly' (known: current, cell,"),
            std::string::npos);
}

TEST(ScenarioParser, QuotesUnprintableAndLongTokensSafely) {
  EXPECT_EQ(
      errorOf(std::string("0 all-cells 4\x01\xff", 16)),
      "s.txt:1:13: error: expected a cell voltage in mV (an integer in 0..5000), got '4\\x01\\xFF\\x00'");
  const std::string longToken(100000, '9');
  EXPECT_EQ(
      errorOf("0 all-cells " + longToken),
      "s.txt:1:13: error: a cell voltage in mV must be in 0..5000, got '" + std::string(40, '9') + "...'");
}

TEST(ScenarioParser, AcceptsCommentsCrLfAndSigns) {
  const Scenario s = parsed("# header\r\n0 current +5000 # charge\r\n\r\n10\tramp-all\t-20\r\n");
  ASSERT_EQ(s.steps.size(), 2U);
  EXPECT_EQ(s.steps[0].action, Action::Current);
  EXPECT_EQ(s.steps[0].value, 5000);
  EXPECT_EQ(s.steps[1].action, Action::RampAll);
  EXPECT_EQ(s.steps[1].value, -20);
  EXPECT_EQ(s.steps[1].line, 4U);
}

// Out-of-order steps used to block every later one until their time came.
TEST(ScenarioParser, SortsOutOfOrderStepsAndSaysWhichMoved) {
  Diagnostics diag;
  const Scenario s =
      parsed("3000 comm-loss on\n1000 all-cells 4300\n3000 bus-off\n2000 intermittent on\n", &diag);
  ASSERT_EQ(s.steps.size(), 4U);
  EXPECT_EQ(s.steps[0].line, 2U);
  EXPECT_EQ(s.steps[1].line, 4U);
  EXPECT_EQ(s.steps[2].line, 1U);  // same time: file order
  EXPECT_EQ(s.steps[3].line, 3U);
  ASSERT_EQ(diag.warnings.size(), 2U);
  EXPECT_EQ(
      diag.warnings[0],
      "s.txt:2:1: warning: the step at 1000 ms is written after one at 3000 ms (line 1): steps run in time "
      "order, so it runs first");
  EXPECT_EQ(
      diag.warnings[1],
      "s.txt:4:1: warning: the step at 2000 ms is written after one at 3000 ms (line 3): steps run in time "
      "order, so it runs first");
}

// scenario.hpp documented `expect`, the parser rejected it and accepted an undocumented `onset` instead.
TEST(ScenarioParser, ExpectIsWhatTheHeaderDocuments) {
  const Scenario s =
      parsed("100 expect comm_loss\n200 expect cell_ov 4250\n300 expect ocd -30000\n0 expect any\n");
  ASSERT_EQ(s.steps.size(), 4U);
  EXPECT_EQ(s.steps[0].fault, "any");
  EXPECT_FALSE(s.steps[0].hasLimit);
  EXPECT_EQ(s.steps[1].fault, "comm_loss");
  EXPECT_EQ(s.steps[2].watch, Watch::CellAbove);
  EXPECT_EQ(s.steps[2].value, 4250);
  EXPECT_EQ(s.steps[3].watch, Watch::CurrentBelow);
  EXPECT_EQ(s.steps[3].value, -30000);
  EXPECT_NE(errorOf("0 onset").find("unknown action 'onset'"), std::string::npos);
  EXPECT_NE(errorOf("0 expect fire").find("s.txt:1:10: error: unknown fault 'fire' (known: cell_ov,"),
            std::string::npos);
  EXPECT_EQ(errorOf("0 expect otd 3332\n5 expect otd"),
            "s.txt:2:10: error: 'otd' is already expected on line 1 (one expect per fault)");
  EXPECT_EQ(errorOf("0 expect any 5"),
            "s.txt:1:14: error: 'any' takes no limit (only cell_ov, cell_uv, occ, ocd, otc, otd, utc and utd "
            "watch a "
            "value)");
  EXPECT_EQ(errorOf("0 expect utd 100"),
            "s.txt:1:14: error: a temperature in 0.1 K must be in 2182..4232, got '100'");
}

TEST(ScenarioParser, ExpectableFaultsAreTheFirmwaresFaultNames) {
  const auto names = expectableFaults();
  ASSERT_EQ(names.size(), fw::app::kFaultCount + 1U);
  for (uint8_t i = 0; i < fw::app::kFaultCount; ++i)
    EXPECT_EQ(names[i], fw::app::faultName(static_cast<fw::app::FaultId>(i)));
  EXPECT_EQ(names.back(), "any");
}

TEST(ScenarioParser, EveryBuiltinIsValidScenarioText) {
  for (const auto& name : builtinNames()) {
    Diagnostics diag;
    const auto s = parseScenario(builtinText(name), name, diag);
    ASSERT_TRUE(s.has_value()) << name << ": " << diag.error;
    EXPECT_TRUE(diag.warnings.empty()) << name;
    ASSERT_TRUE(builtinScenario(name).has_value()) << name;
    EXPECT_FALSE(builtinScenario(name)->description.empty()) << name;
    // The smallest image (BQ4050: one board, four cells, one sensor) runs every built-in.
    EXPECT_TRUE(checkScenario(*s, {1, 4, 1, true}, 10000, diag)) << name << ": " << diag.error;
  }
  EXPECT_FALSE(builtinScenario("no-such").has_value());
}

TEST(ScenarioCheck, ImageDependentIndicesGiveFileLineAndColumn) {
  const Scenario s = parsed("0 cell 0 2 3900\n100 cell 2 1 3900\n");
  Diagnostics diag;
  EXPECT_FALSE(checkScenario(s, {2, 16, 2, false}, 1000, diag));
  EXPECT_EQ(diag.error, "s.txt:2:10: error: board 2 does not exist: this image has boards 0..1");
  diag = {};
  // The sense wires of a 4-cell board: 1..4 below each cell, 5 above the top cell (its top tap).
  EXPECT_TRUE(checkScenario(parsed("0 open-wire 0 5"), {1, 4, 1, true}, 1000, diag)) << diag.error;
  EXPECT_FALSE(checkScenario(parsed("0 open-wire 0 6"), {1, 4, 1, true}, 1000, diag));
  EXPECT_EQ(
      diag.error,
      "s.txt:1:15: error: sense wire 6 does not exist: this image has sense wires 1..5 per board (n below "
      "cell n, 5 above the top cell)");
  diag = {};
  EXPECT_FALSE(checkScenario(parsed("0 ramp-temp 0 2 10"), {1, 4, 1, true}, 1000, diag));
  EXPECT_EQ(diag.error, "s.txt:1:15: error: sensor 2 does not exist: this image has sensors 1..1 per board");
}

TEST(ScenarioCheck, WarnsAboutStepsTheRunDoesNotReachOrTheImageIgnores) {
  Diagnostics diag;
  EXPECT_TRUE(checkScenario(parsed("0 current 1000\n5000 bus-off\n"), {2, 16, 2, false}, 2000, diag));
  ASSERT_EQ(diag.warnings.size(), 2U);
  EXPECT_EQ(diag.warnings[0], "s.txt:1:1: warning: this image measures no current: the step does nothing");
  EXPECT_EQ(
      diag.warnings[1],
      "s.txt:2:1: warning: the step at 5000 ms comes after the end of the run (2000 ms): it does not happen");
}

// An image that records what the player pushed to it.
class RecordingSim final : public ImageSim {
 public:
  int boards() const override { return 2; }
  int cellsPerBoard() const override { return 4; }
  int tempsPerBoard() const override { return 2; }
  bool hasCurrent() const override { return true; }
  void setCellMv(int board, int cell, int mv) override {
    ++cellPushes;
    cell_[board][cell] = mv;
  }
  void setCurrentMa(int ma) override { currentMa = ma; }
  Paths paths() const override { return open; }
  void setTempDeciK(int board, int sensor, int deciK) override { temp_[board][sensor] = deciK; }
  void setCommLost(bool lost) override { commLost = lost; }
  void openWire(int, int) override {}
  void setIntermittent(bool) override {}
  bool busOff() override { return false; }
  bsp::host::Harness& harness() override { return harness_; }
  SimFigures figures() override { return {}; }
  std::vector<fw::app::ProtectionRecord> protectionLog() const override { return {}; }
  std::vector<SentFrame> frames() const override { return {}; }
  void setCellCapacityMah(int mah) override { capacityMah = mah; }
  int cellSpreadMv() override { return 0; }  // the player never reads it (the report does)

  int cell(int b, int c) const { return cell_[b][c]; }
  int temp(int b, int s) const { return temp_[b][s]; }
  int currentMa = 0, cellPushes = 0, capacityMah = 0;
  bool commLost = false;
  Paths open;  // the emulated device's paths (both closed unless a test opens one)

 private:
  bsp::host::Harness harness_;
  int cell_[2][5] = {};
  int temp_[2][3] = {};
};

void playTo(ScenarioPlayer& p, uint32_t fromMs, uint32_t toMs) {
  for (uint32_t t = fromMs; t <= toMs; ++t)
    p.advance(t);
}

// The ov-cell built-in: its onset is the first millisecond the image was given 4250 mV, not earlier (the old
// loop compared the unrounded drift with the limit while the image already had the rounded-up value).
TEST(ScenarioPlayer, OnsetIsTheFirstMillisecondTheImageHasTheLimit) {
  RecordingSim sim;
  const Scenario s = *builtinScenario("ov-cell");
  ScenarioPlayer p(sim, s);
  playTo(p, 0, 2249);
  EXPECT_EQ(sim.cell(0, 2), 4249);
  EXPECT_TRUE(p.onsets().empty());
  p.advance(2250);
  EXPECT_EQ(sim.cell(0, 2), 4250);
  ASSERT_EQ(p.onsets().count("cell_ov"), 1U);
  EXPECT_EQ(p.onsets().at("cell_ov"), 2250U);
  EXPECT_EQ(sim.currentMa, 5000);
}

// The imbalance built-in (issue 28): the capacity reaches the emulated cells, cell 1 of each board is at the
// base and the others 1..4 quarters of the spread above it (a 20..80 mV spread on every board), a drift
// started before is stopped, and the charge ends at 30 s.
TEST(ScenarioPlayer, ImbalanceSpreadsEveryBoardsCells) {
  RecordingSim sim;
  const Scenario s = *builtinScenario("imbalance");
  ScenarioPlayer p(sim, s);
  p.advance(0);
  EXPECT_EQ(sim.capacityMah, 4);
  EXPECT_EQ(sim.currentMa, 2000);
  for (int b = 0; b < 2; ++b) {
    EXPECT_EQ(sim.cell(b, 1), 3900) << b;
    int lo = 5000, hi = 0;
    for (int c = 2; c <= 4; ++c) {
      lo = std::min(lo, sim.cell(b, c));
      hi = std::max(hi, sim.cell(b, c));
    }
    EXPECT_GE(lo, 3920) << b;
    EXPECT_EQ(hi, 3980) << b;
  }
  playTo(p, 1, 30000);
  EXPECT_EQ(sim.currentMa, 0);
  EXPECT_EQ(sim.cell(0, 1), 3900);  // nothing moves the cells but the image's balancing

  EXPECT_EQ(errorOf("0 spread-cells 3900 501\n"),
            "s.txt:1:21: error: a spread in mV must be in 0..500, got '501'");
  EXPECT_EQ(errorOf("0 cell-capacity 0\n"),
            "s.txt:1:17: error: a cell capacity in mAh must be in 1..100000, got '0'");
}

// A value set on a drifting cell used to be overwritten by the drift the next millisecond.
TEST(ScenarioPlayer, ASetValueReplacesTheDrift) {
  RecordingSim sim;
  const Scenario s =
      parsed("0 ramp-cell 0 1 100\n1000 cell 0 1 3000\n1000 ramp-temp 1 2 10\n2000 temp 1 2 2500\n");
  ScenarioPlayer p(sim, s);
  playTo(p, 0, 999);
  EXPECT_EQ(sim.cell(0, 1), 3799);
  playTo(p, 1000, 3000);
  EXPECT_EQ(sim.cell(0, 1), 3000);
  EXPECT_EQ(p.cellMv(0, 1), 3000);
  EXPECT_EQ(sim.temp(1, 2), 2500);
}

// A drift used to run on forever: 20 mV/s for an hour is 75.7 V, which wrapped in the 16-bit registers.
TEST(ScenarioPlayer, DriftsStopAtTheRangeEnds) {
  RecordingSim sim;
  const Scenario s = parsed("0 ramp-all 5000\n0 ramp-temp 0 1 -2050\n");
  ScenarioPlayer p(sim, s);
  playTo(p, 0, 3000);
  EXPECT_EQ(sim.cell(1, 4), kCellMvRange.hi);
  EXPECT_EQ(sim.temp(0, 1), kTempDeciKRange.lo);
  const int pushes = sim.cellPushes;
  playTo(p, 3001, 3100);
  EXPECT_EQ(sim.cellPushes, pushes) << "an unchanged value is not pushed again";
}

TEST(ScenarioPlayer, NewDriftReplacesTheOldAndZeroStopsIt) {
  RecordingSim sim;
  const Scenario s = parsed("0 ramp-cell 0 1 100\n1000 ramp-cell 0 1 -100\n2000 ramp-cell 0 1 0\n");
  ScenarioPlayer p(sim, s);
  playTo(p, 0, 1500);
  EXPECT_EQ(sim.cell(0, 1), 3799 - 50);  // from the value the image had at 999 ms
  playTo(p, 1501, 3000);
  EXPECT_EQ(sim.cell(0, 1), 3799 - 99);  // stopped where it was at 1999 ms
}

TEST(ScenarioPlayer, OnsetsOfStepsAndOfLimitsAlreadyReached) {
  RecordingSim sim;
  const Scenario s = parsed(
      "0 all-cells 2600\n500 expect cell_uv 2700\n700 comm-loss on\n700 expect any\n900 expect ocd -100\n");
  ScenarioPlayer p(sim, s);
  playTo(p, 0, 1000);
  EXPECT_EQ(p.onsets().at("cell_uv"), 500U);
  EXPECT_EQ(p.onsets().at("any"), 700U);
  EXPECT_EQ(p.onsets().count("ocd"), 0U);
  EXPECT_TRUE(sim.commLost);
  EXPECT_TRUE(p.busOffUnsupported() == false);
}

fw::app::ProtectionRecord event(fw::app::FaultId f, uint32_t detectedUs, bool done, uint32_t actedUs) {
  fw::app::ProtectionRecord r{};
  r.fault = f, r.detected = fw::Instant{detectedUs}, r.actionDone = done, r.acted = fw::Instant{actedUs};
  return r;
}

// --devices 64 ov-cell printed "stale_data onset 2250 ms, detected 400 ms, latency -1850 ms": the chain's
// bring-up raised stale data long before the cell drifted, and every event was measured from the one onset.
TEST(EventLatency, NeverNegative) {
  using fw::app::FaultId;
  const Onsets ovOnly{{"cell_ov", 2250}};
  const auto stale = event(FaultId::StaleData, 400000, true, 400000);
  EXPECT_EQ(latencyOf(stale, ovOnly).note, std::string("no expected onset"));
  EXPECT_FALSE(latencyOf(stale, ovOnly).latencyUs.has_value());
  const Onsets any{{"any", 2250}};
  const EventLatency before = latencyOf(stale, any);
  EXPECT_EQ(before.note, std::string("fault before onset"));
  EXPECT_EQ(before.onsetUs, 2250000U);
  EXPECT_FALSE(before.latencyUs.has_value());
  const EventLatency ov = latencyOf(event(FaultId::CellOvervoltage, 2351432, true, 2351432), ovOnly);
  EXPECT_EQ(ov.latencyUs, 101432U);
  EXPECT_EQ(ov.note, nullptr);
  EXPECT_EQ(latencyOf(event(FaultId::CellOvervoltage, 2300000, false, 0), ovOnly).note,
            std::string("action pending"));
  // The fault's own expect wins over `any`.
  const Onsets both{{"any", 1000}, {"comm_loss", 2000}};
  EXPECT_EQ(latencyOf(event(FaultId::CommLoss, 2200000, true, 2200000), both).latencyUs, 200000U);
}

// The simulated current kept flowing with the discharge FET off: the load and the charger now stop while the
// device has their path open, and start again when it closes; occ / ocd onsets follow the current that flows.
TEST(ScenarioPlayer, TheLoadAndTheChargerStopWhileTheirPathIsOpen) {
  RecordingSim sim;
  const Scenario s = parsed("0 current -15000\n0 expect ocd -10000\n2000 current 8000\n");
  ScenarioPlayer p(sim, s);
  sim.open.discharge = false;  // the DSG FET is off from the start
  playTo(p, 0, 999);
  EXPECT_EQ(sim.currentMa, 0) << "the load draws nothing through an open discharge path";
  EXPECT_EQ(p.demandMa(), -15000);
  EXPECT_EQ(p.onsets().count("ocd"), 0U) << "no discharge current flows, so no over-current onset";
  sim.open.discharge = true;
  p.advance(1000);
  EXPECT_EQ(sim.currentMa, -15000);
  EXPECT_EQ(p.onsets().at("ocd"), 1000U);
  sim.open.discharge = false;  // protection opens it again
  p.advance(1001);
  EXPECT_EQ(sim.currentMa, 0);
  EXPECT_EQ(p.flowingMa(), 0);
  playTo(p, 1002, 2000);
  EXPECT_EQ(sim.currentMa, 8000) << "a charger is not blocked by the open discharge path";
  sim.open.charge = false;
  p.advance(2001);
  EXPECT_EQ(sim.currentMa, 0);
}

// An expect that never happened passed silently (no "missed", exit 0): each is judged now.
TEST(ExpectVerdicts, MetOnlyByAnEventOfItsFaultAtOrAfterTheOnset) {
  using fw::app::FaultId;
  const Scenario s = parsed(
      "1000 expect cell_ov 4250\n1000 expect comm_loss\n1000 expect ocd -30000\n2000 expect any\n"
      "9000 expect otd\n");
  const Onsets onsets{{"cell_ov", 2250}, {"comm_loss", 1000}, {"any", 2000}};
  const std::vector<fw::app::ProtectionRecord> log = {
      event(FaultId::CommLoss, 900000, true, 900000),
      event(FaultId::CellOvervoltage, 2302000, true, 2302500)};
  const auto v = judgeExpects(s, onsets, log, 5000);
  ASSERT_EQ(v.size(), 5U);
  EXPECT_EQ(v[0].missed, "");
  EXPECT_EQ(v[0].event->detected.us, 2302000U);
  EXPECT_EQ(v[1].missed,
            "no comm_loss event at or after the onset (one was detected before it, at 900.000 ms)");
  EXPECT_EQ(v[2].missed, "the pack never reached -30000 mA");
  EXPECT_EQ(v[3].missed, "") << "any fault meets `any`";
  EXPECT_EQ(v[4].missed, "the run ended (5000 ms) before the step at 9000 ms");
}

}  // namespace
}  // namespace bmssim
