// The BQ79616 application as the lp-mspm0g3507-bq79616 image composes it (chain on a 1 Mbaud UART, nFAULT,
// CAN out, fault output), on the host BSP against the chain emulator: the nFAULT fast path against its
// budget (README "Figures": fault visible in the device -> action complete <= 2 ms on nFAULT) and the fault
// output's start-up state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "bq79616/board.hpp"
#include "evaluations_per_scan.hpp"

namespace {

// Two devices, as in TI's example.
struct G3507 : bsp::host::Bq79616Board {
  G3507() : Bq79616Board(2) {}
  // When the fault output was last driven high at or after `fromUs`, or 0.
  uint64_t assertedAt(uint64_t fromUs) const {
    for (const auto& [t, level] : faultOut.history())
      if (t >= fromUs && level) return t;
    return 0;
  }
};

TEST(Bq79616App, FaultOutputStaysAssertedUntilTheChainHasBeenMeasured) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_FALSE(b.faultOut.history().empty());
  const auto [releasedAt, level] = b.faultOut.history().front();
  EXPECT_FALSE(level);
  EXPECT_GE(b.app.monitor().stats().scans, 1u);
  // Released by the first evaluation with fresh data, not by a tick before any.
  EXPECT_EQ(b.faultOut.history().size(), 1u);
  std::printf("REPORT app.bq79616.fault_output_released_ms=%.1f (first fresh scan after bring-up)\n",
              static_cast<double>(releasedAt) / 1000.0);
}

// The monitor tests the chain's events as a constant (Bq79616Device::driverEvents()): they must be what the
// chain itself reports once the fault line is attached.
TEST(Bq79616App, TheMonitorsDriverEventsAreTheChains) {
  G3507 b;
  namespace ev = fw::app::monitor_event;
  EXPECT_EQ(b.app.monitor().chain().events(), ev::kBus | ev::kTimer | ev::kFaultLine);
}

// Issue 14 item 3: one evaluation per scan, not a second one of the same data at the periodic check.
TEST(Bq79616App, ProtectionEvaluatesOncePerScan) {
  G3507 b;
  expectOneEvaluationPerScan(b);
}

// nFAULT may fall at any point of the scan period, including during a scan's frames.
TEST(Bq79616App, NfaultToFaultOutputWithinTwoMillisecondsWhereverTheScanIs) {
  uint64_t worst = 0;
  for (uint64_t offset = 0; offset < 3000; offset += 100) {
    G3507 b;
    b.h.runFor(fw::ms(1000));
    ASSERT_FALSE(b.faultOut.level());
    b.h.runFor(fw::us(static_cast<uint32_t>(offset)));
    const uint64_t t0 = b.h.nowUs();
    b.nfault.drive(false);
    ASSERT_TRUE(b.h.runUntil([&] { return b.faultOut.level(); }, fw::ms(20))) << "offset " << offset;
    const uint64_t took = b.assertedAt(t0) - t0;
    worst = std::max(worst, took);
    EXPECT_LE(took, 2000u) << "nFAULT " << offset << " us into the scan period";
  }
  std::printf(
      "REPORT app.bq79616.nfault_to_fault_output_worst_us=%llu of virtual time (budget 2000; the host does "
      "not model CPU time, only bus and wire time)\n",
      static_cast<unsigned long long>(worst));
}

}  // namespace
