// Commands to the images themselves on the twin (build/<preset>/<preset>.elf; skipped when not built):
// - the G3507 MCAN filter as the image programs it: the command identifiers reach RX FIFO 0 (IR.RF0N, one
//   each), every other frame is rejected by the hardware with no trace and no interrupt;
// - bootloader entry on the G3507-BQ76952 image: the FETs off first, the accepted answer on the bus, then the
//   software-invoke reset with RESETLEVEL 2 (which the twin stops at: it does not model the ROM bootloader);
// - an L1306 image answering SLCAN lines on PA9, and ignoring a line longer than any command;
// - the ALERT fast path with the bus (G3507) or the line (L1306) full of valid commands, in CPU-counted time:
//   the flood must not delay protection past its 2 ms budget.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "app/command/e2e.hpp"
#include "board/board.hpp"
#include "can/bms.hpp"
#include "gtest/gtest.h"
#include "sim/harness.hpp"

namespace {

using twin::Board;
using twin::ElfFile;
namespace bms = fw::can::bms;

std::string elfPath(const std::string& preset) {
  return std::string(TWIN_IMAGES) + "/" + preset + "/" + preset + ".elf";
}

struct Rig {
  explicit Rig(const std::string& preset) : board(*twin::imageByPreset(preset), h.clock, 2) {
    if (auto* e = board.bq769x()) {
      for (uint8_t c = 1; c <= 16; ++c)
        e->setCellMv(c, 3700);
    }
    if (std::filesystem::exists(elfPath(preset)) && elf.load(elfPath(preset))) loaded = board.load(elf);
  }
  uint64_t nowUs() { return board.machine().now() / board.machine().cyclesPerUs(); }
  void runMs(uint64_t ms) { board.runUntilUs(nowUs() + ms * 1000); }
  bsp::host::Harness h;
  Board board;
  ElfFile elf;
  bool loaded = false;
};

#define RIG_OR_SKIP(r, preset)                                                             \
  Rig r(preset);                                                                           \
  if (!r.loaded) GTEST_SKIP() << elfPath(preset) << " is not built (./ci/test builds it)"; \
  static_assert(true)

fw::hal::CanFrame sealed(fw::hal::CanFrame f) {
  f.data[0] = fw::app::command::frameCrc(f.id, f.data.data(), f.dlc);
  return f;
}

TEST(TwinCommands, TheMcanFilterPassesTheCommandsAloneAndARejectedFrameRaisesNoInterrupt) {
  RIG_OR_SKIP(r, "lp-mspm0g3507-bq76952");
  r.runMs(500);
  const twin::Mcan& mcan = *r.board.chip().mcan();
  ASSERT_EQ(mcan.newMessageEvents(), 0U);
  // Not commands: another node's telemetry, the identifier after the last command, an extended frame whose
  // base identifier is a command's, and 0x5FF.
  r.board.sendCan({0x100, false, 8, {}});
  r.board.sendCan(sealed({0x608, false, 3, {0, 0, 1}}));
  r.board.sendCan({0x600U << 18, true, 3, {}});
  r.board.sendCan({0x5FF, false, 8, {}});
  r.runMs(20);
  EXPECT_EQ(mcan.framesRejected(), 4U);
  EXPECT_EQ(mcan.newMessageEvents(), 0U);  // no RF0N: no receive interrupt for any of them
  // Each command identifier is stored and raises RF0N once.
  for (uint32_t id : bms::kReceivedIds)
    r.board.sendCan(sealed({id, false, 8, {0, 0, 7}}));  // for node 7: taken in, not answered
  r.runMs(20);
  EXPECT_EQ(mcan.framesReceived(), bms::kReceivedIds.size());
  EXPECT_EQ(mcan.newMessageEvents(), bms::kReceivedIds.size());
  EXPECT_FALSE(r.board.machine().stopped()) << r.board.machine().stopReason();
  EXPECT_TRUE(r.board.warnings().empty());
}

TEST(TwinCommands, BootloaderEntryOpensTheFetsAnswersThenResetsIntoTheBootloader) {
  RIG_OR_SKIP(r, "lp-mspm0g3507-bq76952");
  r.runMs(1000);
  ASSERT_FALSE(r.board.fetsOn().empty());
  ASSERT_TRUE(r.board.fetsOn().back().level) << "the FETs are on before the request";
  bms::EnterBootloader m{};
  m.target = 1;
  m.traceId = r.board.chip().factory().traceId();
  m.key = 0xA5;
  r.board.sendCan(sealed(m.pack()));
  // The reset into the ROM bootloader: the boot code holds the core and starts the BSL (bsp/twin/bsl).
  for (int k = 0; k < 200 && !r.board.machine().coreHeld(); ++k)
    r.runMs(1);
  ASSERT_FALSE(r.board.machine().stopped()) << r.board.machine().stopReason();
  ASSERT_TRUE(r.board.machine().coreHeld()) << "no reset into the bootloader within 200 ms";
  EXPECT_EQ(r.board.chip().bootCode().bslReason(), "software invoke (RESETLEVEL BOOTLOADERENTRY)");
  ASSERT_FALSE(r.board.machine().resets().empty());
  EXPECT_NE(r.board.machine().resets().back().find("bootloader entry (RESETCMD, RESETLEVEL 2)"),
            std::string::npos)
      << r.board.machine().resets().back();
  // The reset log's entries begin with the time in seconds to the microsecond.
  const uint64_t resetAt =
      static_cast<uint64_t>(std::strtod(r.board.machine().resets().back().c_str(), nullptr) * 32e6);
  uint64_t fetsOff = 0, answered = 0;
  for (const auto& e : r.board.fetsOn()) {
    if (!e.level) fetsOff = e.cycle;
  }
  for (const auto& f : r.board.canFrames()) {
    if (f.frame.id == bms::CommandAck::kId &&
        bms::CommandAck::unpack(f.frame).command == bms::EnterBootloader::kId)
      answered = bms::CommandAck::unpack(f.frame).result == 0 ? f.endCycle : 0;
  }
  ASSERT_NE(fetsOff, 0U);
  ASSERT_NE(answered, 0U);
  EXPECT_LT(fetsOff, answered);
  EXPECT_LT(answered, resetAt);
  std::printf(
      "REPORT twin.lp-mspm0g3507-bq76952.bootloader_entry: FETs off %.2f ms before the answer, the "
      "reset %.2f ms after it (CPU-counted)\n",
      (answered - fetsOff) / 32000.0, (resetAt - answered) / 32000.0);
}

TEST(TwinCommands, AnL1306ImageAnswersSlcanLinesOnPa9) {
  RIG_OR_SKIP(r, "lp-mspm0l1306-bq76952");
  r.runMs(500);
  const size_t before = r.board.slcanLines().size();
  r.board.sendSerial("V\rO\rt6003950301\r");
  std::string longLine(40, 'x');
  r.board.sendSerial(longLine + "\r");
  r.runMs(30);
  std::string answers;
  for (size_t k = before; k < r.board.slcanLines().size(); ++k) {
    const std::string& t = r.board.slcanLines()[k].text;
    if (t[0] != 't' || t.rfind("t580", 0) == 0) answers += t;
  }
  // V, O, the frame ("z", then its acknowledgement: ClearFaults, counter 3, accepted), the long line (BEL).
  EXPECT_EQ(answers, "V0101\r\rz\rt58080100060300000000\r\a");
  EXPECT_FALSE(r.board.machine().stopped()) << r.board.machine().stopReason();
}

// A valid Identify for this node, the next counter each time.
fw::hal::CanFrame identify(uint8_t& counter) {
  fw::hal::CanFrame f{bms::Identify::kId, false, bms::Identify::kDlc, {0, counter, 1}};
  counter = static_cast<uint8_t>((counter + 1) & 0x0F);
  return sealed(f);
}

// ALERT to FETs off with commands flooding in from 1 s on, swept over the scan period (200 us grid over the
// first 3 ms of a scan, where the bus is busy, and its last millisecond).
void sweepUnderFlood(const std::string& preset) {
  uint64_t worst = 0, worstAt = 0;
  for (uint64_t offset = 0; offset < 100000; offset += offset < 3000 || offset >= 99000 ? 200 : 96000) {
    Rig r(preset);
    if (!r.loaded) GTEST_SKIP() << elfPath(preset) << " is not built (./ci/test builds it)";
    uint8_t counter = 0;
    const bool can = r.board.chip().mcan() != nullptr;
    auto feed = [&] {  // keep the line full: the next line whenever less than one is waiting
      if (can) return;
      while (r.board.serialBacklog() < 32) {
        const fw::hal::CanFrame f = identify(counter);
        char line[32];
        int n = std::snprintf(line, sizeof line, "t%03X%u", f.id, f.dlc);
        for (uint8_t i = 0; i < f.dlc; ++i)
          n += std::snprintf(line + n, sizeof line - static_cast<size_t>(n), "%02X", f.data[i]);
        r.board.sendSerial(std::string(line) + "\r");
      }
    };
    r.runMs(1000);
    if (can) {
      r.board.setCanFlood([&]() -> std::optional<fw::hal::CanFrame> { return identify(counter); });
    } else {
      r.board.sendSerial("O\r");
    }
    // The next scan's start: its first block read on I2C.
    uint64_t scan = 0;
    for (uint64_t t = r.nowUs(); scan == 0 && t < r.nowUs() + 200000; t += 100) {
      feed();
      r.board.runUntilUs(t);
      for (const auto& tr : r.board.i2cLog()) {
        if (tr.text.rfind("S 10 0A ", 0) == 0 && tr.startCycle / 32 >= 1000000) scan = tr.startCycle / 32;
      }
    }
    ASSERT_NE(scan, 0U);
    for (uint64_t t = r.nowUs(); t < scan + offset; t += 100) {
      feed();
      r.board.runUntilUs(std::min(t + 100, scan + offset));
    }
    const uint64_t t0 = r.board.machine().now();
    r.board.driveMonitorSignal(false);
    uint64_t acted = 0;
    for (uint64_t t = r.nowUs(); t < scan + offset + 20000 && acted == 0; t += 50) {
      feed();
      r.board.runUntilUs(t);
      for (const auto& e : r.board.fetsOn()) {
        if (!e.level && e.cycle >= t0) {
          acted = e.cycle;
          break;
        }
      }
    }
    ASSERT_FALSE(r.board.machine().stopped()) << r.board.machine().stopReason();
    ASSERT_NE(acted, 0U) << "the FETs never went off, signal at " << offset << " us into the scan";
    const uint64_t took = (acted - t0) / 32;
    EXPECT_LE(took, 2000U) << "took " << took << " us with the signal " << offset << " us into the scan";
    if (took > worst) worst = took, worstAt = offset;
  }
  std::printf(
      "REPORT twin.%s.alert_to_fets_off_under_command_flood_worst_us=%llu (signal %llu us into the scan, "
      "200 us grid; budget 2000; CPU-counted time)\n",
      preset.c_str(), static_cast<unsigned long long>(worst), static_cast<unsigned long long>(worstAt));
}

TEST(TwinCommands, AlertToFetsOffStaysInBudgetWithTheBusFullOfCommandsOnTheG3507) {
  sweepUnderFlood("lp-mspm0g3507-bq76952");
}

TEST(TwinCommands, AlertToFetsOffStaysInBudgetWithTheLineFullOfCommandsOnTheL1306) {
  sweepUnderFlood("lp-mspm0l1306-bq76952");
}

}  // namespace
