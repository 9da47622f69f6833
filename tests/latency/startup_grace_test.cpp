// The first bring-up against its bound (issue 24 item 5). Each image's monitor states how long its first
// bring-up and first scan may take from power-up (Device::firstDataBound(): BQ79616 120 ms + 15 ms per
// device, BQ769x two scan periods, BQ4050 one). While it runs within that bound, stale_data and comm_loss
// stay quiet; past it, a pack never measured is a fault. Before, a chain of 21 or more BQ79616 devices
// tripped stale_data at every power-up (its bring-up outlasted the 300 ms stale limit: 933 ms for 64
// devices). Output: REPORT startup.<image>[.<devices>dev] with the first valid data and the fault time when
// it overruns.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/protection/default_limits.hpp"
#include "app/protection/protection.hpp"
#include "image_sim.hpp"

namespace {

using fw::app::FaultId;

struct Config {
  int devices;
  uint32_t boundMs;  // the image's documented bound for this configuration
};

std::string keyOf(const Config& c) {
  std::string key = BMS_SIM_IMAGE;
  if (key == "lp-mspm0g3507-bq79616") key += "." + std::to_string(c.devices) + "dev";
  return key;
}

std::unique_ptr<bmssim::ImageSim> make(const Config& c) {
  bmssim::SimOptions options;
  options.image = BMS_SIM_IMAGE;
  options.devices = c.devices;
  std::string error;
  for (const auto& e : bmssim::images()) {
    if (options.image == e.image) return e.make(options, error);
  }
  return nullptr;
}

class StartupGrace : public ::testing::TestWithParam<Config> {};

// A healthy pack: the first valid data within the bound, and no fault at all, from power-up on.
TEST_P(StartupGrace, NoFaultWhileTheFirstBringUpRunsWithinItsBound) {
  const Config c = GetParam();
  auto sim = make(c);
  ASSERT_TRUE(sim);
  uint32_t firstValid = 0;
  for (uint32_t t = 1; t <= c.boundMs + 1000; ++t) {
    sim->runFor(fw::ms(1));
    sim->afterStep();
    const auto f = sim->figures();
    ASSERT_EQ(f.activeFaults, 0) << "at " << t << " ms, bound " << c.boundMs << " ms";
    if (firstValid == 0 && f.validBoards == f.boards) firstValid = t;
  }
  ASSERT_NE(firstValid, 0u);
  EXPECT_LE(firstValid, c.boundMs);
  std::printf("REPORT startup.%s.first_valid_ms=%u (bound %u ms; no fault from power-up)\n", keyOf(c).c_str(),
              firstValid, c.boundMs);
}

// A monitor that never answers: no stale_data or comm_loss before the bound (nor before the stale limit),
// and a fault within one scan period past the later of the two, plus the bring-up step under way then (a
// failed period is reported when the monitor's current step ends: 7 ms for 2 BQ79616 devices).
TEST_P(StartupGrace, AFirstBringUpThatOverrunsItsBoundIsAFault) {
  const Config c = GetParam();
  auto sim = make(c);
  ASSERT_TRUE(sim);
  sim->setCommLost(true);
  constexpr uint16_t kFresh = fw::app::bit(FaultId::StaleData) | fw::app::bit(FaultId::CommLoss);
  const uint32_t staleMs = fw::app::kDefaultLimits.staleAfter.us / 1000;
  const uint32_t quietUntil = std::max(c.boundMs, staleMs);
  uint32_t fault = 0;
  for (uint32_t t = 1; t <= quietUntil + 200 && fault == 0; ++t) {
    sim->runFor(fw::ms(1));
    sim->afterStep();
    if ((sim->figures().activeFaults & kFresh) != 0) fault = t;
  }
  ASSERT_NE(fault, 0u) << "no fault " << quietUntil + 200 << " ms after power-up";
  EXPECT_GE(fault, quietUntil) << "a fault while the first bring-up was within its bound";
  EXPECT_LE(fault, quietUntil + 100 + 20);
  std::printf("REPORT startup.%s.overrun_fault_ms=%u (bound %u ms, stale limit %u ms)\n", keyOf(c).c_str(),
              fault, c.boundMs, staleMs);
}

// This executable's image: the BQ79616 chain at 1, 2, 16, 21 (the shortest that overran the stale limit) and
// 64 devices; the others with their one device.
std::vector<Config> configs() {
  const std::string image = BMS_SIM_IMAGE;
  if (image == "lp-mspm0g3507-bq4050") return {Config{1, 100}};
  if (image != "lp-mspm0g3507-bq79616") return {Config{1, 200}};  // the BQ769x images: two scan periods
  std::vector<Config> out;
  for (int n : {1, 2, 16, 21, 64})
    out.push_back(Config{n, 120 + 15 * static_cast<uint32_t>(n)});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Images, StartupGrace, ::testing::ValuesIn(configs()),
                         [](const ::testing::TestParamInfo<Config>& info) {
                           std::string name = keyOf(info.param);
                           for (char& ch : name) {
                             if (ch == '-' || ch == '.') ch = '_';
                           }
                           return name;
                         });

}  // namespace
