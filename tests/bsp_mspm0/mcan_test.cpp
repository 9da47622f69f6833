// Register-level tests of the MCAN driver (bsp/mspm0/mcan.*) on the twin's MCAN (bsp/twin/periph/mcan.hpp:
// clock before divider, INIT read-back, line held until EOI, frames on a 500 kbit/s bus at their real length,
// other nodes' frames through the filters into RX FIFO 0, bus-off and its recovery), clocked by the twin's
// HFXT as the G3507 boards start it. Addresses:
// CANFD0_BASE 0x40508000 + the MCAN.* offsets of mspm0g3507.tsv (message RAM at the base), MCANSS_EOI at
// 0x7220 (TI MSPM0 SDK hw_mcan.h); bit timing from TI's bq79616_uart_to_can configuration (MSPM0 SDK 2.09);
// element layout from the tsv "MCAN TX element" rows; the standard filter element and SIDFC from TI's
// dl_mcan.c (MCANSS_STD_ID_FILTER_* shifts: SFT 30, SFEC 27, SFID1 16, SFID2 0) and hw_mcan.h (SIDFC FLSSA at
// bit 2, LSS at 16; IR RF0N bit 0, RF0L bit 3; GFC ANFS at bit 4).
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <vector>

#include "fixture.hpp"
#include "mcan.hpp"
#include "sysclock.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kBase = 0x40508000;
constexpr uintptr_t kCccr = kBase + 0x7018;
constexpr uintptr_t kNbtp = kBase + 0x701C;
constexpr uintptr_t kIr = kBase + 0x7050;
constexpr uintptr_t kIe = kBase + 0x7054;
constexpr uintptr_t kIle = kBase + 0x705C;
constexpr uintptr_t kGfc = kBase + 0x7080;
constexpr uintptr_t kSidfc = kBase + 0x7084;
constexpr uintptr_t kRxf0c = kBase + 0x70A0;
constexpr uintptr_t kRxf0s = kBase + 0x70A4;
constexpr uintptr_t kRxf0a = kBase + 0x70A8;
constexpr uintptr_t kTxbc = kBase + 0x70C0;
constexpr uintptr_t kTxfqs = kBase + 0x70C4;
constexpr uintptr_t kTxbar = kBase + 0x70D0;
constexpr uintptr_t kTxbto = kBase + 0x70D8;
constexpr uintptr_t kSsEoi = kBase + 0x7220;
constexpr uintptr_t kWrapIclr = kBase + 0x7848;
constexpr uintptr_t kWrapImask = kBase + 0x7828;
constexpr uintptr_t kWrapMis = kBase + 0x7838;
constexpr uintptr_t kClkEn = kBase + 0x7900;
constexpr uintptr_t kClkDiv = kBase + 0x7904;
constexpr uint32_t kEoiLine0 = 0x01;  // hw_mcan.h MCAN_EOI: 0x01 clears the MCAN(0) (line 0) interrupt

// MCAN_IR_* bits.
constexpr uint32_t kRf0n = 1U << 0;
constexpr uint32_t kRf0l = 1U << 3;
constexpr uint32_t kTc = 1U << 9;
constexpr uint32_t kBo = 1U << 25;

class McanTest : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    startClock();
    ASSERT_EQ(can.init(), fw::Status::Ok);
    regs().clearLog();
  }
  // CANCLK from the 40 MHz HFXT (PA5/PA6), as the G3507 boards start it; the bus runs at 500 kbit/s.
  void startClock() {
    ASSERT_EQ(startHfxt(Pin{0, 5, 10}, Pin{0, 6, 11}), fw::Status::Ok);
    chip().mcan()->setBus(500000);
  }
  bool interruptPending() { return regs().peek(kWrapMis) != 0; }
  // The CPU takes the CANFD0 interrupt whenever the wrapper asserts it, until `until()` or `maxUs`.
  bool serve(const std::function<bool()>& until, uint64_t maxUs = 5000) {
    return regs().runUntil(
        [&] {
          if (interruptPending()) can.onInterrupt();
          return until();
        },
        maxUs);
  }
  bool sendAndServe(const fw::hal::CanFrame& frame) {
    const uint64_t before = can.counters().txFrames;
    if (can.send(frame) != fw::Status::Ok) return false;
    return serve([&] { return can.counters().txFrames > before; });
  }
  // Another node sends `frame`; the CPU services what it raises.
  void peer(const fw::hal::CanFrame& frame) {
    const uint64_t before = chip().mcan()->peerFrames();
    chip().mcan()->peerSend(frame);
    serve([&] { return chip().mcan()->peerFrames() > before; });
  }

  static constexpr uint32_t kAccepted[] = {0x123, 0x124};
  McanBus can{{kBase, 6, PinFunction{Pin{0, 12, 34}, 5}, PinFunction{Pin{0, 13, 35}, 6}, McanBus::kNbtp500k,
               kAccepted}};
  int events = 0;
};

