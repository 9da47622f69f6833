// Commands on the L1306 images' back-channel UART, as each L1306 image builds them (its option file; the same
// targets as l1306_app_test.cpp): SLCAN lines in at 115 200 Bd, the adapter's answers and the command
// answers out between the published lines.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "app/monitors/bq769x_settings.hpp"
#include "app/publish/slcan.hpp"
#include "bq769x2/board.hpp"
#include "can/bms.hpp"
#include "commands/command_frames.hpp"

namespace {

namespace b769 = fw::drivers::bq769x2;
namespace bms = fw::can::bms;
using Emulator = bsp::host::Bq769xEmulator;
using fw::app::FaultId;

constexpr bool kBq76952 = b769::kFamily == 1;
using Driver = std::conditional_t<kBq76952, b769::Bq769x2, b769::Bq7690x>;
using Measurement = std::conditional_t<kBq76952, b769::Bq769x2Measurement, b769::Bq7690xMeasurement>;
using Board = bsp::host::Bq769xBoard<Driver, Measurement, fw::app::SlcanPublisher, bsp::host::SimSerial>;

std::unique_ptr<Board> makeBoard() {
  if constexpr (kBq76952) {
    return std::make_unique<Board>(Emulator::Model::Bq76952, fw::app::kBq76952Settings, 16, false);
  } else {
    return std::make_unique<Board>(Emulator::Model::Bq76907, fw::app::kBq76907Settings, 7, false,
                                   b769::kBq76907);
  }
}

struct Rig {
  std::unique_ptr<Board> board = makeBoard();
  Board& b = *board;
  bmstool::CommandBuilder commands;
  size_t seen = 0;

