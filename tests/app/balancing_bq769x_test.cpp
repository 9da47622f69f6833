// Balancing on the BQ769x2-family applications (lp-mspm0g3507-bq76952 and the BQ76907 composition), on the
// host BSP against the emulator, each device rule the driver must keep (bsp/host/emul/bq769x2/balancing.cpp)
// and each way the application must stop: every test fails if the firmware breaks its rule.
#include <gtest/gtest.h>

#include <cstdio>
#include <utility>

#include "bq769x2/board.hpp"

namespace {

namespace b769 = fw::drivers::bq769x2;
namespace m2 = fw::regmap::bq769x2;
using Emulator = bsp::host::Bq769xEmulator;
using fw::app::BalancingMode;
using fw::app::BalancingState;

struct G3507 : bsp::host::G3507Bq76952Board {
  G3507() : bsp::host::G3507Bq76952Board(Emulator::Model::Bq76952, fw::app::kBq76952Settings, 16, true) {}
  // Cells 20..80 mV above cell 1 (3900 mV), charging at 2 A: the policy wants the highest cells.
  void imbalance() {
    for (uint8_t c = 1; c <= 16; ++c)
      emu.setCellMv(c, static_cast<int16_t>(c == 1 ? 3900 : 3900 + 20 * (1 + (c % 4))));
    emu.setCurrentMa(2000);
  }
  const fw::app::BalancingStatus& status() const { return *app.pack().balancing; }
  // CB_ACTIVE_CELLS writes on the wire ("S 10 3E 83 00 lo hi P") since `fromUs`.
  size_t cbWrites(uint64_t fromUs = 0) const {
    size_t n = 0;
    for (const auto& r : bus.wireLog())
      if (r.startUs >= fromUs && r.text.rfind("S 10 3E 83 00 ", 0) == 0 && r.text.size() > 20) ++n;
    return n;
  }
};

struct L1306Bq76907 : bsp::host::L1306Bq7690xBoard {
  L1306Bq76907()
      : bsp::host::L1306Bq7690xBoard(Emulator::Model::Bq76907, fw::app::kBq76907Settings, 7, false,
                                     b769::kBq76907) {}
};

// What goes out before the policy has run once (the first BalancingStatus frames can precede the first scan):
// the start-up mode and no data, never "off" and "balancing" from zeroed memory.
TEST(BalancingBq769x, BeforeTheFirstScanTheStatusSaysAutoAndNoData) {
  G3507 b;
  EXPECT_EQ(b.status().mode(), BalancingMode::Auto);
  EXPECT_EQ(b.status().state, BalancingState::NoData);
  EXPECT_EQ(b.status().cells[0], 0);
}

TEST(BalancingBq769x, SetUpWritesMaxCellsAndBalancingConfiguration) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_TRUE(b.app.monitor().running());
  EXPECT_EQ(b.emu.dataMemory(m2::dm::CellBalanceMaxCells.address, 1), fw::app::kBq769x2BalanceCells);
  EXPECT_EQ(b.emu.dataMemory(m2::dm::BalancingConfiguration.address, 1), 0u);  // host commands accepted
}

TEST(BalancingBq769x, HighestCellsBalanceAndTheReadBackIsPublished) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  b.imbalance();
  b.h.runFor(fw::ms(1000));
  const uint16_t on = b.emu.balancing();
  EXPECT_NE(on, 0);
  EXPECT_EQ(on & (on >> 1), 0) << "never two neighbours on the BQ769x2 (E2E 1505209)";
  EXPECT_LE(__builtin_popcount(on), fw::app::kBq769x2BalanceCells);
  EXPECT_EQ(b.status().cells[0], on) << "what the device read back";
  EXPECT_EQ(b.status().state, BalancingState::Balancing);
  EXPECT_EQ(b.emu.balanceCounters().refused, 0u);
  EXPECT_EQ(b.emu.balanceCounters().adjacent, 0u);
}

// The device balances only a few seconds after each write (E2E 958310; the emulator: 2 s): the firmware
// writes again every second, so a minute of balancing never lapses.
TEST(BalancingBq769x, RefreshedWithinTheDeviceTimeout) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  b.imbalance();
  b.h.runFor(fw::s(60));
  EXPECT_EQ(b.emu.balanceCounters().timeouts, 0u);
  EXPECT_NE(b.emu.balancing(), 0);
  EXPECT_GE(b.status().seconds[0], 58u);
}

// The BQ7690x balances for 20 s after a write (SLUAAP7 section 3): written again every 10 s.
TEST(BalancingBq769x, Bq76907RefreshedWithinItsTwentySeconds) {
  L1306Bq76907 b;
  b.h.runFor(fw::ms(1000));
  for (uint8_t c = 1; c <= 7; ++c)
    b.emu.setCellMv(c, static_cast<int16_t>(c == 1 ? 3900 : 3950));
  b.emu.setCurrentMa(2000);
  b.h.runFor(fw::s(60));
  EXPECT_EQ(b.emu.balanceCounters().timeouts, 0u);
  const uint16_t on = b.emu.balancing();
  EXPECT_NE(on, 0);
  EXPECT_LE(__builtin_popcount(on), fw::app::kBq7690xBalanceCells);
  EXPECT_EQ(b.emu.balanceCounters().refused, 0u) << "bit 0 (reserved) never written";
}

