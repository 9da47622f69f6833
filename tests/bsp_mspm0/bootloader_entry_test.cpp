// Register-level test of the software invoke of the ROM bootloader (bsp/mspm0/bootloader_entry.*). Addresses:
// SYSCTL_BASE 0x400AF000 + RESETLEVEL 0x1300 / RESETCMD 0x1304 (hw_sysctl_mspm0g1x0x_g3x0x.h and
// hw_sysctl_mspm0l11xx_l13xx.h, the same on both parts); values: RESETLEVEL_LEVEL_BOOTLOADERENTRY = 2,
// RESETCMD_KEY_VALUE 0xE4000000 | RESETCMD_GO_TRUE 1, in the order TI's DL_SYSCTL_resetDevice writes them.
#include <gtest/gtest.h>

#include <cstdint>

#include "bootloader_entry.hpp"
#include "fixture.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kResetLevel = 0x400AF000 + 0x1300;
constexpr uintptr_t kResetCmd = 0x400AF000 + 0x1304;

class BootloaderEntryTest : public RegisterTest {};

TEST_F(BootloaderEntryTest, SetsTheBootloaderEntryLevelThenIssuesTheResetWithItsKey) {
  requestBootloaderEntry();
  EXPECT_EQ(regs().writes(kResetLevel), std::vector<uint32_t>{2});
  EXPECT_EQ(regs().writes(kResetCmd), std::vector<uint32_t>{0xE4000001});
  EXPECT_TRUE(regs().wroteInOrder({{kResetLevel, 2}, {kResetCmd, 0xE4000001}}));
  EXPECT_EQ(regs().log().size(), 2U) << "nothing else is touched: the reset resets every peripheral";
}

}  // namespace
}  // namespace bsp::mspm0::test
