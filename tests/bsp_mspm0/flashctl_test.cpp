// FlashctlStorage (bsp/mspm0/flashctl.*) against a FLASHCTL register model written from TI's description:
// CMDEXEC runs the command set up in CMDTYPE/CMDADDR/CMDBYTEN/CMDDATA0-1 on a host buffer standing for the
// flash, fails with FAILWEPROT on a sector whose CMDWEPROTA bit is set, re-protects every sector after
// each command (TRM SLAU846A/SLAU847 FLASHCTL; hw_flashctl.h offsets and STATCMD fields).
#include <array>
#include <cstdint>

#include "fixture.hpp"
#include "flashctl.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kFc = 0x400CD000;  // FLASHCTL_BASE (tsv base rows)
constexpr uintptr_t kCmdexec = kFc + 0x1100, kCmdtype = kFc + 0x1104, kCmdaddr = kFc + 0x1120;
constexpr uintptr_t kCmdbyten = kFc + 0x1124, kData0 = kFc + 0x1130, kData1 = kFc + 0x1134;
constexpr uintptr_t kWeprotA = kFc + 0x11D0, kStatcmd = kFc + 0x13D0;
constexpr uint32_t kDone = 1, kPass = 2, kInProgress = 4, kFailWeProt = 0x10;
constexpr uint32_t kRegion = 0x7000;  // sectors 28..31 (bsp/mspm0/linker)

class Flashctl : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    flash_.fill(0xFF);
    regs().set(kWeprotA, ~0U);
    regs().onWrite(kCmdexec, [this](uint32_t) { execute(); });
  }
  // The controller: one command per CMDEXEC, as TI documents it.
  void execute() {
    ++commands_;
    const uint32_t addr = regs().value(kCmdaddr);
    const uint32_t sector = addr / 1024;
    const bool prot = ((regs().value(kWeprotA) >> sector) & 1U) != 0;
    regs().set(kWeprotA, ~0U);  // re-protected after every command
    if (hang_) {
      regs().set(kStatcmd, kInProgress);
      return;
    }
    if (prot) {
      regs().set(kStatcmd, kDone | kFailWeProt);
      return;
    }
    EXPECT_GE(addr, kRegion);
    EXPECT_LT(addr, kRegion + sizeof flash_);
    uint8_t* at = flash_.data() + (addr - kRegion);
    if (regs().value(kCmdtype) == 0x42) {  // ERASE SECTOR
      std::fill(at, at + 1024, 0xFF);
    } else {
      EXPECT_EQ(regs().value(kCmdtype), 0x01U);  // PROGRAM ONEWORD
      EXPECT_EQ(regs().value(kCmdbyten), ecc_ ? 0x1FFU : 0xFFU);
      const uint64_t v = regs().value(kData0) | uint64_t{regs().value(kData1)} << 32;
      for (unsigned i = 0; i < 8; ++i)
        at[i] &= static_cast<uint8_t>(v >> (8 * i));
    }
    regs().set(kStatcmd, kDone | kPass);
  }
  FlashctlStorage storage() { return FlashctlStorage({kFc, kRegion, flash_.data(), 4, ecc_, 32}); }

  std::array<uint8_t, 4096> flash_{};
  bool ecc_ = true;
  bool hang_ = false;
  int commands_ = 0;
};

constexpr std::array<uint8_t, 8> kWord{1, 2, 3, 4, 5, 6, 7, 8};

TEST_F(Flashctl, ProgramsAWordWithTheSectorUnprotectedRightBeforeExecute) {
  auto s = storage();
  EXPECT_EQ(s.program(1024 + 16, kWord), fw::Status::Ok);
  EXPECT_EQ(flash_[1024 + 16], 1);
  EXPECT_EQ(flash_[1024 + 23], 8);
  EXPECT_EQ(regs().lastWrite(kCmdaddr), 0x7410U);
  EXPECT_EQ(regs().lastWrite(kData0), 0x04030201U);
  EXPECT_EQ(regs().lastWrite(kData1), 0x08070605U);
  EXPECT_TRUE(regs().wroteInOrder({{kWeprotA, ~(1U << 29)}, {kCmdexec, 1}}));
}

TEST_F(Flashctl, TheL1306ProgramsWithoutTheEccByte) {
  ecc_ = false;
  auto s = storage();
  EXPECT_EQ(s.program(0, kWord), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kCmdbyten), 0xFFU);
}

TEST_F(Flashctl, ErasesASectorAndChecksItReadsErased) {
  flash_[3 * 1024 + 5] = 0;
  auto s = storage();
  EXPECT_EQ(s.erase(3), fw::Status::Ok);
  EXPECT_EQ(flash_[3 * 1024 + 5], 0xFF);
  EXPECT_EQ(regs().lastWrite(kCmdaddr), 0x7C00U);
  EXPECT_EQ(regs().lastWrite(kWeprotA), ~(1U << 31));
}

TEST_F(Flashctl, RefusesEverythingOutsideTheRegionAndUnerasedWords) {
  auto s = storage();
  EXPECT_EQ(s.erase(4), fw::Status::InvalidArgument);
  EXPECT_EQ(s.program(4096, kWord), fw::Status::InvalidArgument);
  EXPECT_EQ(s.program(4, kWord), fw::Status::InvalidArgument);
  flash_[9] = 0x7F;
  EXPECT_EQ(s.program(8, kWord), fw::Status::InvalidArgument);
  EXPECT_EQ(commands_, 0) << "no command reached the controller";
}

TEST_F(Flashctl, AFailureTheControllerReportsIsVerifyFailed) {
  auto s = storage();
  // The controller refuses (as with a sector left protected): the driver reports it, nothing written.
  regs().onWrite(kWeprotA, [this](uint32_t) { regs().set(kWeprotA, ~0U); });
  EXPECT_EQ(s.program(0, kWord), fw::Status::VerifyFailed);
  EXPECT_EQ(flash_[0], 0xFF);
}

TEST_F(Flashctl, AWordThatDoesNotTakeIsVerifyFailed) {
  auto s = storage();
  regs().onWrite(kCmdexec, [this](uint32_t) { flash_[3] = 0xFF; });  // one byte stays erased
  EXPECT_EQ(s.program(0, kWord), fw::Status::VerifyFailed);
}

TEST_F(Flashctl, TheWaitIsBoundedByTheDataSheetMaximum) {
  hang_ = true;
  auto s = storage();
  regs().clearLog();
  EXPECT_EQ(s.program(0, kWord), fw::Status::Timeout);
  // 275 us x 2 at 32 MHz, >= 4 cycles an iteration: 4400 STATCMD reads (computed).
  EXPECT_EQ(regs().readCount(kStatcmd), 4400U);
  regs().clearLog();
  EXPECT_EQ(s.erase(0), fw::Status::Timeout);
  EXPECT_EQ(regs().readCount(kStatcmd), 320000U);  // 20 ms x 2 at 32 MHz / 4 (computed)
}

}  // namespace
}  // namespace bsp::mspm0::test
