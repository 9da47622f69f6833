// Register-level tests of the window watchdog and its stack guard (bsp/mspm0/watchdog.*) on the twin's WWDT0
// (bsp/twin/periph/wwdt.hpp: the period from LFCLK, a restart with another value or the period expiring is a
// violation, which resets the chip). Addresses: WWDT0_BASE 0x40080000 + WWDT.* offsets; fields
// WWDT_WWDTCTL0_* and note "WWDT restart" (mspm0l1306.tsv).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "fixture.hpp"
#include "watchdog.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kBase = 0x40080000;
constexpr uintptr_t kCtl0 = kBase + 0x1100;
constexpr uintptr_t kCntRst = kBase + 0x1108;

class WatchdogTest : public RegisterTest {
 protected:
  std::array<uint32_t, kStackGuardWords> guard{kStackGuardPattern, kStackGuardPattern};
  WindowWatchdog watchdog{kBase, guard.data()};
};

TEST_F(WatchdogTest, StartSelectsAOneSecondPeriodWithoutClosedWindow) {
  watchdog.start();
  // KEY 0xC9 | PER 3 (2^15 counts) in bits 6:4 | CLKDIV 0 | WINDOW0 0 | MODE 0: 2^15 / 32768 Hz = 1 s.
  EXPECT_EQ(regs().lastWrite(kCtl0), 0xC9000030U);
  EXPECT_EQ(regs().lastWrite(kBase + 0x800), 0x26000001U);
}

TEST_F(WatchdogTest, FeedRestartsTheCounter) {
  watchdog.start();
  watchdog.feed();
  EXPECT_EQ(regs().lastWrite(kCntRst), 0xA7U);
}

TEST_F(WatchdogTest, FedEveryHalfSecondTheChipRunsOnAndUnfedItResetsAfterOneSecond) {
  // The period: 2^15 LFCLK counts, 1 s (hw_wwdt.h WWDTCTL0.PER; SLAU847D WWDT); a WWDT0 violation is a
  // BOOTRST (the twin's reset log: the power-on, then each reset).
  watchdog.start();
  for (int i = 0; i < 6; ++i) {
    regs().advanceUs(500000);
    watchdog.feed();
  }
  EXPECT_EQ(chip().machine().resets().size(), 1U) << "3 s fed: no reset";
  regs().advanceUs(990000);
  EXPECT_EQ(chip().machine().resets().size(), 1U);
  regs().advanceUs(20000);
  EXPECT_EQ(chip().machine().resets().size(), 2U) << "1 s after the last feed";
}

TEST_F(WatchdogTest, FeedWithAnOverwrittenGuardFaultsInsteadOfFeeding) {
  guard[1] = 0;  // the stack ran into the guard
  EXPECT_FALSE(watchdog.stackGuardIntact());
  EXPECT_DEATH(watchdog.feed(), "FW_ASSERT failed: module 30");
}

}  // namespace
}  // namespace bsp::mspm0::test
