// The BQ769x2-family application as the L1306 images build it (bsp/mspm0/images/images.cmake): compiled
// with their options (tests/app/CMakeLists.txt), on the host BSP against the BQ76952 emulator. The host
// build of everything else keeps every default, so these tests cover what only the images leave out: no
// start-up CONFIG_UPDATE, PackSummary as the only SLCAN message, no statistics and no protection log, no
// protection delays, and a driver without the configuration paths.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/default_limits.hpp"
#include "bq769x2/board.hpp"

static_assert(!fw::app::kConfigUpdate && !fw::app::kCoreMessages && !fw::kStats &&
                  fw::app::ProtectionTask::kLogSize == 0 && !fw::app::kProtectionDelays &&
                  !fw::drivers::bq769x2::kConfigPaths && !fw::app::kFaultIndicator,
              "built with the L1306 image options");

namespace {

namespace b769 = fw::drivers::bq769x2;
using Emulator = bsp::host::Bq769xEmulator;

// The L1306-BQ76952 board, without a settings table (no CONFIG_UPDATE in this build).
struct L1306 : bsp::host::Bq769xBoard<b769::Bq769x2, b769::Bq769x2Measurement, fw::app::SlcanPublisher,
                                      bsp::host::SimSerialTx> {
  L1306() : Bq769xBoard(Emulator::Model::Bq76952, {}, 16, false) {}
  bsp::host::SimSerialTx& serial = output;
  // The SLCAN lines written so far.
  std::vector<std::string> lines() const {
    std::vector<std::string> out;
    const std::string& t = serial.text();
    for (size_t pos = 0, end; (end = t.find('\r', pos)) != std::string::npos; pos = end + 1)
      out.push_back(t.substr(pos, end - pos));
    return out;
  }
  size_t count(const std::string& prefix) const {
    size_t n = 0;
    for (const auto& r : bus.wireLog())
      n += r.text.rfind(prefix, 0) == 0 ? 1 : 0;
    return n;
  }
};

TEST(L1306App, StartsWithoutConfigUpdateEnablesTheFetsAndScans) {
  L1306 b;
  b.h.runFor(fw::ms(1000));
  EXPECT_TRUE(b.app.monitor().running());
  EXPECT_TRUE(b.emu.fetEnabled()) << "FET_ENABLE sent after the probe";
  EXPECT_FALSE(b.emu.sleepAllowed()) << "SLEEP_DISABLE needs no CONFIG_UPDATE: sent all the same";
  EXPECT_EQ(b.count("S 10 3E 90 00"), 0u) << "no SET_CFGUPDATE: the image applies no settings";
  EXPECT_EQ(b.count("S 10 60 "), 0u) << "no data-memory write";
  EXPECT_GE(b.count("S 10 0A Sr 11 ["), 8u) << "a scan every 100 ms";
  const fw::app::PackView& pack = b.app.pack();
  ASSERT_TRUE(pack.totals.cells);
  EXPECT_EQ(pack.totals.extreme[fw::app::kMaxCell], 3700);
  EXPECT_EQ(pack.totals.packMv, 16 * 3700);
  EXPECT_TRUE(b.app.status().chargeOn && b.app.status().dischargeOn);
  // Statistics are not kept; the link still counts retries (the scan acts on them).
  EXPECT_EQ(b.app.monitor().stats().scans, 0u);
  EXPECT_EQ(b.app.monitor().driver().stats().transactions, 0u);
  EXPECT_TRUE(b.app.protection().log().empty());
}

TEST(L1306App, SlcanCarriesPackSummaryOnlyEveryCycle) {
  L1306 b;
  b.h.runFor(fw::ms(2050));  // two slow-cycle periods
  const auto lines = b.lines();
  ASSERT_GE(lines.size(), 19u);  // one PackSummary per 100 ms
  for (const auto& l : lines) {
    ASSERT_EQ(l.size(), 21u) << l;
    EXPECT_EQ(l.substr(0, 5), "t1008") << l;
  }
  // The last summary: 16 x 3.700 V = 59.20 V in 10 mV, data valid, both paths on, no fault.
  const std::string& last = lines.back();
  EXPECT_EQ(last.substr(5, 4), "2017");  // 5920 = 0x1720, little-endian
  const int flags = std::stoi(last.substr(15, 2), nullptr, 16);
  EXPECT_EQ(flags & 0x0F, 0x0B);  // ChargeFet, DischargeFet, DataValid
  EXPECT_EQ(last.substr(17, 4), "0000");
}

TEST(L1306App, OvervoltageOpensBothPathsThroughTheDeviceWithinAScanPeriod) {
  L1306 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_TRUE(b.app.monitor().running());
  b.bus.clearWireLog();
  b.emu.setCellMv(5, 4300);  // above the firmware limit (4250 mV), below the device's own COV
  b.h.runFor(fw::ms(250));
  EXPECT_EQ(b.count("S 10 3E 95 00"), 1u) << "ALL_FETS_OFF";
  EXPECT_FALSE(b.app.status().chargeOn);
  EXPECT_FALSE(b.app.status().dischargeOn);
  EXPECT_NE(b.app.status().active & fw::app::bit(fw::app::FaultId::CellOvervoltage), 0);
  const auto lines = b.lines();
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.back().substr(17, 4), "0100");  // ActiveFaults bit 0, little-endian
}

TEST(L1306App, AlertOpensThePathsWithoutWaitingForAScan) {
  L1306 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_TRUE(b.app.monitor().running());
  b.bus.clearWireLog();
  const uint64_t t0 = b.h.nowUs();
  b.alert.drive(false);  // the device asserts ALERT
  // The command goes out at the next read boundary of the scan in progress, if any, long before the next
  // scan would tell: complete within the 2 ms budget (ARCHITECTURE.md).
  ASSERT_TRUE(b.h.runUntil([&] { return b.count("S 10 3E 95 00") != 0; }, fw::ms(10)));
  uint64_t done = 0;
  for (const auto& r : b.bus.wireLog())
    if (r.text.rfind("S 10 3E 95 00", 0) == 0) done = r.endUs;
  EXPECT_LE(done - t0, 2000u) << "fault line to FET-off command complete";
}

TEST(L1306App, TheDriverHasNoConfigurationPaths) {
  L1306 b;
  b.h.runFor(fw::ms(1000));
  // The link operation only the configure operation needs (a delayed read: the CFGUPDATE polls) is refused
  // rather than sent half-built. Subcommand writes with data stay: FET_CONTROL needs them.
  b769::Link& link = const_cast<b769::Bq769x2&>(b.app.monitor().driver()).link();
  ASSERT_TRUE(b.h.runUntil([&] { return !link.busy(); }, fw::ms(100)));  // between two scans
  EXPECT_EQ(link.startRead(0x12, 2, 0, fw::us(250)), fw::Status::InvalidArgument);
  const b769::Setting one[] = {{0x9278, 1, 83}};
  b769::Bq769x2& driver = const_cast<b769::Bq769x2&>(b.app.monitor().driver());
  EXPECT_EQ(driver.startConfigure(one), fw::Status::InvalidArgument);
  EXPECT_EQ(driver.startBalance(0x0001), fw::Status::InvalidArgument);
}

}  // namespace
