// Issue 15, I2C family: the BQ76952 and BQ76907 applications (host defaults: the full application) against a
// device that vanishes from the bus (every address NACKed) for 50 ms .. 10 s, starting anywhere in the scan
// period, with and without a device reset during the outage (the reset loses the RAM configuration: the
// start-up configuration must be written again). Asserted for every case:
//   - no measurement taken during the outage is published as valid;
//   - good scans resume, the device is configured again (after a reset), comm_loss and stale_data clear
//     within one probe period (the monitor probes an absent device every scan period) plus one bring-up time
//     after the link heals, the bring-up time being what the same application needs from power-on to its
//     first complete scan;
//   - then the FETs are on and the G3507's fault output is released within rateWindow (10) scan periods
//     more: an outage that failed four scans trips comm_rate, which clears once ten scans in a row validated
//     (the tail of an outage looks like the tail of an intermittent link).
// The worst recovery per device is printed as a REPORT line, with the worst release.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "bq769x2/board.hpp"

namespace {

using bsp::host::Bq769xEmulator;
using fw::app::FaultId;

// Recovered: a good scan after `since`, the device configured (SLEEP disabled), no comm_loss or stale_data.
template <class Board>
bool recovered(const Board& b, uint64_t since) {
  const auto& s = b.sample();
  const fw::app::FaultMask lost = fw::app::bit(FaultId::CommLoss) | fw::app::bit(FaultId::StaleData);
  return s.valid && s.last == fw::Status::Ok && s.takenAt.us > since && !b.emu.sleepAllowed() &&
         (b.app.status().active & lost) == 0;
}
// Released: no fault active, the FETs on and the fault output (where the board has one) released.
template <class Board>
bool released(const Board& b) {
  return b.app.status().active == 0 && b.emu.chgFet() && b.emu.dsgFet() &&
         (b.config.faultIndicator == nullptr || !b.faultOut.level());
}

auto makeBq76952() {
  return bsp::host::makeG3507Bq76952Board();
}
auto makeBq76907() {
  return bsp::host::makeL1306Bq7690xBoard(Bq769xEmulator::Model::Bq76907);
}

// Power-on to the first complete scan, the device fully set up (SLEEP disabled, FETs on).
template <class Make>
uint64_t bringUpUs(Make make) {
  auto b = make();
  EXPECT_TRUE(b->h.runUntil([&] { return recovered(*b, 0) && released(*b); }, fw::s(2)));
  return b->h.nowUs();
}

struct Outcome {
  uint64_t recoveryUs = 0;
  uint64_t releaseUs = 0;  // from recovery to released()
  bool publishedDuringOutage = false;
};

// Runs one outage: `lengthMs` starting `offsetUs` into a scan period (scans start on each 100 ms tick), the
// device reset half-way through it if `reset`.
template <class Make>
Outcome outage(Make make, uint32_t lengthMs, uint32_t offsetUs, bool reset, uint64_t limitUs) {
  auto b = make();
  Outcome o;
  b->h.runFor(fw::ms(1000));
  EXPECT_TRUE(recovered(*b, 0) && released(*b)) << "healthy before the outage";
  b->h.runFor(fw::us(offsetUs));
  const uint64_t start = b->h.nowUs();
  const uint64_t heal = start + lengthMs * 1000ULL;
  b->emu.setMuted(true);
  bool resetDone = !reset;
  // A scan whose last transaction began before the device vanished may end just after: allow 2 ms.
  while (b->h.nowUs() < heal) {
    if (!resetDone && b->h.nowUs() >= start + lengthMs * 500ULL) {
      b->emu.reset();
      resetDone = true;
    }
    b->h.runFor(fw::us(static_cast<uint32_t>(std::min<uint64_t>(1000, heal - b->h.nowUs()))));
    const auto& s = b->sample();
    if (s.valid && s.takenAt.us >= start + 2000 && s.takenAt.us < heal) o.publishedDuringOutage = true;
  }
  b->emu.setMuted(false);
  if (!b->h.runUntil([&] { return recovered(*b, heal); }, fw::us(static_cast<uint32_t>(limitUs + 500'000)))) {
    o.recoveryUs = UINT64_MAX;
    return o;
  }
  o.recoveryUs = b->h.nowUs() - heal;
  const uint64_t back = b->h.nowUs();
  if (!b->h.runUntil([&] { return released(*b); }, fw::app::kScanPeriod * 11)) {
    o.releaseUs = UINT64_MAX;
    return o;
  }
  o.releaseUs = b->h.nowUs() - back;
  return o;
}

template <class Make>
void sweep(const char* device, Make make, bool reset) {
  const uint64_t bringUp = bringUpUs(make);
  // One probe period plus one bring-up, plus the failed probe's own time (its three NACKed attempts, 0.5 ms
  // apart): the next probe starts one scan period after it ended.
  const uint64_t limit = fw::app::kScanPeriod.us + bringUp + 2000;
  uint64_t worst = 0, release = 0;
  std::string worstCase;
  for (uint32_t lengthMs : {50u, 150u, 250u, 320u, 400u, 1000u, 3000u, 10000u}) {
    for (uint32_t offsetUs = 0; offsetUs < fw::app::kScanPeriod.us; offsetUs += 7000) {
      const Outcome o = outage(make, lengthMs, offsetUs, reset, limit);
      const std::string what = std::to_string(lengthMs) + " ms outage at +" + std::to_string(offsetUs) +
                               " us" + (reset ? " with a reset" : "");
      EXPECT_FALSE(o.publishedDuringOutage) << device << ": " << what;
      EXPECT_LE(o.recoveryUs, limit) << device << ": " << what << " (limit " << limit << " us)";
      EXPECT_NE(o.releaseUs, UINT64_MAX) << device << ": " << what << ": not released 1.1 s after recovering";
      if (o.releaseUs != UINT64_MAX) release = std::max(release, o.releaseUs);
      if (o.recoveryUs > worst && o.recoveryUs != UINT64_MAX) worst = o.recoveryUs, worstCase = what;
    }
  }
  std::printf(
      "REPORT app.%s.outage_recovery_worst_us=%llu reset=%s (%s; bring-up %llu us; limit %llu us; FETs on "
      "%llu us after recovering at worst)\n",
      device, static_cast<unsigned long long>(worst), reset ? "yes" : "no", worstCase.c_str(),
      static_cast<unsigned long long>(bringUp), static_cast<unsigned long long>(limit),
      static_cast<unsigned long long>(release));
}

TEST(Bq769xOutage, Bq76952DeviceVanishes) {
  sweep("bq76952", makeBq76952, false);
}
TEST(Bq769xOutage, Bq76952DeviceVanishesAndResets) {
  sweep("bq76952", makeBq76952, true);
}
TEST(Bq769xOutage, Bq76907DeviceVanishes) {
  sweep("bq76907", makeBq76907, false);
}
TEST(Bq769xOutage, Bq76907DeviceVanishesAndResets) {
  sweep("bq76907", makeBq76907, true);
}

}  // namespace
