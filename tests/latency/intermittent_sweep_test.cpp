// An intermittent link (issue 24 item 4): from its onset until it heals, most monitor transactions fail, in
// bms-sim's pattern (the I2C devices drop off the bus for 250 ms of every 350 ms; the BQ79616 base corrupts
// every other millisecond's response). Which scans fail depends on where the link's edges fall against the
// scan grid, so the onset is swept over a whole scan period on a 1 ms grid. For every onset the firmware
// must raise a fault that holds the paths off from at most one second after the onset until the link heals
// (comm_rate: failures within a window, not only in a row), and let them on again within 2.5 s of the
// healing. Before comm_rate, comm_loss (three failures in a row) and stale_data tripped and cleared with the
// pattern, so the paths came back on between them, and for some onsets no fault came at all.
// Output: REPORT intermittent.<image>[.<devices>dev] with the latest trip and the latest clear over the
// onsets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "app/protection/protection.hpp"
#include "image_sim.hpp"

namespace {

using fw::app::FaultId;

constexpr uint32_t kPeriodMs = 100;
constexpr uint32_t kOnsetMs = 2000;      // after bring-up (a 2-device chain: 0.1 s)
constexpr uint32_t kEpisodeMs = 3000;    // the link is intermittent this long
constexpr uint32_t kHoldAfterMs = 1000;  // by then the paths are off, and stay off until it heals
// Clearing needs the monitor back (a BQ769x set-up step that failed waits its 1 s retry interval) and then
// rateWindow (10) scans in a row that validate.
constexpr uint32_t kClearWithinMs = 2500;

std::unique_ptr<bmssim::ImageSim> make() {
  bmssim::SimOptions options;
  options.image = BMS_SIM_IMAGE;
  options.devices = 2;
  std::string error;
  for (const auto& e : bmssim::images()) {
    if (options.image == e.image) return e.make(options, error);
  }
  return nullptr;
}

// One millisecond as bms-sim runs it: the scenario's change first, then the firmware, then the binding's
// bookkeeping (the intermittent pattern).
void step(bmssim::ImageSim& sim) {
  sim.runFor(fw::ms(1));
  sim.afterStep();
}

TEST(IntermittentLink, EveryOnsetHoldsThePathsOffUntilTheLinkHeals) {
  constexpr uint16_t kRate = fw::app::bit(FaultId::CommErrorRate);
  uint32_t latestTrip = 0, latestClear = 0;
  for (uint32_t shift = 0; shift < kPeriodMs; ++shift) {
    auto sim = make();
    ASSERT_TRUE(sim);
    const uint32_t onset = kOnsetMs + shift, healed = onset + kEpisodeMs;
    uint32_t t = 0;
    for (; t < onset; ++t)
      step(*sim);
    ASSERT_EQ(sim->figures().activeFaults, 0) << "healthy before the onset";
    sim->setIntermittent(true);
    uint32_t tripped = 0;
    for (; t < healed; ++t) {
      step(*sim);
      const uint16_t active = sim->figures().activeFaults;
      if (tripped == 0 && (active & kRate) != 0) tripped = t + 1;
      if (t + 1 >= onset + kHoldAfterMs) {
        ASSERT_NE(active & kRate, 0) << "comm_rate not active " << t + 1 - onset << " ms after an onset "
                                     << shift << " ms into the scan period";
      }
    }
    ASSERT_NE(tripped, 0u) << "onset " << shift;
    latestTrip = std::max(latestTrip, tripped - onset);
    sim->setIntermittent(false);
    uint32_t cleared = 0;
    for (; t < healed + kClearWithinMs && cleared == 0; ++t) {
      step(*sim);
      if ((sim->figures().activeFaults & kRate) == 0) cleared = t + 1;
    }
    ASSERT_NE(cleared, 0u) << "comm_rate still active " << kClearWithinMs
                           << " ms after the link healed, onset " << shift;
    latestClear = std::max(latestClear, cleared - healed);
  }
  std::printf(
      "REPORT intermittent.%s: comm_rate tripped within %u ms of the onset and cleared within %u ms of "
      "the healing, every onset over the scan period (1 ms grid)\n",
      BMS_SIM_IMAGE, latestTrip, latestClear);
}

}  // namespace
