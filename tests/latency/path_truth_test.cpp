// What an image reports about its paths (PackSummary ChargeFet/DischargeFet, bms-sim's summary and JSON: the
// PublishStatus behind them) is only ever true (issue 24 item 2): over every built-in scenario, run as
// bms-sim runs it (the image's binding, built with its option file), each millisecond the reported state is
// either unknown or one the hardware (ImageSim::paths(): the emulated monitor's FET drivers, or the fault
// output for both paths)
// was in at some instant of the last scan period and a half: a confirmation may lag what happened by the scan
// that read it back, but never claims what did not happen. A scenario that ends with the link healthy ends
// with the state known and equal to the hardware's.
// Output: REPORT path_truth.<image>.<scenario>.unknown_ms (how long nothing confirmed the paths).
#include <gtest/gtest.h>

#include <deque>
#include <memory>
#include <string>

#include "image_sim.hpp"
#include "scenario.hpp"
#include "scenario_player.hpp"

namespace {

using bmssim::ImageSim;

constexpr uint32_t kDurationMs = 8000;
constexpr uint32_t kLagMs = 150;  // one scan period and a half

std::unique_ptr<ImageSim> make(std::string& error) {
  bmssim::SimOptions options;
  options.image = BMS_SIM_IMAGE;
  for (const auto& e : bmssim::images()) {
    if (options.image == e.image) {
      options.devices = e.defaultDevices;
      return e.make(options, error);
    }
  }
  error = "no binding";
  return nullptr;
}

class PathTruth : public ::testing::TestWithParam<std::string> {};

TEST_P(PathTruth, TheReportedPathsAreOnesTheHardwareWasIn) {
  const std::string name = GetParam();
  const auto scenario = bmssim::builtinScenario(name);
  ASSERT_TRUE(scenario);
  std::string error;
  auto sim = make(error);
  ASSERT_TRUE(sim) << error;
  bmssim::Diagnostics diag;
  ASSERT_TRUE(bmssim::checkScenario(
      *scenario, {sim->boards(), sim->cellsPerBoard(), sim->tempsPerBoard(), sim->hasCurrent()}, kDurationMs,
      diag))
      << diag.error;
  bmssim::ScenarioPlayer player(*sim, *scenario);
  std::deque<bmssim::Paths> recent;  // the hardware's paths over the last kLagMs, one per millisecond
  uint32_t unknownMs = 0, claims = 0;
  for (uint32_t t = 0; t < kDurationMs; ++t) {
    player.advance(t);
    sim->runFor(fw::ms(1));
    sim->afterStep();
    const bmssim::Paths hw = sim->paths();
    recent.push_back(hw);
    if (recent.size() > kLagMs) recent.pop_front();
    const bmssim::SimFigures f = sim->figures();
    if (!f.pathsKnown) {
      ++unknownMs;
      continue;
    }
    ++claims;
    bool seen = false;
    for (const auto& p : recent)
      seen = seen || (p.charge == f.chargeOn && p.discharge == f.dischargeOn);
    ASSERT_TRUE(seen) << name << " at " << t << " ms: reported CHG " << f.chargeOn << " DSG " << f.dischargeOn
                      << ", the hardware CHG " << hw.charge << " DSG " << hw.discharge
                      << " throughout the last " << kLagMs << " ms";
  }
  EXPECT_GT(claims, 0u) << "the paths were never reported at all";
  const bmssim::SimFigures f = sim->figures();
  const bmssim::Paths hw = sim->paths();
  const bool linkHealthy = name != "comm-loss";
  if (linkHealthy) {
    ASSERT_TRUE(f.pathsKnown) << name << ": a healthy link ends with the paths confirmed";
    EXPECT_EQ(f.chargeOn, hw.charge) << name;
    EXPECT_EQ(f.dischargeOn, hw.discharge) << name;
  }
  std::printf("REPORT path_truth.%s.%s.unknown_ms=%u\n", BMS_SIM_IMAGE, name.c_str(), unknownMs);
}

INSTANTIATE_TEST_SUITE_P(EveryBuiltinScenario, PathTruth, ::testing::ValuesIn(bmssim::builtinNames()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

}  // namespace
