// Bring-up of the LP-MSPM0G3507 board with a BQ79616 chain on UART0 (images/common/board_g3507_can.cpp with
// the board_config.hpp of lp-mspm0g3507-bq79616, default UART0_PA10_PA11) on the register model: the link's
// TX DMA and the nFAULT input, checked against the twin's SYSCTL, IOMUX, GPIO, UART and DMA.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "board_g3507_can.hpp"
#include "chip/mspm0g3507.hpp"
#include "fixture.hpp"

extern "C" {
uint32_t __stack_limit__[2];  // the linker symbol the watchdog's stack guard reads on the target
void UART0_IRQHandler();
void GROUP1_IRQHandler();
}

namespace bsp::mspm0::test {
namespace {

using Chip = chip::Mspm0g3507;

class G3507UartBoardTest : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    chip().uart(0).onTransmit([this](uint8_t b) { sent.push_back(b); });
    image::bringUp();
  }

  std::vector<uint8_t> sent;  // what UART0 put on the line
  int calls = 0;
};

TEST_F(G3507UartBoardTest, TheSysoscRunsInFclModeOnTheLaunchPadsRoscResistor) {
  // R8, 100 kOhm 0.1 % on ROSC (SLAU873D 2.7): SYSOSCFCLCTL = KEY 0x2A | SETUSEFCL | SETUSEEXRES
  // (dl_sysctl_mspm0g1x0x_g3x0x.h DL_SYSCTL_enableSYSOSCFCLExternalResistor).
  EXPECT_EQ(regs().lastWrite(0x400AF000 + 0x1310), 0x2A000003U);
  EXPECT_NE(regs().peek(0x400AF000 + 0x1204) & (1U << 24), 0U);  // CLKSTATUS.FCLMODE
}

TEST_F(G3507UartBoardTest, Bq79616FramesLeaveByDmaAtOneFreeEntry) {
  // The frame TI prints in its BQ79600-Q1 documents (SLUUC56B): single write of CONTROL1 = 0x20 to device 0.
  const std::array<uint8_t, 7> frame{0x90, 0x00, 0x03, 0x09, 0x20, 0x13, 0x95};
  fw::hal::UartExchange exchange;
  exchange.tx = frame;
  regs().dmaBuffer(std::span<const uint8_t>(frame));
  ASSERT_EQ(image::board().bq79616.start(exchange, counter(calls)), fw::Status::Ok);
  regs().advanceUs(100);  // seven frames at 1 Mbaud
  EXPECT_EQ(sent, std::vector<uint8_t>(frame.begin(), frame.end()));
  UART0_IRQHandler();  // EOT
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(exchange.status, fw::Status::Ok);
}

TEST_F(G3507UartBoardTest, NfaultIsAFallingEdgeInput) {
  // BQ79616 nFAULT: active low, driven by the device (high when no fault), on PB0 (PINCM12).
  chip().pins().setExternal(12, twin::Drive::High);
  image::board().nfault.enable(counter(calls));
  chip().pins().setExternal(12, twin::Drive::Low);
  GROUP1_IRQHandler();
  EXPECT_EQ(calls, 1);
  image::board().nfault.disable();
}

}  // namespace
}  // namespace bsp::mspm0::test
