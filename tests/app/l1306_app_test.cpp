// The BQ769x2-family application as each L1306 image builds it: compiled with the image's own option file
// (tests/app/CMakeLists.txt reads images/<preset>/options.cmake), with the image's settings table, on the
// host BSP against the emulator of the image's device (FW_BQ769X_FAMILY: 1 BQ76952, 2 BQ76907). The L1306
// images run the whole application (issue 14): the start-up CONFIG_UPDATE, every SLCAN message, statistics,
// the protection log; these tests check each of them with the shipped option set.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "app/monitors/bq769x_settings.hpp"
#include "app/protection/default_limits.hpp"
#include "bq769x2/board.hpp"

static_assert(fw::app::kConfigUpdate && fw::app::kAllMessages && fw::kStats &&
                  fw::app::ProtectionTask::kLogSize != 0 && fw::drivers::bq769x2::kConfigPaths,
              "the L1306 images build the whole application");
static_assert(fw::drivers::bq769x2::kFamily != 0, "built with an L1306 image's options (one device family)");

namespace {

namespace b769 = fw::drivers::bq769x2;
using Emulator = bsp::host::Bq769xEmulator;

// The image's device: what its app_init.cpp composes.
constexpr bool kBq76952 = b769::kFamily == 1;
using Driver = std::conditional_t<kBq76952, b769::Bq769x2, b769::Bq7690x>;
using Measurement = std::conditional_t<kBq76952, b769::Bq769x2Measurement, b769::Bq7690xMeasurement>;
constexpr uint8_t kCells = kBq76952 ? 16 : 7;

// The image's board (bq769x2/board.hpp) with the image's settings table.
using Board = bsp::host::Bq769xBoard<Driver, Measurement, fw::app::SlcanPublisher, bsp::host::SimSerial>;
std::unique_ptr<Board> makeBoard() {
  if constexpr (kBq76952) {
    return std::make_unique<Board>(Emulator::Model::Bq76952, fw::app::kBq76952Settings, kCells, false);
  } else {
    return std::make_unique<Board>(Emulator::Model::Bq76907, fw::app::kBq76907Settings, kCells, false,
                                   b769::kBq76907);
  }
}

struct L1306 {
  std::unique_ptr<Board> board = makeBoard();
  bsp::host::Harness& h = board->h;
  bsp::host::SimI2cBus& bus = board->bus;
  Emulator& emu = board->emu;
  bsp::host::SimEdgeInput& alert = board->alert;
  bsp::host::SimSerial& serial = board->output;
  const fw::app::Bq769xAppConfig& config = board->config;
  Board::App& app = board->app;

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

// The L1306 images build the link without the CRC mode (FW_BQ769X_CRC=0: their device runs without CRC). A
// configuration that asks for CRC is refused before anything starts, instead of talking to a CRC-mode
// device in the wrong mode.
TEST(L1306App, ALinkConfiguredForCrcIsRefusedWhereTheBuildHasNoCrc) {
  static_assert(!b769::kCrc, "the L1306 images build without the CRC mode");
  L1306 b;
  b769::LinkConfig config{};
  config.crc = true;
  b769::Link link(b.bus, fw::drivers::DriverContext{b.h.sched, 7, 0x1, 0x2}, config);
  const uint8_t data[1] = {0};
  EXPECT_EQ(link.startRead(0x14, 2), fw::Status::InvalidArgument);
  EXPECT_EQ(link.startSubcommand(0x0022), fw::Status::InvalidArgument);
  EXPECT_EQ(link.startSubcommandWrite(0x9335, data), fw::Status::InvalidArgument);
  EXPECT_FALSE(link.busy()) << "nothing started";
}

TEST(L1306App, ConfiguresTheDeviceEnablesTheFetsAndScans) {
  L1306 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_TRUE(b.app.monitor().running());
  EXPECT_TRUE(b.emu.fetEnabled()) << "FET_ENABLE sent after the configuration";
  EXPECT_EQ(b.count("S 10 3E 90 00"), 1u)
      << "one SET_CFGUPDATE: the emulator's defaults differ from the table";
  EXPECT_GT(b.app.monitor().stats().configWrites, 0u);
  EXPECT_FALSE(b.emu.inConfigUpdate()) << "left CONFIG_UPDATE";
  // The settings took: each reads back as the table says.
  for (const auto& s : b.board->rows) {
    uint32_t want = s.value;
    EXPECT_EQ(b.emu.dataMemory(s.address, s.size), want) << std::hex << s.address;
  }
  const fw::app::PackView& pack = b.app.pack();
  ASSERT_TRUE(pack.totals.cells);
  EXPECT_EQ(pack.totals.extreme[fw::app::kMaxCell], 3700);
  EXPECT_EQ(pack.totals.packMv, kCells * 3700);
  EXPECT_TRUE(b.app.status().chargeOn && b.app.status().dischargeOn);
  // Statistics are kept.
  EXPECT_GE(b.app.monitor().stats().scans, 8u);
  EXPECT_GT(b.app.monitor().driver().stats().transactions, 0u);
}

TEST(L1306App, SlcanCarriesEveryNativeMessage) {
  L1306 b;
  b.h.runFor(fw::ms(2050));  // two slow-cycle periods
  std::set<std::string> ids;
  for (const auto& l : b.lines())
    ids.insert(l.substr(0, 4));
  // PackSummary, CellExtremes, TemperatureExtremes, CellVoltages, Temperatures (bms.yaml); ProtectionEvent
  // comes with a fault (next test).
  for (const char* id : {"t100", "t101", "t102", "t200", "t201"})
    EXPECT_EQ(ids.count(id), 1u) << id;
}

TEST(L1306App, OvervoltageOpensTheChargePathLogsItAndReportsIt) {
  L1306 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_TRUE(b.app.monitor().running());
  const size_t before = b.lines().size();
  b.emu.setCellMv(kCells, 4280);  // above the firmware limit (4250 mV), below the device's own COV
  b.h.runFor(fw::ms(250));
  EXPECT_FALSE(b.app.status().chargeOn);
  EXPECT_TRUE(b.app.status().dischargeOn) << "discharging relieves it: the discharge path stays";
  EXPECT_TRUE(b.app.status().pathsKnown) << "as the device's FET read-back says";
  EXPECT_NE(b.app.status().active & fw::app::bit(fw::app::FaultId::CellOvervoltage), 0);
  EXPECT_FALSE(b.emu.chgFet()) << "the device opened the charge FET";
  EXPECT_TRUE(b.emu.dsgFet());
  ASSERT_FALSE(b.app.protection().log().empty());
  EXPECT_EQ(b.app.protection().log().back().fault, fw::app::FaultId::CellOvervoltage);
  EXPECT_TRUE(b.app.protection().log().back().actionDone);
  bool event = false;
  const auto lines = b.lines();
  for (size_t i = before; i < lines.size(); ++i)
    event = event || lines[i].rfind("t103", 0) == 0;
  EXPECT_TRUE(event) << "ProtectionEvent on SLCAN";
}

TEST(L1306App, AlertOpensThePathsWithoutWaitingForAScan) {
  L1306 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_TRUE(b.app.monitor().running());
  b.bus.clearWireLog();
  const uint64_t t0 = b.h.nowUs();
  b.alert.drive(false);  // the device asserts ALERT
  // The FET-off command goes out at the next read boundary of the scan in progress, if any, long before the
  // next scan would tell: its write complete within the 2 ms budget (README "Figures"). BQ76952:
  // ALL_FETS_OFF; BQ76907: FET Control with CHG_OFF and DSG_OFF.
  char command[16] = "S 10 3E 95 00";
  if constexpr (!kBq76952)
    std::snprintf(command, sizeof command, "S 10 %02X 0C", fw::regmap::bq7690x::cmd::FetControl.address);
  ASSERT_TRUE(b.h.runUntil([&] { return b.count(command) != 0; }, fw::ms(10))) << command;
  uint64_t done = 0;
  for (const auto& r : b.bus.wireLog())
    if (done == 0 && r.text.rfind(command, 0) == 0) done = r.endUs;
  EXPECT_LE(done - t0, 2000u) << "fault line to FET-off command written";
}

}  // namespace
