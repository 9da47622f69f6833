// The simulated command/response UART: byte timing, timeouts, unsolicited bytes and pings.
#include <gtest/gtest.h>

#include <vector>

#include "sim/harness.hpp"
#include "sim/uart.hpp"

namespace {

using fw::Status;

struct EchoPeer final : bsp::host::UartPeer {
  bsp::host::SimUart* uart = nullptr;
  std::vector<uint8_t> reply;
  uint64_t delayUs = 0;
  uint64_t lastEnd = 0;
  fw::Duration lastPing{};
  void onHostBytes(std::span<const uint8_t>, uint64_t endUs) override {
    lastEnd = endUs;
    if (!reply.empty()) uart->peerSend(reply, endUs + delayUs);
  }
  std::string onPing(fw::Duration low, uint64_t) override {
    lastPing = low;
    return low.us >= 2000 && low.us <= 3000 ? "WAKE" : "";
  }
};

struct Fixture {
  bsp::host::Harness h;
  bsp::host::SimUart uart{h.clock, h.irq, 1000000};
  EchoPeer peer;
  bool done = false;
  Fixture() {
    peer.uart = &uart;
    uart.attach(peer);
  }
  fw::hal::Notify notify() {
    return fw::hal::Notify{[](void* c, uint32_t) { *static_cast<bool*>(c) = true; }, &done};
  }
};

TEST(SimUart, ExchangeCompletesWhenTheReplyIsComplete) {
  Fixture f;
  f.peer.reply = {1, 2, 3, 4, 5, 6, 7};
  f.peer.delayUs = 3;
  const uint8_t tx[] = {0x80, 0x00, 0x03, 0x06, 0x00, 0xD7, 0x82};
  uint8_t rx[7];
  fw::hal::UartExchange ex{tx, rx};
  ASSERT_EQ(f.uart.start(ex, f.notify()), Status::Ok);
  f.h.runUntil([&] { return f.done; }, fw::ms(10));
  EXPECT_EQ(ex.status, Status::Ok);
  EXPECT_EQ(ex.received, 7u);
  // 7 bytes out (70 us), 3 us turnaround, 7 bytes back (70 us).
  EXPECT_EQ(f.peer.lastEnd, 70u);
  EXPECT_EQ(f.h.nowUs(), 143u);
  EXPECT_EQ(f.uart.wireLog(),
            (std::vector<std::string>{"TX 80 00 03 06 00 D7 82", "RX 01 02 03 04 05 06 07"}));
}

TEST(SimUart, SilenceIsNoResponseAfterTheFirstByteTimeout) {
  Fixture f;
  const uint8_t tx[] = {0xC0};
  uint8_t rx[4];
  fw::hal::UartExchange ex{tx, rx, fw::ms(2), fw::us(100)};
  ASSERT_EQ(f.uart.start(ex, f.notify()), Status::Ok);
  f.h.runUntil([&] { return f.done; }, fw::ms(10));
  EXPECT_EQ(ex.status, Status::NoResponse);
  EXPECT_EQ(f.h.nowUs(), 10u + 2000u);
}

TEST(SimUart, ShortReplyIsTruncatedAfterTheGapTimeout) {
  Fixture f;
  f.peer.reply = {1, 2};
  const uint8_t tx[] = {0xC0};
  uint8_t rx[4];
  fw::hal::UartExchange ex{tx, rx, fw::ms(2), fw::us(100)};
  ASSERT_EQ(f.uart.start(ex, f.notify()), Status::Ok);
  f.h.runUntil([&] { return f.done; }, fw::ms(10));
  EXPECT_EQ(ex.status, Status::Truncated);
  EXPECT_EQ(ex.received, 2u);
  EXPECT_EQ(f.h.nowUs(), 10u + 20u + 100u);
}

TEST(SimUart, BytesWithNoExchangeArmedAreCountedAsUnsolicited) {
  Fixture f;
  const uint8_t junk[] = {9, 9, 9};
  f.uart.peerSend(junk, 0);
  f.h.runFor(fw::ms(1));
  EXPECT_EQ(f.uart.unsolicitedBytes(), 3u);
}

TEST(SimUart, PingHoldsTheLineForTheRequestedTimeAndIsNamedByThePeer) {
  Fixture f;
  ASSERT_EQ(f.uart.ping(fw::us(2250), f.notify()), Status::Ok);
  EXPECT_EQ(f.uart.ping(fw::us(2250), f.notify()), Status::Busy);
  f.h.runUntil([&] { return f.done; }, fw::ms(10));
  EXPECT_EQ(f.h.nowUs(), 2250u);
  EXPECT_EQ(f.peer.lastPing, fw::us(2250));
  EXPECT_EQ(f.uart.wireLog().back(), "PING WAKE 2250us");
  EXPECT_EQ(f.uart.ping(fw::us(0), f.notify()), Status::InvalidArgument);
}

TEST(SimUart, AbortStopsWithoutCallingDone) {
  Fixture f;
  const uint8_t tx[] = {0xC0};
  uint8_t rx[4];
  fw::hal::UartExchange ex{tx, rx};
  ASSERT_EQ(f.uart.start(ex, f.notify()), Status::Ok);
  f.uart.abort();
  f.h.runFor(fw::ms(10));
  EXPECT_FALSE(f.done);
  EXPECT_FALSE(f.uart.busy());
}

}  // namespace
