// The simulated CAN controller: frame length on the wire, queueing, bus-off and recovery.
#include <gtest/gtest.h>

#include "sim/can.hpp"
#include "sim/harness.hpp"

namespace {

using fw::Status;
using fw::hal::CanFrame;
using fw::hal::CanState;

TEST(SimCan, FrameBitsIncludeStuffingWithinTheIsoBounds) {
  for (uint8_t dlc = 0; dlc <= 8; ++dlc) {
    for (uint32_t id : {0x000u, 0x004u, 0x555u, 0x7FFu}) {
      CanFrame f{id, false, dlc, {0x16, 0xC0, 0x16, 0xBC, 0x00, 0x00, 0xFF, 0xFF}};
      const uint32_t bits = bsp::host::canFrameBits(f);
      const uint32_t unstuffed = 47 + 8U * dlc;  // incl. 3-bit intermission
      const uint32_t worst = unstuffed + (34 + 8U * dlc - 1) / 4;
      EXPECT_GE(bits, unstuffed) << id << " " << int(dlc);
      EXPECT_LE(bits, worst) << id << " " << int(dlc);
    }
  }
  // All-zero ID and data stuff every fifth bit.
  CanFrame zeros{0x000, false, 8, {}};
  EXPECT_GT(bsp::host::canFrameBits(zeros), 47u + 64u + 15u);
}

TEST(SimCan, FramesLeaveInOrderAtTheBitRate) {
  bsp::host::Harness h;
  bsp::host::SimCan can(h.clock, h.irq, 500000, 4);
  CanFrame a{0x004, false, 8, {0x16, 0xC0}}, b{0x005, false, 8, {}};
  EXPECT_EQ(can.send(a), Status::Ok);
  EXPECT_EQ(can.send(b), Status::Ok);
  h.runFor(fw::ms(5));
  ASSERT_EQ(can.sent().size(), 2u);
  EXPECT_EQ(can.sent()[0].frame.id, 0x004u);
  EXPECT_EQ(can.sent()[0].timeUs, bsp::host::canFrameBits(a) * 2u);
  EXPECT_EQ(can.counters().txFrames, 2u);
}

TEST(SimCan, FullQueueIsOverflowNotABlock) {
  bsp::host::Harness h;
  bsp::host::SimCan can(h.clock, h.irq, 500000, 2);
  CanFrame f{0x100, false, 1, {}};
  EXPECT_EQ(can.send(f), Status::Ok);
  EXPECT_EQ(can.send(f), Status::Ok);
  EXPECT_EQ(can.send(f), Status::Overflow);
  EXPECT_EQ(can.counters().txOverflows, 1u);
  EXPECT_EQ(can.send(CanFrame{0x800, false, 1, {}}), Status::InvalidArgument);
}

TEST(SimCan, BusOffRefusesFramesUntilRecoveryCompletes) {
  bsp::host::Harness h;
  bsp::host::SimCan can(h.clock, h.irq, 500000);
  int events = 0;
  can.onEvent(fw::hal::Notify{[](void* c, uint32_t) { ++*static_cast<int*>(c); }, &events});
  can.injectBusOff();
  EXPECT_EQ(can.state(), CanState::BusOff);
  EXPECT_EQ(events, 1);
  EXPECT_EQ(can.send(CanFrame{0x1, false, 0, {}}), Status::BusOff);
  EXPECT_EQ(can.recover(), Status::Ok);
  h.runFor(fw::us(2815));
  EXPECT_EQ(can.state(), CanState::BusOff) << "128 x 11 bits at 500 kbit/s take 2.816 ms";
  h.runFor(fw::us(2));
  EXPECT_EQ(can.state(), CanState::ErrorActive);
  EXPECT_EQ(can.send(CanFrame{0x1, false, 0, {}}), Status::Ok);
  EXPECT_EQ(can.counters().busOffEvents, 1u);
}

TEST(SimCan, ErrorFramesPassThroughErrorPassiveToBusOffAndFramesFlowAfterRecovery) {
  // ISO 11898-1 fault confinement: each destroyed transmission adds 8 to TEC; error passive at 128, bus-off
  // above 255 (the 32nd). After recovery the next frame goes out (it stayed queued forever before: the
  // transmission that ended in bus-off left the controller marked busy).
  bsp::host::Harness h;
  bsp::host::SimCan can(h.clock, h.irq, 500000);
  can.injectErrorFrames(40);
  EXPECT_EQ(can.send(CanFrame{0x100, false, 8, {}}), Status::Ok);
  h.runFor(fw::ms(20));
  EXPECT_EQ(can.state(), CanState::BusOff);
  EXPECT_TRUE(can.sent().empty());
  EXPECT_EQ(can.recover(), Status::Ok);
  h.runFor(fw::ms(3));
  ASSERT_EQ(can.state(), CanState::ErrorActive);
  EXPECT_EQ(can.send(CanFrame{0x101, false, 8, {}}), Status::Ok);
  h.runFor(fw::ms(3));
  ASSERT_FALSE(can.sent().empty()) << "nothing was sent after recovery";
  EXPECT_EQ(can.sent().back().frame.id, 0x101u);
}

}  // namespace
