// Register-level tests of the G3507's crystal start-up (bsp/mspm0/sysclock.*) against the twin's SYSCTL
// (bsp/twin/periph/sysctl.hpp: its rules, and HFCLKGOOD HFXTTIME after the start). Addresses: SYSCTL_BASE
// 0x400AF000 + the SYSCTL.SOCLOCK.* offsets of mspm0g3507.tsv; fields: its SYSCTL_HSCLKEN_*,
// SYSCTL_HFCLKCLKCFG_*, SYSCTL_GENCLKCFG_* rows; pins: its example row "HFXT" (PA5 PINCM10, PA6 PINCM11).
#include <gtest/gtest.h>

#include <cstdint>

#include "fixture.hpp"
#include "sysclock.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kSysctl = 0x400AF000;
constexpr uintptr_t kHsclken = kSysctl + 0x1108;
constexpr uintptr_t kHfclkclkcfg = kSysctl + 0x1110;
constexpr uintptr_t kGenclkcfg = kSysctl + 0x1138;
constexpr uintptr_t kClkstatus = kSysctl + 0x1204;
// HFXTRSEL 13:12 = 3 (32..48 MHz), HFXTTIME 7:0 = 10 (x 64 us), HFCLKFLTCHK bit 28 (start-up monitor).
constexpr uint32_t kRangeAndTime = 0x3000 | 10;
constexpr uint32_t kMonitor = 1U << 28;

constexpr uint32_t kFclMode = 1U << 24;  // CLKSTATUS.FCLMODE

class SysclockTest : public RegisterTest {
 protected:
  fw::Status start() { return startHfxt(Pin{0, 5, 10}, Pin{0, 6, 11}); }
};

TEST_F(SysclockTest, HfxtIsDisabledBeforeItIsConfiguredThenStartedAndMonitored) {
  // An earlier run started the HFXT in range 16..32 MHz with the longest start-up time, then a software
  // SYSRST (the fault path) kept the oscillator on (sysctl.hpp): the twin refuses new settings while it runs.
  twin::Machine& m = chip().machine();
  ASSERT_TRUE(m.map().store(kHfclkclkcfg, 4, 0x2000 | 0xFF));
  ASSERT_TRUE(m.map().store(kHsclken, 4, 1));
  m.reset(twin::ResetKind::Sysrst, "software SYSRST", twin::rstcause::kSysSoftware);
  EXPECT_EQ(start(), fw::Status::Ok);
  // TI's DL_SYSCTL_setHFCLKSourceHFXTParams: HFXTEN off, range and start-up time, HFXTEN on, then the
  // start-up monitor, then wait for HFCLKGOOD.
  EXPECT_TRUE(regs().wroteInOrder({{kHsclken, 0x0},
                                   {kHfclkclkcfg, kRangeAndTime},
                                   {kHsclken, 0x1},
                                   {kHfclkclkcfg, kRangeAndTime | kMonitor}}));
  EXPECT_EQ(regs().value(kGenclkcfg) & (1U << 8), 0U);  // CANCLKSRC 0 = HFCLK
  EXPECT_EQ(regs().lastWrite(0x40428028), 0U);          // PINCM10 (PA5, HFXIN): no digital function
  EXPECT_EQ(regs().lastWrite(0x4042802C), 0U);          // PINCM11 (PA6, HFXOUT)
}

TEST_F(SysclockTest, WithoutACrystalTheWaitIsBoundedAndTimesOut) {
  chip().sysctl().removeCrystal();
  EXPECT_EQ(start(), fw::Status::Timeout);
  EXPECT_EQ(regs().readCount(kClkstatus), 500U);  // ~5 ms of polls, then give up
}

TEST_F(SysclockTest, TheFclComesOnWithItsKeyAfterTheBaseFrequency) {
  // TI's order (SysConfig SYSCTL.Board.c.xdt): DL_SYSCTL_setSYSOSCFreq(BASE), then
  // DL_SYSCTL_enableSYSOSCFCLExternalResistor: SYSOSCFCLCTL = KEY 0x2A | SETUSEFCL | SETUSEEXRES on the G350x
  // (dl_sysctl_mspm0g1x0x_g3x0x.h).
  constexpr uintptr_t kSysosccfg = kSysctl + 0x1100, kFclctl = kSysctl + 0x1310;
  initSysosc(true,
             reg::sysctl::kFclKey | reg::sysctl::kFclSetUseFcl | reg::sysctl::kFclSetUseExternalResistor);
  EXPECT_EQ(regs().value(kSysosccfg) & 0x3U, 0U);  // FREQ 0: base, 32 MHz
  EXPECT_EQ(regs().lastWrite(kFclctl), 0x2A000003U);
  EXPECT_LT(regs().findWrite(kSysosccfg, 0), regs().findWrite(kFclctl, 0x2A000003U));
  EXPECT_NE(regs().peek(kClkstatus) & kFclMode, 0U);
}

TEST_F(SysclockTest, ABoardWithoutTheResistorLeavesTheFclOff) {
  initSysosc(true, 0);
  EXPECT_FALSE(regs().lastWrite(kSysctl + 0x1310).has_value());
  EXPECT_EQ(regs().peek(kClkstatus) & kFclMode, 0U);
}

}  // namespace
}  // namespace bsp::mspm0::test
