// The lp-mspm0g3507-bq79616 application with the devices' own open-wire check (bq79616_app.hpp,
// drivers/bq79616/open_wire.hpp), on the host BSP against the chain emulator: an open sense wire whose cells
// keep reading a plausible 3.7 V (the case the reading rules of pack_view.hpp cannot see) at the bottom tap,
// a middle tap and the top tap, on a 2-device and an 8-device chain, becomes open_wire with the cells beside
// it out of what is published; a repaired wire clears it. The checks keep the scan period and the nFAULT fast
// path within budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "app/protection/protection.hpp"
#include "bq79616/board.hpp"
#include "drivers/bq79616/open_wire.hpp"

namespace {

using fw::app::FaultId;

bool openWireActive(const bsp::host::Bq79616Board& b) {
  return (b.app.status().active & fw::app::bit(FaultId::OpenWire)) != 0;
}

struct Tap {
  const char* name;
  int pin;         // VC pin whose wire opens
  uint16_t cells;  // the cells taken out (bit c = cell c + 1): the one the device names and the one above
};
constexpr Tap kTaps[] = {{"bottom VC0", 0, 0x0003}, {"middle VC8", 8, 0x0180}, {"top VC16", 16, 0x8000}};

class Bq79616AppOpenWire : public ::testing::TestWithParam<std::tuple<int, size_t>> {};

TEST_P(Bq79616AppOpenWire, AnOpenWireThatReadsPlausiblyIsOpenWireFromTheDevicesCheck) {
  const Tap tap = kTaps[std::get<0>(GetParam())];
  const size_t devices = std::get<1>(GetParam());
  bsp::host::Bq79616Board b(devices);
  b.h.runFor(fw::ms(1500));
  ASSERT_TRUE(b.app.monitor().running());
  ASSERT_FALSE(openWireActive(b));
  ASSERT_GE(b.app.monitor().stats().openWireChecks, 1u) << "a check after the first scan";
  ASSERT_FALSE(b.faultOut.level());

  const size_t open = devices - 1;
  b.emu.setOpenWire(open, tap.pin, true);  // every cell still reads 3.700 V
  // Within one check period (10 scans) and a scan.
  ASSERT_TRUE(b.h.runUntil([&] { return openWireActive(b); }, fw::ms(1200))) << tap.name;
  EXPECT_TRUE(b.faultOut.level()) << "open_wire opens both paths (the fault output)";
  const fw::app::PackView& v = b.app.pack();
  EXPECT_TRUE(v.totals.openWire);
  EXPECT_FALSE(v.totals.complete) << "the pack's sum leaves the board out";
  for (size_t d = 0; d < devices; ++d) {
    for (int c = 0; c < 16; ++c) {
      const bool out = d == open && ((tap.cells >> c) & 1U) != 0;
      EXPECT_EQ(v.boards[d].cellMv[c], out ? 0 : 3700) << tap.name << ", device " << d << ", cell " << c + 1;
    }
  }
  EXPECT_EQ(fw::app::openWireCells(v.boards[open].cellMv, 16) & tap.cells, tap.cells);

  // Repaired: the next check clears the verdict, and open_wire ends.
  b.emu.setOpenWire(open, tap.pin, false);
  ASSERT_TRUE(b.h.runUntil([&] { return !openWireActive(b); }, fw::ms(1500))) << tap.name;
  EXPECT_EQ(v.boards[open].cellMv[tap.pin == 0 ? 0 : tap.pin - 1], 3700);
}

INSTANTIATE_TEST_SUITE_P(Taps, Bq79616AppOpenWire,
                         ::testing::Combine(::testing::Values(0, 1, 2),
                                            ::testing::Values(size_t{2}, size_t{8})));

// Ten seconds with a check every second: no scan period overrun, every check within its bound, the scans on
// their grid; and nFAULT during a check reaches the fault output within the 2 ms budget (protection acts on
// the line itself; the check only holds the monitor's bus).
TEST(Bq79616AppOpenWireBudget, ChecksKeepTheScanPeriodAndTheFaultPath) {
  for (size_t devices : {size_t{2}, size_t{16}}) {
    bsp::host::Bq79616Board b(devices);
    b.h.runFor(fw::ms(1500));
    const auto& st = b.app.monitor().stats();
    const uint32_t scans0 = st.scans, checks0 = st.openWireChecks;
    fw::Duration longest{};
    for (int i = 0; i < 10000; ++i) {
      b.h.runFor(fw::ms(1));
      longest = std::max(longest, st.lastOpenWireCheck);
    }
    EXPECT_EQ(st.scanOverruns, 0u);
    EXPECT_EQ(st.openWireFailed, 0u);
    EXPECT_GE(st.openWireChecks - checks0, 9u);
    EXPECT_LE(st.openWireChecks - checks0, 11u);
    EXPECT_GE(st.scans - scans0, 99u) << "a scan every 100 ms";
    EXPECT_LE(longest.us, fw::drivers::bq79616::OpenWireCheck::worstCase(static_cast<uint8_t>(devices)).us);
    std::printf(
        "REPORT app.bq79616.open_wire_check_us devices=%zu longest=%u (virtual time, a check a second)\n",
        devices, longest.us);

    // nFAULT while the sinks are on.
    ASSERT_TRUE(b.h.runUntil([&] { return b.emu.owSinksOn(0); }, fw::ms(1200)));
    const uint64_t t0 = b.h.nowUs();
    b.nfault.drive(false);
    ASSERT_TRUE(b.h.runUntil([&] { return b.faultOut.level(); }, fw::ms(20)));
    uint64_t at = 0;
    for (const auto& [t, level] : b.faultOut.history())
      if (t >= t0 && level && at == 0) at = t;
    EXPECT_LE(at - t0, 2000u);
    std::printf("REPORT app.bq79616.nfault_during_open_wire_check_us devices=%zu took=%llu (budget 2000)\n",
                devices, static_cast<unsigned long long>(at - t0));
  }
}

}  // namespace
