// Bring-up of the LP-MSPM0L1306 board (images/common/board_l1306_i2c_slcan.cpp with the board_config.hpp of
// lp-mspm0l1306-bq76952) on the register model: the pins, settings and interrupt paths the image programs,
// checked against TI's LaunchPad facts, the twin's SYSCTL, IOMUX, GPIO, UART, DMA and
// I2C.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "board_l1306_i2c_slcan.hpp"
#include "chip/mspm0l1306.hpp"
#include "fixture.hpp"
#include "sysclock.hpp"

extern "C" {
uint32_t __stack_limit__[2];  // the linker symbol the watchdog's stack guard reads on the target
void UART0_IRQHandler();
void GROUP1_IRQHandler();
}

namespace bsp::mspm0::test {
namespace {

using Chip = chip::Mspm0l1306;
constexpr uintptr_t pincm(uint32_t n) {
  return 0x40428000 + 4 * n;
}
constexpr uint32_t kBq769x2StretchLimitUs = 4000;  // board_config.hpp: the BQ769x2 stretches SCL up to 4 ms

class L1306BoardTest : public RegisterTest {
 protected:
  L1306BoardTest() : RegisterTest(twin::Part::L1306) {}
  void SetUp() override {
    RegisterTest::SetUp();
    chip().uart(0).onTransmit([this](uint8_t b) { sent.push_back(b); });
    image::bringUp();
  }