TEST_F(McanTest, InitProgramsClassic500kAt87_5PercentInConfigurationMode) {
  RegisterTest::SetUp();
  startClock();
  McanBus fresh(
      {kBase, 6, PinFunction{Pin{0, 12, 34}, 5}, PinFunction{Pin{0, 13, 35}, 6}, McanBus::kNbtp500k});
  ASSERT_EQ(fresh.init(), fw::Status::Ok);
  // NBRP 0, NTSEG1 68, NTSEG2 9, NSJW 9 (register values of TI's example): 1 + 69 + 10 = 80 tq of 25 ns at
  // 40 MHz = 500 kbit/s, sample point 70 / 80 = 87.5 % (the twin checks it against the bus: WIRE-CAN-*).
  EXPECT_EQ(regs().lastWrite(kNbtp), (9U << 25) | (0U << 16) | (68U << 8) | 9U);
  // Module clock requested before its divider is set (TI's DL_MCAN_enableModuleClock, then
  // DL_MCAN_setClockConfig); INIT, then INIT|CCE, configuration, then INIT cleared to join the bus.
  EXPECT_TRUE(regs().wroteInOrder(
      {{kClkEn, 1}, {kClkDiv, 0}, {kCccr, 0x1}, {kCccr, 0x3}, {kNbtp, 0x12004409}, {kCccr, 0x0}}));
  // init() returns only once CCCR.INIT has read back 0 (TI's example polls DL_MCAN_getOpMode for NORMAL).
  EXPECT_EQ(regs().peek(kCccr) & 1U, 0U);
  EXPECT_EQ(regs().lastWrite(kTxbc), 8U << 24);             // TFQS 8, TFQM 0 (FIFO), TBSA 0
  EXPECT_EQ(regs().lastWrite(kRxf0c), 0x80U | (8U << 16));  // F0SA 0x80, F0S 8
  // ANFS = ANFE = 2 (reject what no filter element stores), RRFS = RRFE = 1 (reject remote frames).
  EXPECT_EQ(regs().lastWrite(kGfc), 0x2BU);
  EXPECT_EQ(regs().lastWrite(kSidfc), 0x100U);  // FLSSA 0x100, no element: nothing is received
  EXPECT_EQ(regs().lastWrite(kIe), kRf0n | kRf0l | kTc | (1U << 23) | kBo);
  EXPECT_EQ(regs().lastWrite(kIle), 0x1U);
  EXPECT_EQ(regs().lastWrite(kWrapImask), 0x1U);
  EXPECT_EQ(regs().lastWrite(0xE000E100), 1U << 6);  // CANFD0 is IRQ 6 (tsv irq rows)
}

TEST_F(McanTest, InitWithoutMessageRamIsNotReady) {
  // A board whose HFXT never starts: no CANCLK, so MEM_INIT_DONE never comes (bounded wait).
  RegisterTest::SetUp();
  chip().sysctl().removeCrystal();
  EXPECT_EQ(startHfxt(Pin{0, 5, 10}, Pin{0, 6, 11}), fw::Status::Timeout);
  McanBus fresh(
      {kBase, 6, PinFunction{Pin{0, 12, 34}, 5}, PinFunction{Pin{0, 13, 35}, 6}, McanBus::kNbtp500k});
  EXPECT_EQ(fresh.init(), fw::Status::NotReady);
  fw::hal::CanFrame frame;
  EXPECT_EQ(fresh.send(frame), fw::Status::NotReady);
}

TEST_F(McanTest, InitThatNeverLeavesInitIsNotReady) {
  RegisterTest::SetUp();
  startClock();
  chip().mcan()->holdInit();  // CCCR.INIT never reads back 0
  McanBus fresh(
      {kBase, 6, PinFunction{Pin{0, 12, 34}, 5}, PinFunction{Pin{0, 13, 35}, 6}, McanBus::kNbtp500k});
  EXPECT_EQ(fresh.init(), fw::Status::NotReady);  // bounded wait, then give up
  EXPECT_EQ(regs().peek(kCccr) & 1U, 1U);
  fw::hal::CanFrame frame;
  EXPECT_EQ(fresh.send(frame), fw::Status::NotReady);
}

