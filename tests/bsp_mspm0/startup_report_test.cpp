// The start-up report (bsp/mspm0/fault.hpp): RSTCAUSE read once against the twin's read-to-clear SYSCTL
// (bsp/twin/periph/sysctl.hpp), and which resets let the fault record count. Cause IDs: hw_sysctl_*.h
// SYSCTL_RSTCAUSE_ID_*; what each reset level resets: SLAU846B Table 2-12 / SLAU847D Table 2-9.
#include <gtest/gtest.h>

#include <cstdint>

#include "fault.hpp"
#include "fixture.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kRstcause = 0x400AF000 + 0x1220;

class StartupReportTest : public RegisterTest {};

TEST_F(StartupReportTest, TheResetCauseIsReadOnceAndTheReadClearsIt) {
  // The twin's WWDT0 violation: a BOOTRST with cause 0x0E (bsp/twin/periph/wwdt.hpp).
  chip().machine().reset(twin::ResetKind::Bootrst, "WWDT0 violation", twin::rstcause::kBootWwdt0);
  EXPECT_EQ(takeResetCause(), 0x0E);
  EXPECT_EQ(regs().readCount(kRstcause), 1U);
  EXPECT_EQ(takeResetCause(), 0x00) << "no reset since the last read";
}

TEST_F(StartupReportTest, OnlyTheIdFieldIsTaken) {
  regs().queueRead(kRstcause, 0xFFFFFF1B);  // reserved bits above RSTCAUSE.ID 4:0 (the twin reads them 0)
  EXPECT_EQ(takeResetCause(), 0x1B);
}

constexpr FaultRecord kRecord{true, fw::Module::BspI2c, 123};

TEST(StartupReport, AWatchdogResetIsABootrstThatLeavesNoRecord) {
  // "A WWDT0 violation generates a BOOTRST" (SLAU846B WWDT overview), and a BOOTRST resets SRAM: whatever
  // the .noinit words hold is not a record, even if its check word happens to match.
  const StartupReport r = startupReport(kResetCauseWwdt0, kRecord);
  EXPECT_EQ(r.resetCause, 0x0E);
  EXPECT_FALSE(r.fault.valid);
}

TEST(StartupReport, ASoftwareSysrstKeepsTheRecord) {
  const StartupReport r = startupReport(kResetCauseSysSoftware, kRecord);
  EXPECT_TRUE(r.fault.valid);
  EXPECT_EQ(r.fault.module, fw::Module::BspI2c);
  EXPECT_EQ(r.fault.line, 123);
}

TEST(StartupReport, SramSurvivesExactlyTheSysrstAndCpurstCauses) {
  for (uint8_t cause = 0; cause < 32; ++cause) {
    SCOPED_TRACE(static_cast<int>(cause));
    // POR 0x01..0x03, BOR 0x04/0x05, BOOTRST 0x08..0x0E reset SRAM; SYSRST 0x10..0x1B and CPURST 0x1C/0x1D
    // do not (SLAU846B Table 2-12).
    const bool kept = cause >= 0x10 && cause <= 0x1D;
    EXPECT_EQ(sramKept(cause), kept);
    EXPECT_EQ(startupReport(cause, kRecord).fault.valid, kept);
  }
  EXPECT_FALSE(startupReport(kResetCauseSysSoftware, FaultRecord{}).fault.valid) << "no record written";
}

}  // namespace
}  // namespace bsp::mspm0::test