  std::vector<uint8_t> sent;  // what UART0 put on the line
  int calls = 0;
};

TEST_F(L1306BoardTest, TheSysoscRunsInFclModeOnTheRoscResistor) {
  // SYSOSCFCLCTL = KEY 0x2A | SETUSEFCL (the L13xx's FCL always uses the external ROSC resistor:
  // dl_sysctl_mspm0l11xx_l13xx.h DL_SYSCTL_enableSYSOSCFCLExternalResistor).
  EXPECT_EQ(regs().lastWrite(0x400AF000 + 0x1310), 0x2A000001U);
  EXPECT_NE(regs().peek(0x400AF000 + 0x1204) & (1U << 24), 0U);  // CLKSTATUS.FCLMODE
}

TEST_F(L1306BoardTest, SlcanLeavesOnTheBackChannelPinPa8) {
  // The LP-MSPM0L1306's XDS110 back-channel is UART0 TX on PA8 = PINCM9, PF 2 (mspm0l130x.h
  // IOMUX_PINCM9_PF_UART0_TX; TI's LP_MSPM0L1306 uart_tx_console_multibyte_repeated_fifo_dma README: jumpers
  // J16 1:2 and J101 9:10). PA23 (PINCM24) reaches only BoosterPack pin J2_12, so it is left alone.
  EXPECT_EQ(regs().lastWrite(pincm(9)), 0x80U | 2U);
  EXPECT_FALSE(regs().lastWrite(pincm(24)).has_value());
}

TEST_F(L1306BoardTest, SlcanTextReachesTheLineAndCompletesAtEndOfTransmission) {
  const std::array<uint8_t, 6> text{'t', '1', '0', '0', '0', '\r'};
  regs().dmaBuffer(std::span<const uint8_t>(text));
  ASSERT_EQ(image::board().serial.write(text, counter(calls)), fw::Status::Ok);
  regs().advanceUs(1000);  // six frames at 115200 Bd
  EXPECT_EQ(sent, std::vector<uint8_t>(text.begin(), text.end()));
  UART0_IRQHandler();
  EXPECT_EQ(calls, 1);
}

TEST_F(L1306BoardTest, ALineStillShiftingWhenTheDmaIsDoneCompletesAtEndOfTransmission) {
  // The usual case on the part: DMA_DONE_TX comes with the last bytes still in the 4-entry FIFO, so the line
  // completes at EOT, which the UART raises only with CTL0.RXE set as well (UART_ERR_02, twin
  // periph/uart.hpp).
  const std::array<uint8_t, 6> text{'t', '1', '0', '0', '0', '\r'};
  regs().dmaBuffer(std::span<const uint8_t>(text));
  ASSERT_EQ(image::board().serial.write(text, counter(calls)), fw::Status::Ok);
  ASSERT_TRUE(regs().runUntil([this] { return sent.size() == 2; }, 1000));  // the DMA has moved all six
  UART0_IRQHandler();
  EXPECT_EQ(calls, 0) << "not done while bytes are still on their way";
  regs().advanceUs(1000);
  UART0_IRQHandler();
  EXPECT_EQ(sent.size(), text.size());
  EXPECT_EQ(calls, 1);
}

TEST_F(L1306BoardTest, AlertIsAFallingEdgeInputWithThePullUpAndReachesItsHandler) {
  // The BQ76952 ALERT, configured active-low open-drain by the BQ769x2-family images, on PA15 (PINCM16): its
  // fall reaches the handler, and released it reads high on the MCU's pull-up.
  image::board().alert.enable(counter(calls));
  chip().pins().setExternal(16, twin::Drive::Low);
  GROUP1_IRQHandler();
  EXPECT_EQ(calls, 1);
  chip().pins().setExternal(16, twin::Drive::None);
  EXPECT_TRUE(image::board().alert.level());
  EXPECT_TRUE(chip().pins().floatingReads().empty());
  image::board().alert.disable();
}

TEST_F(L1306BoardTest, I2cTimeoutIsTheStretchLimitWithinOneCount) {
  // TI's count of TIMEOUT_CTL.TCNTLA (the twin's I2C, bsp/twin/periph/i2c.hpp): 4 ms at 400 kHz is 84 counts
  // of 48 us = 4.03 ms (the old 247 counts were 11.9 ms). Measured on the twin (one SCL period of the START
  // included: 2.5 us at 400 kHz).
  const uint64_t us = i2cTimeoutOnTheTwinUs(image::board().i2c);
  EXPECT_GE(us, kBq769x2StretchLimitUs);
  EXPECT_LT(us, kBq769x2StretchLimitUs + 48);
  regs().takeViolations();  // the controller is left waiting on the held SCL
}

TEST_F(L1306BoardTest, TheStandbyIdleCountsTimg1OnLfclkAndSelectsStandby1) {
  // BSP_DEEP_IDLE=1 (the image's options.cmake): TIMG1 (0x40086000, IRQ 2: mspm0l130x.h) counts LFCLK
  // (CLKSEL.LFCLK_SEL bit 1, hw_gptimer.h) up from zero, free-running over 16 bits; its NVIC line is enabled
  // (ISER bit 2) so that its compare wakes the core; SCR.SLEEPDEEP is to enter STANDBY1: PMODECFG (0x1140)
  // DSLEEP = STANDBY (1) and MCLKCFG (0x1104) STOPCLKSTBY (bit 21) (hw_sysctl_mspm0l11xx_l13xx.h); the
  // scheduler gets the policy from the board.
  static_assert(BSP_DEEP_IDLE == 1, "the lp-mspm0l1306-bq76952 options turn the policy on");
  constexpr uintptr_t kTimg1 = 0x40086000;
  EXPECT_EQ(regs().lastWrite(kTimg1 + 0x1008), 1U << 1);
  EXPECT_EQ(regs().lastWrite(kTimg1 + 0x1808), 0xFFFFU);
  const auto ctrctl = regs().lastWrite(kTimg1 + 0x1804);
  ASSERT_TRUE(ctrctl.has_value());
  EXPECT_EQ(*ctrctl & 0x1U, 1U) << "counting";
  EXPECT_EQ(*ctrctl & 0x30U, 0x20U) << "up";
  const auto iser = regs().writes(0xE000E100);
  EXPECT_NE(std::find(iser.begin(), iser.end(), 1U << 2), iser.end()) << "TIMG1's NVIC line enabled";
  EXPECT_EQ(regs().lastWrite(0x400AF000 + 0x1140), 1U);
  const auto mclkcfg = regs().lastWrite(0x400AF000 + 0x1104);
  ASSERT_TRUE(mclkcfg.has_value());
  EXPECT_NE(*mclkcfg & (1U << 21), 0U);
  EXPECT_NE(image::board().power, nullptr);
}

}  // namespace
}  // namespace bsp::mspm0::test
