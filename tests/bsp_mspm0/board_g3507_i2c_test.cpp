// Bring-up of the LP-MSPM0G3507 board with the monitor on I2C0 (images/common/board_g3507_can.cpp with the
// board_config.hpp of lp-mspm0g3507-bq76952) on the register model: crystal, CAN, ALERT input and I2C
// timeout, checked against TI's facts and the twin's SYSCTL, IOMUX, GPIO, I2C and MCAN.
#include <gtest/gtest.h>

#include <cstdint>

#include "board_g3507_can.hpp"
#include "chip/mspm0g3507.hpp"
#include "fixture.hpp"
#include "sysclock.hpp"

extern "C" {
uint32_t __stack_limit__[2];  // the linker symbol the watchdog's stack guard reads on the target
void CANFD0_IRQHandler();
void GROUP1_IRQHandler();
}

namespace bsp::mspm0::test {
namespace {

using Chip = chip::Mspm0g3507;
constexpr uint32_t kBq769x2StretchLimitUs = 4000;  // board_config.hpp: the BQ769x2 stretches SCL up to 4 ms

class G3507I2cBoardTest : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    image::bringUp();
  }

  int calls = 0;
};

TEST_F(G3507I2cBoardTest, TheSysoscRunsInFclModeOnTheLaunchPadsRoscResistor) {
  // R8, 100 kOhm 0.1 % on ROSC (SLAU873D 2.7): SYSOSCFCLCTL = KEY 0x2A | SETUSEFCL | SETUSEEXRES
  // (dl_sysctl_mspm0g1x0x_g3x0x.h DL_SYSCTL_enableSYSOSCFCLExternalResistor).
  EXPECT_EQ(regs().lastWrite(0x400AF000 + 0x1310), 0x2A000003U);
  EXPECT_NE(regs().peek(0x400AF000 + 0x1204) & (1U << 24), 0U);  // CLKSTATUS.FCLMODE
}

TEST_F(G3507I2cBoardTest, CanRunsOnTheCrystalAndEveryInterruptIsAcknowledged) {
  ASSERT_EQ(image::board().canStatus, fw::Status::Ok);
  EXPECT_EQ(regs().peek(Chip::kCanfd0 + 0x7018) & 1U, 0U);  // CCCR.INIT: left before bring-up went on
  chip().mcan()->setBus(500000);
  fw::hal::CanFrame frame;
  frame.id = 0x100;
  frame.dlc = 1;
  for (int i = 0; i < 2; ++i) {
    ASSERT_EQ(image::board().can.send(frame), fw::Status::Ok);
    // The frame on the wire, IR.TC, the wrapper's line 0 (CPU_INT MIS 0x7838) to the handler.
    ASSERT_TRUE(regs().runUntil([] { return model().peek(Chip::kCanfd0 + 0x7838) != 0; }, 2000));
    CANFD0_IRQHandler();
    // MCANSS_EOI written: the next transmission can interrupt again.
    EXPECT_EQ(chip().mcan()->awaitingEoiCycles(0), 0U);
  }
  EXPECT_EQ(image::board().can.counters().txFrames, 2U);
}

TEST_F(G3507I2cBoardTest, AlertIsAFallingEdgeInputWithThePullUp) {
  // The BQ76952 ALERT, configured active-low open-drain by the BQ769x2-family images, on PB0 (PINCM12): its
  // fall reaches the handler, and released it reads high on the MCU's pull-up.
  image::board().alert.enable(counter(calls));
  chip().pins().setExternal(12, twin::Drive::Low);
  GROUP1_IRQHandler();
  EXPECT_EQ(calls, 1);
  chip().pins().setExternal(12, twin::Drive::None);
  EXPECT_TRUE(image::board().alert.level());
  EXPECT_TRUE(chip().pins().floatingReads().empty());
  image::board().alert.disable();
}

TEST_F(G3507I2cBoardTest, I2cTimeoutIsTheStretchLimitWithinOneCount) {
  // TI's count of TIMEOUT_CTL.TCNTLA (the twin's I2C, bsp/twin/periph/i2c.hpp): 4 ms at 400 kHz is 84 counts
  // of 48 us = 4.03 ms (the old 247 counts were 11.9 ms). Measured on the twin (one SCL period of the START
  // included: 2.5 us at 400 kHz).
  const uint64_t us = i2cTimeoutOnTheTwinUs(image::board().i2c);
  EXPECT_GE(us, kBq769x2StretchLimitUs);
  EXPECT_LT(us, kBq769x2StretchLimitUs + 48);
  regs().takeViolations();  // the controller is left waiting on the held SCL
}

}  // namespace
}  // namespace bsp::mspm0::test
