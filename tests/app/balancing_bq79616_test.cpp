// Balancing on the lp-mspm0g3507-bq79616 application, on the host BSP against the chain emulator: the device
// rules the firmware must keep (bsp/host/emul/bq79616/balancing.cpp), the refresh of the timers, the stops,
// and the confirmation from BAL_STAT. Each test fails if the firmware breaks its rule.
#include <gtest/gtest.h>

#include <cstdio>

#include "bq79616/board.hpp"

namespace {

using fw::app::BalancingState;

struct Chain : bsp::host::Bq79616Board {
  explicit Chain(size_t devices = 2) : Bq79616Board(devices) {}
  // Every device: cell 1 at 3.900 V, the others 20..80 mV above it.
  void imbalance() {
    for (size_t d = 0; d < emu.size(); ++d) {
      for (int c = 1; c <= 16; ++c)
        emu.setCellMicrovolts(d, c, c == 1 ? 3900000 : 3900000 + 20000 * (1 + (c % 4)));
    }
  }
  const fw::app::BalancingStatus& status() const { return *app.pack().balancing; }
};

TEST(BalancingBq79616, EveryDeviceBalancesItsHighestCellsWithinTheDeviceRules) {
  Chain b(2);
  b.h.runFor(fw::ms(1500));
  ASSERT_TRUE(b.app.monitor().running());
  b.imbalance();
  b.h.runFor(fw::ms(2500));
  for (size_t d = 0; d < 2; ++d) {
    const uint16_t on = b.emu.balancingCells(d);
    EXPECT_NE(on, 0) << "device " << d;
    EXPECT_EQ(on & (on >> 1), 0) << "no neighbours (DEV_CONF[NO_ADJ_CB])";
    EXPECT_LE(__builtin_popcount(on), 8) << "at most 8 channels in manual control";
    EXPECT_EQ(b.status().cells[d], on) << "BAL_STAT confirmed what runs";
  }
  EXPECT_EQ(b.emu.balanceCounters().invalid, 0u);
  EXPECT_EQ(b.emu.balanceCounters().aborted, 0u);
  EXPECT_EQ(b.status().state, BalancingState::Balancing);
}

// The timers run 30 s (Balancer::kTimerCode): written again every 10 s, a minute of balancing never lapses.
TEST(BalancingBq79616, TimersRefreshedBeforeTheyRunOut) {
  Chain b(2);
  b.h.runFor(fw::ms(1500));
  b.imbalance();
  b.h.runFor(fw::s(60));
  EXPECT_EQ(b.emu.balanceCounters().expired, 0u);
  EXPECT_NE(b.emu.balancingCells(0), 0);
  EXPECT_GE(b.status().seconds[0], 57u);
}

// FLTSTOP_EN (set with every BAL_GO): an unmasked device fault stops balancing in the device at once
// (ABORTFLT); the firmware sees it in BAL_STAT, publishes nothing balancing and backs off.
TEST(BalancingBq79616, DeviceFaultStopsBalancingAndTheFirmwareSeesIt) {
  Chain b(2);
  b.h.runFor(fw::ms(1500));
  b.imbalance();
  b.h.runFor(fw::ms(2500));
  ASSERT_NE(b.emu.balancingCells(1), 0);
  b.emu.injectCommFault(1, false);  // an unmasked fault in device 1 (and FCOMM_DET in the base)
  EXPECT_EQ(b.emu.balancingCells(1), 0) << "the device stopped on its own";
  EXPECT_GE(b.emu.balanceCounters().aborted, 1u);
  b.h.runFor(fw::ms(1500));
  EXPECT_EQ(b.status().cells[1], 0) << "ABORTFLT: not balancing";
}

// A firmware protection fault: the whole chain is stopped by one broadcast within the scan period after it.
TEST(BalancingBq79616, ProtectionFaultStopsTheChainAtOnce) {
  Chain b(2);
  b.h.runFor(fw::ms(1500));
  b.imbalance();
  b.h.runFor(fw::ms(2500));
  ASSERT_NE(b.emu.balancingCells(0), 0);
  b.emu.setCellMicrovolts(1, 5, 4300000);  // over the firmware's 4.25 V limit
  const uint64_t t0 = b.h.nowUs();
  ASSERT_TRUE(b.h.runUntil([&] { return b.emu.balancingCells(0) == 0 && b.emu.balancingCells(1) == 0; },
                           fw::ms(300)));
  std::printf("REPORT app.bq79616.balancing_stop_after_fault_ms=%.1f (cell over-voltage on board 1)\n",
              static_cast<double>(b.h.nowUs() - t0) / 1000.0);
  EXPECT_EQ(b.status().state, BalancingState::Fault);
}

// The die past CB TWARN pauses balancing in the device (BAL_STAT[OT_PAUSE_DET]); the board counts as not
// balancing while paused. (The policy's own die limit, 65 degC, would stop it first: the device pause is the
// backstop, checked here with the policy's limit out of the way by a die above it only on the emulator side.)
TEST(BalancingBq79616, DieOverTwarnPausesAndIsNotCountedAsBalancing) {
  Chain b(2);
  b.h.runFor(fw::ms(1500));
  b.imbalance();
  b.h.runFor(fw::ms(2500));
  ASSERT_NE(b.emu.balancingCells(0), 0);
  b.emu.setDieTempRaw(0, 2, 4400);  // 110 degC
  EXPECT_EQ(b.emu.balancingCells(0), 0) << "paused";
  EXPECT_NE(b.emu.balStat(0) & 0x40, 0) << "OT_PAUSE_DET";
  b.h.runFor(fw::ms(1500));
  EXPECT_EQ(b.status().cells[0], 0);
}

// The UART time balancing adds to the chain's scans: a minute balancing against a minute of the same chain
// without (REPORT, measured on the wire-timed UART at 1 Mbaud).
TEST(BalancingBq79616, UartTimePerScanReport) {
  for (size_t devices : {2u, 16u}) {
    auto perScan = [devices](bool imbalanced) {
      Chain b(devices);
      b.h.runFor(fw::ms(1500));
      if (imbalanced) b.imbalance();
      b.h.runFor(fw::ms(2500));
      const uint64_t n0 = b.uart.txBytes() + b.uart.rxBytes();
      b.h.runFor(fw::s(60));
      EXPECT_EQ(b.emu.balancingCells(0) != 0, imbalanced);
      return static_cast<double>(b.uart.txBytes() + b.uart.rxBytes() - n0) * b.uart.byteTimeUs() / 600.0;
    };
    const double idle = perScan(false), balancing = perScan(true);
    EXPECT_GT(balancing, idle);
    std::printf(
        "REPORT app.bq79616.balancing_uart_per_scan devices=%zu: +%.0f us (%.0f us without balancing, "
        "%.0f us with; 100 ms scans, 1 Mbaud)\n",
        devices, balancing - idle, idle, balancing);
  }
}

}  // namespace
