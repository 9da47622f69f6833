// Worst-case cell over-voltage latency of an image, built with its option file: the onset swept across the
// whole scan period (tests/latency/CMakeLists.txt builds one executable per image).
//
// One onset in mid-period (the ov-cell scenario) says little: the latency depends on where in the scan period
// the cell crosses its limit relative to the instant the scan reads it. Each configuration runs the image as
// bms-sim does (its binding in bsp/host/tools/bms-sim on the host BSP, with its emulated devices) and, for
// onsets at every 1 ms of the 100 ms period, steps cell 1 of board 0 from 3.7 V to just over the firmware's
// 4.25 V limit (below the devices' own thresholds, so the firmware path is what is measured), and takes the
// time from the onset to the FETs off (the FET command complete) or the fault output asserted, from the
// protection log. Wherever the latency jumps between two neighbouring onsets (the onset moved past the
// instant the scan reads the cell), the jump is bisected down to 10 us, so the worst onset is found to within
// 10 us. Then the cell returns to 3.7 V and the next trial waits until the fault has cleared.
//
// Budget (README "Figures"): worst case <= scan period + the image's scan time + 2 ms, where the scan time is
// measured here: the longest time from a scan's start (its period tick) to the evaluation of its data (the
// protection log's `detected` of the trips). The scan's bus time (bms-sim's scan_bus_us) is printed beside
// it: a scan also waits between its transactions.
// Output: REPORT latency.<image>[.<devices>dev].ov_worst_ms and the budget, for ./ci/test's figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/protection/protection.hpp"
#include "image_sim.hpp"

namespace {

using bmssim::ImageSim;

constexpr uint64_t kPeriodUs = 100000;
constexpr int kTripMv = 4260;  // just over the 4 250 mV limit (default_limits.hpp)
constexpr int kRestMv = 3700;
constexpr uint64_t kGridUs = 1000;
constexpr uint64_t kResolutionUs = 10;

struct Config {
  const char* image;
  int devices;
};

std::string keyOf(const Config& c) {
  std::string key = c.image;
  if (std::string(c.image) == "lp-mspm0g3507-bq79616") key += "." + std::to_string(c.devices) + "dev";
  return key;
}

// One image under test, re-created when its protection log (which does not wrap) runs short of room.
class Rig {
 public:
  explicit Rig(const Config& c) : config_(c) { create(); }

  // Latency in us from an onset `phaseUs` into a scan period (at least one period from now) to the action.
  uint64_t trial(uint64_t phaseUs) {
    if (sim_->protectionLog().size() + 2 > fw::app::ProtectionTask::kLogSize) create();
    auto& h = sim_->harness();
    const uint64_t onset = (h.nowUs() / kPeriodUs + 1) * kPeriodUs + phaseUs;
    run(fw::us(static_cast<uint32_t>(onset - h.nowUs())));
    const size_t before = sim_->protectionLog().size();
    sim_->setCellMv(0, 1, kTripMv);
    uint64_t latency = UINT64_MAX;
    size_t record = 0;
    for (int ms = 0; ms < 400 && latency == UINT64_MAX; ++ms) {
      run(fw::ms(1));
      const auto log = sim_->protectionLog();
      for (size_t i = before; i < log.size(); ++i) {
        if (log[i].fault == fw::app::FaultId::CellOvervoltage && log[i].actionDone) {
          latency = log[i].acted.us - static_cast<uint32_t>(onset);
          record = i;
          // Detected on a scan's data: the scan started at its period's tick and ended here.
          scanUs_ = std::max<uint64_t>(scanUs_, log[i].detected.us % kPeriodUs);
        }
      }
    }
    sim_->setCellMv(0, 1, kRestMv);
    if (latency == UINT64_MAX) return latency;
    // Back to normal: the fault cleared and the paths are on again before the next trial.
    for (int ms = 0; ms < 400 && !sim_->protectionLog()[record].cleared; ++ms)
      run(fw::ms(1));
    run(fw::ms(10));
    return latency;
  }

  double scanBusUs() { return sim_->figures().scanBusUs; }
  // The longest time from a scan's start (its period tick) to the evaluation of its data, over the trials.
  uint64_t scanUs() const { return scanUs_; }
  // Runs the image for `d`, then lets the binding do its per-step bookkeeping (the scan meter), as bms-sim
  // does every millisecond.
  void run(fw::Duration d) {
    sim_->harness().runFor(d);
    sim_->afterStep();
  }
  uint32_t scanPeriodMs() { return sim_->figures().scanPeriodMs; }