// A board without its crystal never calls init() (board_g3507_can.cpp): the publisher and the command link
// still ask the bus for its state and for frames. The peripheral is unpowered then, and its registers may not
// be read (the twin stopped an image at the PSR read); off the bus, nothing received, nothing touched.
TEST_F(McanTest, AControllerNeverInitialisedIsOffTheBusAndTouchesNoRegister) {
  McanBus never(
      {kBase, 6, PinFunction{Pin{0, 12, 34}, 5}, PinFunction{Pin{0, 13, 35}, 6}, McanBus::kNbtp500k});
  regs().clearLog();
  EXPECT_EQ(never.state(), fw::hal::CanState::BusOff);
  fw::hal::CanFrame frame;
  EXPECT_FALSE(never.receive(frame));
  EXPECT_EQ(never.send(frame), fw::Status::NotReady);
  EXPECT_EQ(never.recover(), fw::Status::NotReady);
  EXPECT_TRUE(regs().log().empty()) << regs().log().size() << " register accesses";
}

TEST_F(McanTest, TransmitWritesTheElementAtThePutIndexAndRequestsIt) {
  fw::hal::CanFrame first;
  ASSERT_TRUE(sendAndServe(first));
  ASSERT_TRUE(sendAndServe(first));  // two frames sent: the put index (TXFQS.TFQPI) is 2
  regs().clearLog();
  fw::hal::CanFrame frame;
  frame.id = 0x004;
  frame.dlc = 8;
  frame.data = {0x16, 0xC0, 0x16, 0xBC, 0x16, 0xB4, 0x16, 0xB9};
  ASSERT_EQ(can.send(frame), fw::Status::Ok);
  constexpr uintptr_t element = kBase + 0x000 + 2 * 16;   // TX FIFO at byte 0, 16-byte elements
  EXPECT_EQ(regs().lastWrite(element), 0x004U << 18);     // T0: standard ID in 28:18
  EXPECT_EQ(regs().lastWrite(element + 4), 8U << 16);     // T1: DLC 19:16, FDF 0, BRS 0
  EXPECT_EQ(regs().lastWrite(element + 8), 0xBC16C016U);  // data bytes 0..3, byte 0 in bits 7:0
  EXPECT_EQ(regs().lastWrite(element + 12), 0xB916B416U);
  EXPECT_EQ(regs().lastWrite(kTxbar), 1U << 2);
  EXPECT_GT(regs().findWrite(kTxbar, 1U << 2), regs().findWrite(element + 12, 0xB916B416U));

  std::vector<fw::hal::CanFrame> wire;
  chip().mcan()->onFrame([&](const twin::CanWireFrame& f) { wire.push_back(f.frame); });
  ASSERT_TRUE(serve([&] { return can.counters().txFrames == 3; }));
  EXPECT_NE(regs().peek(kTxbto) & (1U << 2), 0U);
  EXPECT_EQ(regs().lastWrite(kIr), kTc);  // IR is write-1-to-clear: exactly the handled bit
  EXPECT_EQ(regs().lastWrite(kWrapIclr), 0x1U);
  ASSERT_EQ(wire.size(), 1U);
  EXPECT_EQ(wire[0].id, 0x004U);
  EXPECT_EQ(wire[0].data, frame.data);
}

TEST_F(McanTest, EachServicedInterruptEndsWithEoiSoTheNextOneArrives) {
  fw::hal::CanFrame frame;
  ASSERT_TRUE(sendAndServe(frame));
  // The wrapper clear (ICLR), then IR cleared, then MCANSS_EOI = 0x01 for line 0, as TI's
  // DL_MCAN_clearIntrStatus does after every ISR: the line drops and nothing is pending any more.
  EXPECT_TRUE(regs().wroteInOrder({{kWrapIclr, 0x1}, {kIr, kTc}, {kSsEoi, kEoiLine0}}));
  EXPECT_EQ(chip().mcan()->awaitingEoiCycles(0), 0U);
  EXPECT_FALSE(interruptPending());

  // The next transmission interrupts again (without the EOI the wrapper would hold the first one forever).
  ASSERT_TRUE(sendAndServe(frame));
  EXPECT_FALSE(interruptPending());
  EXPECT_EQ(regs().writes(kSsEoi), (std::vector<uint32_t>{kEoiLine0, kEoiLine0}));
}

