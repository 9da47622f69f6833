// FlashctlStorage (bsp/mspm0/flashctl.*) on the twin's FLASHCTL (bsp/twin/periph/flashctl.hpp: one command
// per CMDEXEC, PROGRAM ONEWORD in 50 us and ERASE SECTOR in 4 ms (typical), FAILWEPROT on a protected
// sector, every sector protected again after each command; its rules FLASH-PROTECTED, FLASH-UNERASED). The
// driver reads the region where the twin keeps its flash, as on the part it reads the mapped flash.
// Addresses: FLASHCTL_BASE (tsv base rows) + hw_flashctl.h offsets and STATCMD fields.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "fixture.hpp"
#include "flashctl.hpp"
#include "gpio.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kFc = 0x400CD000;  // FLASHCTL_BASE (tsv base rows)
constexpr uintptr_t kCmdexec = kFc + 0x1100, kCmdaddr = kFc + 0x1120;
constexpr uintptr_t kCmdbyten = kFc + 0x1124, kData0 = kFc + 0x1130, kData1 = kFc + 0x1134;
constexpr uintptr_t kWeprotA = kFc + 0x11D0, kStatcmd = kFc + 0x13D0;
constexpr uint32_t kInProgress = 4;
constexpr uint32_t kRegion = 0x7000;  // sectors 28..31 (bsp/mspm0/linker)

class Flashctl : public RegisterTest {
 protected:
  explicit Flashctl(twin::Part part = twin::Part::G3507) : RegisterTest(part) {}
  // The twin's flash at `address` (the region's bytes as the part holds them).
  uint8_t& flash(uint32_t address) { return chip().machine().flash()[address]; }
  FlashctlStorage storage() {
    const bool ecc = chip().machine().layout().flashSize > 64 * 1024;  // the G3507 (128 KB) has ECC
    return FlashctlStorage({kFc, kRegion, &flash(kRegion), 4, ecc, 32});
  }
  size_t commands() { return regs().writes(kCmdexec).size(); }
};

class FlashctlL1306 : public Flashctl {
 protected:
  FlashctlL1306() : Flashctl(twin::Part::L1306) {}
};

constexpr std::array<uint8_t, 8> kWord{1, 2, 3, 4, 5, 6, 7, 8};

TEST_F(Flashctl, ProgramsAWordWithTheSectorUnprotectedRightBeforeExecute) {
  auto s = storage();
  EXPECT_EQ(s.program(1024 + 16, kWord), fw::Status::Ok);
  EXPECT_EQ(flash(kRegion + 1024 + 16), 1);
  EXPECT_EQ(flash(kRegion + 1024 + 23), 8);
  EXPECT_EQ(regs().lastWrite(kCmdaddr), 0x7410U);
  EXPECT_EQ(regs().lastWrite(kData0), 0x04030201U);
  EXPECT_EQ(regs().lastWrite(kData1), 0x08070605U);
  EXPECT_EQ(regs().lastWrite(kCmdbyten), 0x1FFU);  // the G3507: the ECC byte too
  EXPECT_TRUE(regs().wroteInOrder({{kWeprotA, ~(1U << 29)}, {kCmdexec, 1}}));
}

TEST_F(FlashctlL1306, ProgramsWithoutTheEccByte) {
  auto s = storage();
  EXPECT_EQ(s.program(0, kWord), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kCmdbyten), 0xFFU);
  EXPECT_EQ(flash(kRegion + 7), 8);
}

TEST_F(Flashctl, ErasesASectorAndChecksItReadsErased) {
  auto s = storage();
  ASSERT_EQ(s.program(3 * 1024 + 0, kWord), fw::Status::Ok);
  EXPECT_EQ(s.erase(3), fw::Status::Ok);
  EXPECT_EQ(flash(kRegion + 3 * 1024), 0xFF);
  EXPECT_EQ(regs().lastWrite(kCmdaddr), 0x7C00U);
  EXPECT_EQ(regs().lastWrite(kWeprotA), ~(1U << 31));
}

TEST_F(Flashctl, RefusesEverythingOutsideTheRegionAndUnerasedWords) {
  auto s = storage();
  EXPECT_EQ(s.erase(4), fw::Status::InvalidArgument);
  EXPECT_EQ(s.program(4096, kWord), fw::Status::InvalidArgument);
  EXPECT_EQ(s.program(4, kWord), fw::Status::InvalidArgument);
  flash(kRegion + 9) = 0x7F;  // a word with a programmed bit
  EXPECT_EQ(s.program(8, kWord), fw::Status::InvalidArgument);
  EXPECT_EQ(commands(), 0U) << "no command reached the controller";
}