// A protection fault stops balancing within the scan period after it (the policy's fault rule, and the FET
// command that opens a path), and nothing is published as balancing.
TEST(BalancingBq769x, ProtectionFaultStopsBalancingAtOnce) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  b.imbalance();
  b.h.runFor(fw::ms(2000));
  ASSERT_NE(b.emu.balancing(), 0);
  b.emu.setCellMv(5, 4300);  // over the firmware's 4.25 V limit
  const uint64_t t0 = b.h.nowUs();
  ASSERT_TRUE(b.h.runUntil([&] { return b.emu.balancing() == 0; }, fw::ms(300)));
  std::printf("REPORT app.bq76952.balancing_stop_after_fault_ms=%.1f (cell over-voltage)\n",
              static_cast<double>(b.h.nowUs() - t0) / 1000.0);
  b.h.runFor(fw::ms(1500));
  EXPECT_EQ(b.emu.balancing(), 0) << "not started again while the fault is active";
  EXPECT_EQ(b.status().cells[0], 0);
  EXPECT_EQ(b.status().state, BalancingState::Fault);
}

// The command interface's Off (BalancingPolicy::setMode): CB_ACTIVE_CELLS 0 within a scan period, and the
// read-back publishes it.
TEST(BalancingBq769x, ModeOffStopsTheDevice) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  b.imbalance();
  b.h.runFor(fw::ms(2000));
  ASSERT_NE(b.emu.balancing(), 0);
  ASSERT_EQ(b.app.balancing().setMode(BalancingMode::Off, 0, 0, 1, 16), fw::Status::Ok);
  ASSERT_TRUE(b.h.runUntil([&] { return b.emu.balancing() == 0; }, fw::ms(200)));
  b.h.runFor(fw::ms(500));
  EXPECT_EQ(b.status().cells[0], 0);
  EXPECT_EQ(b.status().mode(), BalancingMode::Off);
  EXPECT_EQ(b.status().state, BalancingState::Off);
}

// The device refuses what was asked (here its Cell Balance Max Cells lowered to 1 behind the firmware's
// back): the read-back shows it, nothing is published as balancing, and the firmware backs off instead of
// writing every second.
TEST(BalancingBq769x, ARefusedMaskIsNotPublishedAndBacksOff) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  b.emu.setDataMemory(m2::dm::CellBalanceMaxCells.address, 1, 1);
  b.imbalance();
  const uint64_t t0 = b.h.nowUs();
  bool refusedSeen = false;
  for (int i = 0; i < 300; ++i) {  // 30 s
    b.h.runFor(fw::ms(100));
    EXPECT_EQ(b.status().cells[0], 0) << "nothing the device did not confirm";
    refusedSeen = refusedSeen || b.status().state == BalancingState::Refused;
  }
  EXPECT_TRUE(refusedSeen);
  EXPECT_GE(b.emu.balanceCounters().refused, 1u);
  EXPECT_LE(b.cbWrites(t0), 3u) << "one write after each 10 s back-off, not one a second";
}

// The bus time balancing adds to the BQ76952's scans: a minute balancing against a minute of the same pack
// without (REPORT, measured on the wire-timed bus).
TEST(BalancingBq769x, BusTimePerScanReport) {
  auto perScan = [](bool imbalanced) {
    G3507 b;
    b.h.runFor(fw::ms(1000));
    if (imbalanced) b.imbalance();
    b.h.runFor(fw::ms(2000));
    const uint64_t t0 = b.bus.transactions(), u0 = b.bus.busTimeUs();
    b.h.runFor(fw::s(60));
    EXPECT_EQ(b.emu.balancing() != 0, imbalanced);
    return std::pair{static_cast<double>(b.bus.transactions() - t0) / 600.0,
                     static_cast<double>(b.bus.busTimeUs() - u0) / 600.0};
  };
  const auto [tIdle, uIdle] = perScan(false);
  const auto [tBal, uBal] = perScan(true);
  EXPECT_GT(uBal, uIdle);
  EXPECT_LT(uBal - uIdle, 500.0) << "a write of three short transactions a second and a read-back";
  std::printf(
      "REPORT app.bq76952.balancing_bus_per_scan: +%.2f transactions, +%.0f us (%.2f / %.0f us "
      "without balancing, %.2f / %.0f us with; 100 ms scans, 400 kHz)\n",
      tBal - tIdle, uBal - uIdle, tIdle, uIdle, tBal, uBal);
}

}  // namespace