TEST_F(McanTest, AnEventDuringTheHandlerInterruptsAgainAfterEoi) {
  // The controller reports bus-off while the handler clears TC: IR keeps BO, so the EOI asserts the line
  // again (hw_mcan.h MCAN_EOI) and the handler runs a second time for it.
  can.onEvent(counter(events));
  regs().onWrite(kIr, [this](uint32_t cleared) {
    if (cleared == kTc) chip().mcan()->injectBusOff();
  });
  fw::hal::CanFrame frame;
  ASSERT_EQ(can.send(frame), fw::Status::Ok);
  ASSERT_TRUE(regs().runUntil([this] { return interruptPending(); }, 2000));
  can.onInterrupt();
  EXPECT_TRUE(interruptPending());
  can.onInterrupt();
  EXPECT_EQ(regs().peek(kIr) & (kTc | kBo), 0U);
  EXPECT_FALSE(interruptPending());
  EXPECT_EQ(events, 2);
}

TEST_F(McanTest, ExtendedIdAndBadFrames) {
  fw::hal::CanFrame frame;
  frame.extended = true;
  frame.id = 0x18FF50E5;
  frame.dlc = 2;
  ASSERT_EQ(can.send(frame), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kBase), (1U << 30) | 0x18FF50E5U);  // XTD bit 30, ID 28:0
  frame.dlc = 9;
  EXPECT_EQ(can.send(frame), fw::Status::InvalidArgument);
  frame.dlc = 1;
  frame.extended = false;
  frame.id = 0x800;
  EXPECT_EQ(can.send(frame), fw::Status::InvalidArgument);
}

TEST_F(McanTest, FullTxFifoIsOverflowAndCounted) {
  // Frames queued faster than the bus carries them (250 us each): the 8-element FIFO (TXBC.TFQS) fills.
  fw::hal::CanFrame frame;
  int sent = 0;
  while (sent < 20 && can.send(frame) == fw::Status::Ok)
    ++sent;
  EXPECT_EQ(sent, 8);
  EXPECT_NE(regs().peek(kTxfqs) & (1U << 21), 0U);  // TFQF
  EXPECT_EQ(regs().writes(kTxbar).size(), 8U);
  EXPECT_EQ(can.counters().txOverflows, 1U);
}

TEST_F(McanTest, BusOffRefusesFramesNotifiesAndRecoversByLeavingInit) {
  can.onEvent(counter(events));
  chip().mcan()->injectBusOff();  // PSR.BO, and the controller sets INIT itself
  ASSERT_TRUE(interruptPending());
  can.onInterrupt();
  EXPECT_EQ(events, 1);
  EXPECT_EQ(can.counters().busOffEvents, 1U);
  EXPECT_EQ(can.state(), fw::hal::CanState::BusOff);
  fw::hal::CanFrame frame;
  EXPECT_EQ(can.send(frame), fw::Status::BusOff);

  EXPECT_EQ(can.recover(), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kCccr), 0x0U);  // INIT cleared: 129 x 11 recessive bits, then error active
  ASSERT_TRUE(serve([this] { return events == 2; }));  // BO changes again when the controller leaves bus-off
  EXPECT_EQ(events, 2);
  EXPECT_EQ(can.counters().busOffEvents, 1U);
  EXPECT_EQ(can.state(), fw::hal::CanState::ErrorActive);
}

TEST_F(McanTest, ReceivePopsFifoZeroInOrderAndAcknowledges) {
  fw::hal::CanFrame frame;
  fw::hal::CanFrame sent;
  sent.id = 0x124;
  for (int i = 0; i < 3; ++i) {  // three frames taken: the get index is 3
    peer(sent);
    ASSERT_TRUE(can.receive(frame));
  }
  sent.id = 0x123;
  sent.dlc = 3;
  sent.data = {0xAA, 0xBB, 0xCC};
  peer(sent);
  regs().clearLog();
  ASSERT_TRUE(can.receive(frame));
  EXPECT_EQ(frame.id, 0x123U);
  EXPECT_FALSE(frame.extended);
  EXPECT_EQ(frame.dlc, 3);
  EXPECT_EQ(frame.data[0], 0xAA);
  EXPECT_EQ(frame.data[2], 0xCC);
  EXPECT_EQ(regs().lastWrite(kRxf0a), 3U);
  EXPECT_GE(regs().findWrite(kRxf0a, 3U), 0);
  EXPECT_FALSE(can.receive(frame));
  EXPECT_EQ(can.counters().rxFrames, 4U);
}