  Rig() { b.h.runFor(fw::ms(1000)); }
  std::string line(const std::string& message, const std::vector<std::string>& words = {}) {
    std::string error;
    const auto f = commands.build(message, words, error);
    EXPECT_TRUE(f) << error;
    uint8_t text[fw::app::slcan::kMaxEncodedLength];
    return std::string(reinterpret_cast<const char*>(text), fw::app::slcan::encode(*f, text));
  }
  // What the board sent since the last call.
  std::string sent() {
    const std::string& t = b.output.text();
    std::string out = t.substr(seen);
    seen = t.size();
    return out;
  }
  // The CommandAck lines in `text`, decoded.
  static std::vector<bms::CommandAck> acks(const std::string& text) {
    std::vector<bms::CommandAck> out;
    for (size_t pos = 0; (pos = text.find("t5808", pos)) != std::string::npos; pos += 5) {
      fw::hal::CanFrame f{0x580, false, 8, {}};
      for (int i = 0; i < 8; ++i)
        f.data[i] = static_cast<uint8_t>(std::stoul(text.substr(pos + 5 + 2 * i, 2), nullptr, 16));
      out.push_back(bms::CommandAck::unpack(f));
    }
    return out;
  }
  std::string exchange(const std::string& text, fw::Duration wait = fw::ms(30)) {
    sent();
    b.output.peerSend(text);
    b.h.runFor(wait);
    return sent();
  }
  bool active(FaultId f) const { return (b.app.status().active & fw::app::bit(f)) != 0; }
};

TEST(L1306Commands, PythonCanOpensTheChannelAndTheAdapterAnswers) {
  Rig r;
  const std::string out = r.exchange("C\rS6\rO\rV\rN\rF\r");
  // In order, between published lines: BEL (C while closed), CR, CR, the version, the serial (TraceId's low
  // 16 bits, bsp::host::SimSystem's 0x5A5A1306), the flags.
  std::string answers;
  for (size_t pos = 0; pos < out.size();) {
    if (out[pos] == 't') {  // a published line
      pos = out.find('\r', pos) + 1;
      continue;
    }
    const size_t end = out.find_first_of("\r\a", pos);
    answers += out.substr(pos, end - pos + 1);
    pos = end + 1;
  }
  EXPECT_EQ(answers, "\a\r\rV0101\rN1306\rF00\r");
}

// A single discharge over-current does not latch (the third within the window does, below): ClearFaults is
// answered, and a discharge over-current whose current has stopped stays until its recovery, a charge for 3
// s.
TEST(L1306Commands, ClearFaultsOverSlcanNeverEndsAnOverCurrentBeforeItsRecovery) {
  Rig r;
  r.exchange("O\r");
  std::string out = r.exchange(r.line("SettingWrite", {"Setting=ocd_trip", "Value=-20000"}));
  auto acks = Rig::acks(out);
  ASSERT_EQ(acks.size(), 1U) << out;
  EXPECT_EQ(acks[0].result, 0);
  EXPECT_NE(out.find("z\r"), std::string::npos);
  r.b.h.runFor(fw::ms(200));
  r.b.emu.setCurrentMa(-25000);
  ASSERT_TRUE(r.b.h.runUntil([&] { return r.active(FaultId::DischargeOvercurrent); }, fw::ms(500)));
  r.b.emu.setCurrentMa(0);
  r.b.h.runFor(fw::ms(500));
  ASSERT_TRUE(r.active(FaultId::DischargeOvercurrent));
  EXPECT_FALSE(r.b.emu.dsgFet());
  out = r.exchange(r.line("ClearFaults"), fw::ms(300));
  acks = Rig::acks(out);
  ASSERT_EQ(acks.size(), 1U);
  EXPECT_EQ(acks[0].command, bms::ClearFaults::kId);
  EXPECT_EQ(acks[0].result, 0);
  EXPECT_TRUE(r.active(FaultId::DischargeOvercurrent));
  EXPECT_FALSE(r.b.emu.dsgFet());
  r.b.emu.setCurrentMa(1000);  // a charge: the recovery
  ASSERT_TRUE(r.b.h.runUntil([&] { return !r.active(FaultId::DischargeOvercurrent); }, fw::ms(4000)));
  ASSERT_TRUE(r.b.h.runUntil([&] { return r.b.emu.dsgFet(); }, fw::ms(300)));
}

// The latched discharge over-current over SLCAN (app/protection/default_limits.hpp: the third trip within
// the window): ClearFaults while the current flows is answered condition_present, once it has gone accepted,
// and the DSG FET comes back on.
TEST(L1306Commands, ClearFaultsOverSlcanEndsALatchedOverCurrentOnceTheCurrentIsGone) {
  Rig r;
  r.exchange("O\r");
  r.exchange(r.line("SettingWrite", {"Setting=ocd_trip", "Value=-20000"}));
  r.b.h.runFor(fw::ms(200));
  for (int trip = 1; trip <= 3; ++trip) {
    r.b.emu.setCurrentMa(-25000);
    ASSERT_TRUE(r.b.h.runUntil([&] { return r.active(FaultId::DischargeOvercurrent); }, fw::ms(500))) << trip;
    r.b.emu.setCurrentMa(1000);
    const bool recovered =
        r.b.h.runUntil([&] { return !r.active(FaultId::DischargeOvercurrent); }, fw::ms(4000));
    EXPECT_EQ(recovered, trip < 3) << trip;
  }
  EXPECT_FALSE(r.b.emu.dsgFet());
  EXPECT_TRUE(r.b.emu.chgFet());
  r.b.emu.setCurrentMa(-25000);
  r.b.h.runFor(fw::ms(300));
  auto acks = Rig::acks(r.exchange(r.line("ClearFaults"), fw::ms(300)));
  ASSERT_EQ(acks.size(), 1U);
  EXPECT_EQ(acks[0].result, 10) << "condition_present";
  EXPECT_TRUE(r.active(FaultId::DischargeOvercurrent));
  r.b.emu.setCurrentMa(0);
  r.b.h.runFor(fw::ms(300));
  acks = Rig::acks(r.exchange(r.line("ClearFaults"), fw::ms(300)));
  ASSERT_EQ(acks.size(), 1U);
  EXPECT_EQ(acks[0].result, 0);
  EXPECT_FALSE(r.active(FaultId::DischargeOvercurrent));
  EXPECT_TRUE(r.b.h.runUntil([&] { return r.b.emu.dsgFet(); }, fw::ms(300)));
}

TEST(L1306Commands, AMalformedLineGetsBelAndABadFrameARefusal) {
  Rig r;
  r.exchange("O\r");
  EXPECT_NE(r.exchange("t60G\r").find('\a'), std::string::npos);
  const std::string out = r.exchange(r.line("ClearFaults", {"Crc=0"}));
  const auto acks = Rig::acks(out);
  ASSERT_EQ(acks.size(), 1U);
  EXPECT_EQ(acks[0].result, 1);  // bad_crc
  EXPECT_EQ(r.b.app.commands().handler().stats().rejected, 1);
}

TEST(L1306Commands, AFloodOfCommandsDoesNotStarveThePublishedLines) {
  Rig r;
  r.exchange("O\r");
  // The PC sends valid Identify lines back to back for 2 s (its 115 200 Bd line full: about 520 lines a
  // second), each answered with three frames: far more than the line back can carry beside the published
  // lines.
  std::string flood;
  for (int k = 0; k < 1100; ++k)
    flood += r.line("Identify");
  const size_t firstWrite = r.b.output.writeTimes().size();
  r.b.output.peerSend(flood);
  r.b.h.runFor(fw::ms(2000));
  // PackSummary ("t100") keeps its 100 ms period: at most one answer write (about 6 ms at 115 200 Bd) ever
  // goes between a due line and the wire.
  const auto& text = r.b.output.text();
  const auto& ends = r.b.output.writeTimes();
  const auto& starts = r.b.output.writeStarts();
  uint64_t last = 0, worstGap = 0;
  size_t summaries = 0, answers = 0;
  for (size_t w = firstWrite; w < ends.size(); ++w) {
    if (text.compare(starts[w], 4, "t100") == 0) {
      if (last != 0) worstGap = std::max(worstGap, ends[w] - last);
      last = ends[w];
      ++summaries;
    } else if (text[starts[w]] == 'z') {
      ++answers;
    }
  }
  EXPECT_GE(summaries, 19U);
  EXPECT_LE(worstGap, 100000U + 7000U);
  EXPECT_GT(answers, 100U);
  // Bytes lost to the full buffer splice lines together: such a line is malformed (BEL) or, should it still
  // parse, fails its CRC or counter. Nothing else is refused, and nothing but Identify is acted on.
  const auto& st = r.b.app.commands().handler().stats();
  EXPECT_EQ(st.rejected, st.rejectedFor[1] + st.rejectedFor[2] + st.rejectedFor[3]);
  EXPECT_EQ(st.accepted + st.rejected, answers);
  std::printf(
      "REPORT l1306.slcan_flood: %zu command lines answered in 2 s of a full 115 200 Bd line in "
      "(%u received bytes lost to the full buffer), PackSummary every %.1f ms at worst (period 100 ms)\n",
      answers, r.b.output.lost(), worstGap / 1000.0);
}

// The L1306 images build pack storage out (FW_STORAGE=0, flash): StorageMode is answered unsupported and
// nothing changes (100 ms scans, the device's SLEEP still disallowed).
TEST(L1306Commands, StorageModeIsAnsweredUnsupportedWhereTheImageBuildsItOut) {
  Rig r;
  if (FW_STORAGE != 0) GTEST_SKIP() << "this build has storage";
  r.exchange("O\r");
  const auto acks = Rig::acks(r.exchange(r.line("StorageMode", {"Mode=enter"})));
  ASSERT_EQ(acks.size(), 1U);
  EXPECT_EQ(acks[0].command, bms::StorageMode::kId);
  EXPECT_EQ(acks[0].result, 6) << "unsupported";
  const uint32_t scans = r.b.app.monitor().stats().scans;
  r.b.h.runFor(fw::ms(2000));
  EXPECT_GE(r.b.app.monitor().stats().scans - scans, 19U);
  EXPECT_FALSE(r.b.emu.sleepAllowed());
}

}  // namespace