TEST_F(Flashctl, AFailureTheControllerReportsIsVerifyFailed) {
  auto s = storage();
  // The sector protected again between the driver's unprotect and CMDEXEC (as by code run in between): the
  // twin ends the command with FAILWEPROT and nothing written (FLASH-PROTECTED), and the driver reports it.
  regs().onWrite(kWeprotA,
                 [this](uint32_t) { chip().machine().map().store(static_cast<uint32_t>(kWeprotA), 4, ~0U); });
  EXPECT_EQ(s.program(0, kWord), fw::Status::VerifyFailed);
  EXPECT_EQ(flash(kRegion), 0xFF);
  const std::vector<std::string> broken = regs().takeViolations();
  ASSERT_EQ(broken.size(), 1U);
  EXPECT_NE(broken[0].find("FLASH-PROTECTED"), std::string::npos) << broken[0];
}

TEST_F(Flashctl, AWordThatDoesNotTakeIsVerifyFailed) {
  auto s = storage();
  // A cell that does not take the program (a worn cell; the twin's flash changed from outside): one byte
  // still reads erased once the command is done.
  regs().onWrite(kCmdexec, [this](uint32_t) {
    regs().advanceUs(twin::Flashctl::kProgramUs + 1);
    flash(kRegion + 3) = 0xFF;
  });
  EXPECT_EQ(s.program(0, kWord), fw::Status::VerifyFailed);
}

TEST_F(Flashctl, TheWaitIsBoundedByTheDataSheetMaximum) {
  // A controller that never reports done, which the twin's never is: STATCMD CMDINPROGRESS is played back
  // for exactly as many reads as the bound allows (a read more gets the twin's CMDDONE and the test fails).
  auto s = storage();
  regs().clearLog();
  // 275 us x 2 at 32 MHz, >= 4 cycles an iteration: 4400 STATCMD reads (computed).
  for (int i = 0; i < 4400; ++i)
    regs().queueRead(kStatcmd, kInProgress);
  EXPECT_EQ(s.program(0, kWord), fw::Status::Timeout);
  EXPECT_EQ(regs().readCount(kStatcmd), 4400U);
  regs().clearLog();
  for (int i = 0; i < 320000; ++i)  // 20 ms x 2 at 32 MHz / 4 (computed)
    regs().queueRead(kStatcmd, kInProgress);
  EXPECT_EQ(s.erase(1), fw::Status::Timeout);
  EXPECT_EQ(regs().readCount(kStatcmd), 320000U);
}

// The watch (flashctl.hpp): the fault line's edge pending (PB0's bit in GPIOB's CPU_INT MIS) while armed
// drives the outputs (DOUTSET of GPIOB: PB2 | PB3) once, from inside the wait; not armed, it drives nothing.
constexpr uintptr_t kGpiobMis = 0x400A2000 + 0x1020 + 0x18, kGpiobDoutset = 0x400A2000 + 0x1290;

TEST_F(Flashctl, AFaultLineEdgeDuringTheWaitDrivesTheOutputsOnceWhileArmed) {
  powerGpioPort(kGpioaBase + kGpioPortStride);
  auto s = storage();
  bool armed = true;
  FlashFaultWatch watch = faultLineWatch(Pin{1, 0, 12}, 1, 0xC);
  watch.armed = &armed;
  EXPECT_EQ(watch.edgeStatus, kGpiobMis);
  EXPECT_EQ(watch.outputSet, kGpiobDoutset);
  s.watchFaultLine(&watch);
  regs().clearLog();
  regs().queueReads(kStatcmd, {kInProgress, kInProgress, kInProgress, kInProgress});
  regs().queueReads(kGpiobMis, {0, 0x2, 0x1, 0x1});  // another pin's edge, then PB0's
  EXPECT_EQ(s.program(0, kWord), fw::Status::Ok);
  ASSERT_EQ(regs().writes(kGpiobDoutset).size(), 1U);
  EXPECT_EQ(regs().lastWrite(kGpiobDoutset), 0xCU);
  EXPECT_EQ(flash(kRegion + 7), 8) << "the program completes as without a watch";
}

TEST_F(Flashctl, AFaultLineEdgeWhileNotArmedDrivesNothing) {
  powerGpioPort(kGpioaBase + kGpioPortStride);
  auto s = storage();
  bool armed = false;  // the monitor is not running: protection does not take the line as a fault
  FlashFaultWatch watch = faultLineWatch(Pin{1, 0, 12}, 1, 0xC);
  watch.armed = &armed;
  s.watchFaultLine(&watch);
  regs().queueReads(kStatcmd, {kInProgress, kInProgress});
  regs().queueReads(kGpiobMis, {0x1, 0x1});
  EXPECT_EQ(s.erase(1), fw::Status::Ok);
  EXPECT_TRUE(regs().writes(kGpiobDoutset).empty());
}

}  // namespace
}  // namespace bsp::mspm0::test