// The filter element TI's mcan_message_rx example adds (SFT 1 dual ID, SFEC 1 FIFO 0, SFID1 3, SFID2 4).
static_assert(reg::mcan::stdFilterDual(3, 4) == 0x48030004U);

TEST_F(McanTest, FiltersAcceptExactlyTheConfiguredIdentifiersIntoFifoZero) {
  RegisterTest::SetUp();
  startClock();
  static constexpr uint32_t kIds[] = {0x600, 0x601, 0x602, 0x603, 0x604, 0x605, 0x606};
  McanBus fresh(
      {kBase, 6, PinFunction{Pin{0, 12, 34}, 5}, PinFunction{Pin{0, 13, 35}, 6}, McanBus::kNbtp500k, kIds});
  ASSERT_EQ(fresh.init(), fw::Status::Ok);
  // Four dual-ID elements at 0x100 (the last repeats 0x606), storing to RX FIFO 0; SIDFC FLSSA 0x100, LSS 4.
  EXPECT_EQ(regs().lastWrite(kBase + 0x100), 0x4E000601U);
  EXPECT_EQ(regs().lastWrite(kBase + 0x104), 0x4E020603U);
  EXPECT_EQ(regs().lastWrite(kBase + 0x108), 0x4E040605U);
  EXPECT_EQ(regs().lastWrite(kBase + 0x10C), 0x4E060606U);
  EXPECT_EQ(regs().lastWrite(kSidfc), 0x100U | (4U << 16));
  EXPECT_EQ(regs().lastWrite(kGfc), 0x2BU);  // everything else rejected by the hardware
  // Filters and global filter are set while the controller is in INIT with CCE (protected registers).
  EXPECT_TRUE(regs().wroteInOrder({{kCccr, 0x3},
                                   {kGfc, 0x2B},
                                   {kBase + 0x10C, 0x4E060606U},
                                   {kSidfc, 0x100U | (4U << 16)},
                                   {kCccr, 0x0}}));
  // On the bus: 0x606 is stored, 0x607 rejected by the hardware (no trace, no interrupt).
  fw::hal::CanFrame frame;
  frame.id = 0x606;
  chip().mcan()->peerSend(frame);
  frame.id = 0x607;
  chip().mcan()->peerSend(frame);
  regs().advanceUs(1000);
  EXPECT_EQ(chip().mcan()->framesReceived(), 1U);
  EXPECT_EQ(chip().mcan()->framesRejected(), 1U);
}

TEST_F(McanTest, MoreIdentifiersThanFilterElementsIsRefused) {
  RegisterTest::SetUp();
  startClock();
  static constexpr uint32_t kIds[17] = {};
  McanBus fresh(
      {kBase, 6, PinFunction{Pin{0, 12, 34}, 5}, PinFunction{Pin{0, 13, 35}, 6}, McanBus::kNbtp500k, kIds});
  EXPECT_EQ(fresh.init(), fw::Status::InvalidArgument);
}

TEST_F(McanTest, ANewMessageWakesTheReceiverAloneAndIsAcknowledged) {
  int received = 0;
  can.onEvent(counter(events));
  can.onReceive(counter(received));
  fw::hal::CanFrame frame;
  frame.id = 0x123;
  peer(frame);
  EXPECT_EQ(received, 1);
  EXPECT_EQ(events, 0);  // the transmit side is not woken by a reception
  // The wrapper's line flag, IR (exactly RF0N, write 1 to clear), then EOI line 0: TI's
  // DL_MCAN_clearIntrStatus order.
  EXPECT_TRUE(regs().wroteInOrder({{kWrapIclr, 0x1}, {kIr, kRf0n}, {kSsEoi, kEoiLine0}}));
  EXPECT_FALSE(interruptPending());
  ASSERT_TRUE(sendAndServe(frame));
  EXPECT_EQ(received, 1);
  EXPECT_EQ(events, 1);
}

TEST_F(McanTest, AFrameLostToAFullFifoIsCounted) {
  int received = 0;
  can.onReceive(counter(received));  // notified, but nobody reads the frames: the 8-element FIFO fills
  fw::hal::CanFrame frame;
  frame.id = 0x123;
  for (int i = 0; i < 9; ++i)
    peer(frame);
  EXPECT_EQ(can.counters().rxLost, 1U);
  EXPECT_EQ(received, 8);
  EXPECT_EQ(regs().lastWrite(kIr), kRf0l);
}

}  // namespace
}  // namespace bsp::mspm0::test
