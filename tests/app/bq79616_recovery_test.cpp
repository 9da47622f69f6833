// Issue 15: the lp-mspm0g3507-bq79616 board recovers from a monitor-link outage. Before the fix, an outage of
// about 0.5 s or more left the board failing after the link healed: recovery restarted at COMM CLEAR, whose
// probe passed because the devices answered, but the cell ADC had been stopped by the WAKE of a failed
// bring-up during the outage, so every scan failed again and recovery never went further.
//
// The sweep (outage_sweep.hpp): outages of 50 ms .. 10 s starting at points across the 100 ms scan period,
// for 1, 2, 16 and 64 devices, of three kinds: the chain stops answering (bms-sim's comm-loss: commands
// still arrive), the link to the base is cut both ways, and the stack loses power during a cut (it comes back
// in SHUTDOWN).
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "bq79616/board.hpp"
#include "outage_sweep.hpp"

namespace {

namespace b616 = fw::drivers::bq79616;

enum Outage : int { kMute, kCut, kPowerLoss };

struct Board : bsp::host::Bq79616Board {
  explicit Board(size_t devices) : Bq79616Board(devices) {}
  static const char* outageName(int kind) {
    return kind == kMute ? "mute" : kind == kCut ? "cut" : "power-loss";
  }
  void setOutage(int kind, bool on) {
    if (kind == kMute) {
      for (size_t d = 0; d < emu.size(); ++d)
        emu.setMuted(d, on);
      return;
    }
    emu.setDisconnected(on);
    if (kind == kPowerLoss && on) emu.shutdownAll();
  }
};

// How long after the heal good scans may take: the loss must first be noticed (three failed scans, when the
// outage was too short for a recovery to have started), a recovery attempt under way when the link healed may
// still fail (its WAKE was lost: at most one bring-up's worth, then retryAfterFailure), and then one bring-up
// runs. `bootUs`, from power-on to the first good scan, is one bring-up with the LPF settling and a scan.
uint64_t bound(const Board& b, uint64_t bootUs) {
  return 3 * b.config.scanPeriod.us + b.config.retryAfterFailure.us + 2 * bootUs;
}

void sweep(size_t devices, const test::OutageGrid& grid) {
  test::outageSweep<Board>(
      "app.bq79616.outage_recovery_worst_ms.devices_" + std::to_string(devices),
      [devices] { return std::make_unique<Board>(devices); }, grid, bound);
}

// Grid points: shorter than a scan period, just under and over the three failed scans that start a recovery
// (250/350 ms), healing during the first ladder (500 ms, 1 s) or after several attempts (2.5 s, 10 s);
// starting with a scan (0, and 1 ms into it) and between scans. Fewer points for the long chains, whose scans
// and bring-ups cost more simulation time (about 20 s of CPU for the four under ASan).
const test::OutageGrid kFull{
    {50, 250, 350, 500, 1000, 2500, 10000}, {0, 1, 30, 60, 90}, {kMute, kCut, kPowerLoss}};

TEST(Bq79616Recovery, OutageSweepOneDevice) {
  sweep(1, kFull);
}
TEST(Bq79616Recovery, OutageSweepTwoDevices) {
  sweep(2, kFull);
}
TEST(Bq79616Recovery, OutageSweepSixteenDevices) {
  sweep(16, {{50, 350, 1000, 10000}, {0, 5, 60}, {kMute, kCut, kPowerLoss}});
}
TEST(Bq79616Recovery, OutageSweepSixtyFourDevices) {
  sweep(64, {{50, 500, 10000}, {10}, {kMute, kPowerLoss}});  // 10 ms: inside the 25 ms scan
}

// A chain that answers and reports its ADC running, but whose cells never convert: COMM CLEAR and
// SLEEPtoACTIVE pass their probe yet bring back no good scan, so the next recoveries climb to the full
// bring-up, whose WAKE restarts the device. Fails on the code before: every recovery started at COMM CLEAR.
TEST(Bq79616Recovery, ALighterRungThatBringsBackNoGoodScanIsFollowedByAHigherOne) {
  bsp::host::Bq79616Board b(2);
  ASSERT_TRUE(
      b.h.runUntil([&] { return b.app.monitor().stats().scans >= 3 && !b.faultOut.level(); }, fw::s(2)));
  b.emu.freezeAdc(1);
  const uint64_t t0 = b.h.nowUs();
  const auto& reached = b.app.monitor().chain().stats().recoveries;
  ASSERT_TRUE(b.h.runUntil(
      [&] {
        const auto& s = b.app.pack().boards[1];
        return s.last == fw::Status::Ok && b.h.clock.expand(s.takenAt) > t0 && !b.faultOut.level();
      },
      fw::s(10)))
      << "never recovered";
  EXPECT_EQ(reached[static_cast<int>(b616::RecoveryLevel::CommClear)], 1u);
  EXPECT_EQ(reached[static_cast<int>(b616::RecoveryLevel::SleepToActive)], 1u);
  EXPECT_EQ(reached[static_cast<int>(b616::RecoveryLevel::Rewake)], 1u);
  EXPECT_EQ(b.app.monitor().chain().lastRecovery(), b616::RecoveryLevel::Rewake);
  // Each step up waited one recovery interval from the start of the one before.
  EXPECT_GE(b.h.nowUs() - t0, 2 * b.config.recoveryInterval.us);
}

}  // namespace