 private:
  void create() {
    sim_.reset();  // one harness at a time
    bmssim::SimOptions options;
    options.image = config_.image;
    options.devices = config_.devices;
    std::string error;
    for (const auto& e : bmssim::images()) {
      if (options.image == e.image) sim_ = e.make(options, error);
    }
    ASSERT_TRUE(sim_) << config_.image << ": " << error;
    // Bring-up (a 64-device chain takes 0.9 s) and a few scans.
    for (int ms = 0; ms < 1500; ++ms)
      run(fw::ms(1));
  }

  Config config_;
  std::unique_ptr<ImageSim> sim_;
  uint64_t scanUs_ = 0;
};

class LatencySweep : public ::testing::TestWithParam<Config> {};

TEST_P(LatencySweep, WorstOnsetToActionWithinBudget) {
  const Config c = GetParam();
  Rig rig(c);
  uint64_t latency[kPeriodUs / kGridUs];
  uint64_t worst = 0, worstPhase = 0;
  auto note = [&](uint64_t phase, uint64_t l) {
    if (l > worst) worst = l, worstPhase = phase;
  };
  for (uint64_t i = 0; i < kPeriodUs / kGridUs; ++i) {
    latency[i] = rig.trial(i * kGridUs);
    ASSERT_NE(latency[i], UINT64_MAX) << "no action for an onset at " << i << " ms into the period";
    note(i * kGridUs, latency[i]);
  }
  // A jump up between neighbours (by more than half a period) is where the scan reads the cell: bisect it.
  for (uint64_t i = 0; i < kPeriodUs / kGridUs; ++i) {
    const uint64_t next = (i + 1) % (kPeriodUs / kGridUs);
    if (latency[next] + kGridUs <= latency[i] + kPeriodUs / 2) continue;
    uint64_t lo = i * kGridUs, hi = lo + kGridUs;  // latency jumps somewhere in (lo, hi]
    while (hi - lo > kResolutionUs) {
      const uint64_t mid = (lo + hi) / 2;
      const uint64_t l = rig.trial(mid % kPeriodUs);
      ASSERT_NE(l, UINT64_MAX);
      note(mid % kPeriodUs, l);
      (l > latency[i] + kPeriodUs / 2 - (mid - lo) ? hi : lo) = mid;
    }
    note(hi % kPeriodUs, rig.trial(hi % kPeriodUs));
  }

  const double scanMs = static_cast<double>(rig.scanUs()) / 1000.0;
  const double budgetMs = rig.scanPeriodMs() + scanMs + 2.0;
  const double worstMs = static_cast<double>(worst) / 1000.0;
  std::printf(
      "REPORT latency.%s.ov_worst_ms=%.3f (onset %.3f ms into the period; budget %.3f = period %u + scan "
      "%.3f + 2; scan bus time %.3f)\n",
      keyOf(c).c_str(), worstMs, static_cast<double>(worstPhase) / 1000.0, budgetMs, rig.scanPeriodMs(),
      scanMs, rig.scanBusUs() / 1000.0);
  EXPECT_LE(worstMs, budgetMs);
}

// This executable's image (BMS_SIM_IMAGE, tests/latency/CMakeLists.txt): the BQ79616 image with 1, 2, 16 and
// 64 devices.
std::vector<Config> configs() {
  const std::string image = BMS_SIM_IMAGE;
  if (image != "lp-mspm0g3507-bq79616") return {Config{BMS_SIM_IMAGE, 1}};
  return {Config{BMS_SIM_IMAGE, 1}, Config{BMS_SIM_IMAGE, 2}, Config{BMS_SIM_IMAGE, 16},
          Config{BMS_SIM_IMAGE, 64}};
}

INSTANTIATE_TEST_SUITE_P(Images, LatencySweep, ::testing::ValuesIn(configs()),
                         [](const ::testing::TestParamInfo<Config>& info) {
                           std::string name = keyOf(info.param);
                           for (char& ch : name) {
                             if (ch == '-' || ch == '.') ch = '_';
                           }
                           return name;
                         });

}  // namespace
