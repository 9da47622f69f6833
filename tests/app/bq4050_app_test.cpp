// The lp-mspm0g3507-bq4050 board (firmware/app/monitors/bq4050_app.hpp) on the host BSP against the gauge
// emulator on a 100 kHz SMBus with the image's 25 ms stretch limit: issue 15's outage sweep. The gauge
// vanishes from the bus (a cable, a gauge in reset) for 50 ms .. 10 s starting at points across the 100 ms
// scan period, either coming back as it was or having reset in between; good scans must resume within the
// bound below after it returns, with the fault output and comm_loss/stale_data cleared, and no scan in
// between may be published as valid.
#include <gtest/gtest.h>

#include <memory>

#include "bq4050/board.hpp"
#include "can/bms.hpp"
#include "commands/command_frames.hpp"
#include "outage_sweep.hpp"

namespace {

enum Outage : int { kVanish, kVanishAndReset };

struct Board : bsp::host::Bq4050Board {
  static const char* outageName(int kind) { return kind == kVanish ? "vanish" : "vanish+reset"; }
  void setOutage(int kind, bool on) {
    attachGauge(!on);
    if (on && kind == kVanishAndReset) gauge.reset();
  }
};

// The loss must first be noticed (three failed scans); once it is, the gauge is probed again within one scan
// period of answering again; then one probe and one scan run (`bootUs`, from power-on to the first good scan,
// is one of each). Fails on the code before, which waited a whole second between probes (worst 1005 ms).
uint64_t bound(const Board& b, uint64_t bootUs) {
  return 4 * b.config.scanPeriod.us + bootUs;
}

// The monitor tests the gauge's events as a constant (Bq4050Device::driverEvents()): they must be what the
// gauge itself reports.
// The BQ4050 image's one fault output opens both paths: its current faults must recover on time.
static_assert(&fw::app::Bq4050App::kLimits == &fw::app::kSingleOutputLimits);

TEST(Bq4050App, TheMonitorsDriverEventsAreTheGauges) {
  Board b;
  namespace ev = fw::app::monitor_event;
  EXPECT_EQ(b.app.monitor().gauge().events(), ev::kBus | ev::kTimer);
}

TEST(Bq4050Recovery, OutageSweep) {
  test::outageSweep<Board>(
      "app.bq4050.outage_recovery_worst_ms", [] { return std::make_unique<Board>(); },
      {{50, 250, 350, 500, 1000, 2500, 10000}, {0, 5, 30, 60, 90}, {kVanish, kVanishAndReset}}, bound);
}

}  // namespace

namespace {

// The gauge's SafetyStatus maps bit by bit to the paths its FETs guard (issue 24 item 1; SLUUAQ3A chapter 2,
// each protection's XCHG / XDSG): COV charge, CUV discharge, OTF both, a permanent failure both; no flag,
// no path. The old code took any flag as "both".
TEST(Bq4050App, TheGaugesFlagsMapToThePathsTheyGuard) {
  using S = fw::regmap::bq4050::bits::SafetyStatus;
  fw::drivers::bq4050::Measurement m{};
  EXPECT_EQ(fw::app::blockedPaths(m), 0);
  m.safetyStatus = S::fromRaw(S::cov_mask);
  EXPECT_EQ(fw::app::blockedPaths(m), 1) << "charge";
  m.safetyStatus = S::fromRaw(S::cuv_mask | S::ascd_mask);
  EXPECT_EQ(fw::app::blockedPaths(m), 2) << "discharge";
  m.safetyStatus = S::fromRaw(S::occ1_mask | S::otd_mask);
  EXPECT_EQ(fw::app::blockedPaths(m), 3);
  m.safetyStatus = S::fromRaw(S::otf_mask);
  EXPECT_EQ(fw::app::blockedPaths(m), 3) << "FET overtemperature: both";
  m.safetyStatus = S::fromRaw(0);
  m.pfStatus = 1;
  EXPECT_EQ(fw::app::blockedPaths(m), 3) << "permanent failure: both";
}

// Pack storage on the BQ4050 image (issue 32): the scan period only (the bq4050-evm pack's 1000 ms; the
// gauge's own SLEEP is its business). StorageMode is accepted at rest, the monitor scans once a second,
// nothing goes stale, and a load ends storage at the next scan; without it the monitor scans every 100 ms.
TEST(Bq4050Storage, StorageScansEverySecondAndALoadEndsIt) {
  Board b;
  b.h.runFor(fw::ms(500));
  bmstool::CommandBuilder commands;
  std::string error;
  const auto f = commands.build("StorageMode", {"Mode=enter"}, error);
  ASSERT_TRUE(f) << error;
  const size_t before = b.can.sent().size();
  b.can.peerSend(*f);
  b.h.runFor(fw::ms(200));
  bool accepted = false;
  for (size_t i = before; i < b.can.sent().size(); ++i) {
    const auto& s = b.can.sent()[i].frame;
    if (s.id == fw::can::bms::CommandAck::kId) accepted = fw::can::bms::CommandAck::unpack(s).result == 0;
  }
  EXPECT_TRUE(accepted);
  EXPECT_TRUE(b.app.pack().storage.on);
  uint32_t scans = b.app.monitor().stats().scans;
  b.h.runFor(fw::ms(5000));
  EXPECT_LE(b.app.monitor().stats().scans - scans, 6U) << "one scan per 1000 ms storage period";
  EXPECT_EQ(b.app.status().active, 0U) << "nothing stale";
  b.gauge.setCurrent(-2000);
  b.h.runFor(fw::ms(1100));
  EXPECT_FALSE(b.app.pack().storage.on);
  scans = b.app.monitor().stats().scans;
  b.h.runFor(fw::ms(1000));
  EXPECT_GE(b.app.monitor().stats().scans - scans, 9U) << "100 ms scans again";
}

}  // namespace
