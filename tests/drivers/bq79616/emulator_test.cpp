// The chain emulator on its own, driven frame by frame over SimUart (no driver): it must behave as the
// datasheet and TI's bring-up guide describe the chip, so that driver tests against it mean something.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "bq79616/chain_emulator.hpp"
#include "drivers/bq79616/frame.hpp"
#include "regmap/bq79616.hpp"
#include "sim/harness.hpp"
#include "sim/peripherals.hpp"
#include "sim/uart.hpp"

namespace {

namespace bq = fw::drivers::bq79616;
namespace r = fw::regmap::bq79616::reg;
using bq::RequestType;
using bsp::host::Bq79616ChainEmulator;
using fw::ms;
using fw::Status;
using fw::us;

constexpr uint16_t kDir0Addr = r::Dir0Addr.address;
constexpr uint16_t kCommCtrl = r::CommCtrl.address;
constexpr uint16_t kControl1 = r::Control1.address;
constexpr uint16_t kFaultSummary = r::FaultSummary.address;
constexpr uint16_t kFaultRst2 = r::FaultRst2.address;
constexpr uint16_t kAdcConf1 = r::AdcConf1.address;

struct Wire {
  explicit Wire(size_t devices) : emu(h.clock, uart, devices) {}

  static void onDone(void* self, uint32_t) { static_cast<Wire*>(self)->done = true; }
  fw::hal::Notify notify() { return {&Wire::onDone, this, 0}; }

  Status exchange(size_t txLen, size_t expect) {
    rx.assign(expect, 0);
    ex = fw::hal::UartExchange{};
    ex.tx = {tx.data(), txLen};
    ex.rx = rx;
    done = false;
    EXPECT_EQ(uart.start(ex, notify()), Status::Ok);
    EXPECT_TRUE(h.runUntil([&] { return done; }, ms(100)));
    return ex.status;
  }
  Status write(RequestType t, uint8_t dev, uint16_t reg, std::vector<uint8_t> data) {
    const size_t n = bq::encodeWrite(t, dev, reg, data, tx);
    EXPECT_NE(n, 0u);
    return exchange(n, 0);
  }
  Status read(RequestType t, uint8_t dev, uint16_t reg, uint8_t count, size_t frames) {
    const size_t n = bq::encodeRead(t, dev, reg, count, tx);
    EXPECT_NE(n, 0u);
    return exchange(n, frames * bq::responseSize(count));
  }
  void ping(fw::Duration low) {
    done = false;
    ASSERT_EQ(uart.ping(low, notify()), Status::Ok);
    ASSERT_TRUE(h.runUntil([&] { return done; }, ms(100)));
  }
  // TI's sequence, by hand: WAKE, SEND_WAKE, wait, auto-address N devices.
  void bringUp(size_t n) {
    ping(us(2250));
    h.runFor(ms(11));
    EXPECT_EQ(write(RequestType::SingleWrite, 0, kControl1, {0x20}), Status::Ok);
    h.runFor(ms(12) * static_cast<uint32_t>(n));
    EXPECT_EQ(write(RequestType::BroadcastWrite, 0, kControl1, {0x01}), Status::Ok);
    for (uint8_t a = 0; a < n; ++a)
      EXPECT_EQ(write(RequestType::BroadcastWrite, 0, kDir0Addr, {a}), Status::Ok);
    EXPECT_EQ(write(RequestType::BroadcastWrite, 0, kCommCtrl, {0x02}), Status::Ok);
    if (n == 1) {
      EXPECT_EQ(write(RequestType::SingleWrite, 0, kCommCtrl, {0x01}), Status::Ok);
    } else {
      EXPECT_EQ(write(RequestType::SingleWrite, 0, kCommCtrl, {0x00}), Status::Ok);
      EXPECT_EQ(write(RequestType::SingleWrite, static_cast<uint8_t>(n - 1), kCommCtrl, {0x03}), Status::Ok);
    }
  }
  std::string lastLine() const { return uart.wireLog().empty() ? "" : uart.wireLog().back(); }

  bsp::host::Harness h;
  bsp::host::SimUart uart{h.clock, h.irq};
  Bq79616ChainEmulator emu;
  std::array<uint8_t, bq::kMaxCommandBytes> tx{};
  std::vector<uint8_t> rx;
  fw::hal::UartExchange ex;
  bool done = false;
};

TEST(Bq79616Emulator, AChainInShutdownAnswersNothing) {
  Wire w(2);
  EXPECT_EQ(w.read(RequestType::SingleRead, 0, kDir0Addr, 1, 1), Status::NoResponse);
  EXPECT_GT(w.emu.counters().ignoredBytes, 0u);
  EXPECT_EQ(w.emu.power(0), Bq79616ChainEmulator::Power::Shutdown);
}

TEST(Bq79616Emulator, WakePingAtTheBottomEdgeIsRejectedAndTheMiddleAccepted) {
  Wire w(1);
  w.ping(us(2000));  // TI's example: 2.0 ms, the bottom of tHLD_WAKE, no margin for clock error
  EXPECT_EQ(w.lastLine(), "PING ? 2000us");
  w.h.runFor(ms(20));
  EXPECT_FALSE(w.emu.awake(0));
  w.ping(us(2250));
  EXPECT_EQ(w.lastLine(), "PING WAKE 2250us");
  w.h.runFor(us(9999));
  EXPECT_FALSE(w.emu.awake(0)) << "tSU(WAKE_SHUT) is up to 10 ms";
  w.h.runFor(us(1));
  EXPECT_TRUE(w.emu.awake(0));
}

TEST(Bq79616Emulator, PingsAreClassifiedByTheirWindows) {
  Wire w(1);
  const std::vector<std::pair<uint32_t, std::string>> cases = {
      {18, "COMM_CLEAR"}, {30, ""},           {275, "SLEEPtoACTIVE"}, {250, ""},   {2250, "WAKE"},
      {2500, ""},         {8500, "SHUTDOWN"}, {40000, "HW_RESET"},    {36000, ""},
  };
  for (const auto& [low, name] : cases)
    EXPECT_EQ(w.emu.onPing(us(low), w.h.nowUs()), name) << low << " us";
}

TEST(Bq79616Emulator, WakeResetsTheRegisters) {
  Wire w(1);
  w.bringUp(1);
  const uint8_t dflt = w.emu.reg(0, kAdcConf1);
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, kAdcConf1, {static_cast<uint8_t>(dflt ^ 0x05)}),
            Status::Ok);
  EXPECT_EQ(w.emu.reg(0, kAdcConf1), dflt ^ 0x05);
  EXPECT_TRUE(w.emu.addressed(0));
  w.ping(us(2250));
  EXPECT_EQ(w.emu.reg(0, kAdcConf1), dflt);
  EXPECT_FALSE(w.emu.addressed(0));
}

TEST(Bq79616Emulator, SendWakeWakesTheStackOneDeviceAfterAnother) {
  Wire w(3);
  w.ping(us(2250));
  w.h.runFor(ms(11));
  EXPECT_EQ(w.write(RequestType::SingleWrite, 0, kControl1, {0x20}), Status::Ok);
  const uint64_t sent = w.h.nowUs();  // the frame's last stop bit
  EXPECT_FALSE(w.emu.awake(1));
  w.h.clock.advanceTo(sent + 11600 - 1);
  EXPECT_FALSE(w.emu.awake(1));
  w.h.clock.advanceTo(sent + 11600);
  EXPECT_TRUE(w.emu.awake(1));
  EXPECT_FALSE(w.emu.awake(2));
  w.h.clock.advanceTo(sent + 2 * 11600);
  EXPECT_TRUE(w.emu.awake(2));
}

TEST(Bq79616Emulator, WithoutSendWakeTheStackSleepsOn) {
  Wire w(2);
  w.ping(us(2250));
  w.h.runFor(ms(100));
  EXPECT_TRUE(w.emu.awake(0));
  EXPECT_FALSE(w.emu.awake(1));
}

TEST(Bq79616Emulator, AfterAShutdownPingOnlyTheSecondWakeReachesTheStack) {
  Wire w(2);
  w.bringUp(2);
  ASSERT_TRUE(w.emu.awake(1));
  w.ping(us(8500));
  EXPECT_FALSE(w.emu.awake(0));
  EXPECT_FALSE(w.emu.awake(1));
  w.ping(us(2250));  // one WAKE: the base comes up, its daisy-chain port does not
  w.h.runFor(ms(11));
  EXPECT_EQ(w.write(RequestType::SingleWrite, 0, kControl1, {0x20}), Status::Ok);
  w.h.runFor(ms(30));
  EXPECT_TRUE(w.emu.awake(0));
  EXPECT_FALSE(w.emu.awake(1));
  w.ping(us(2250));  // the second WAKE turns it on
  w.h.runFor(ms(11));
  EXPECT_EQ(w.write(RequestType::SingleWrite, 0, kControl1, {0x20}), Status::Ok);
  w.h.runFor(ms(30));
  EXPECT_TRUE(w.emu.awake(1));
}

TEST(Bq79616Emulator, AutoAddressingGivesEachDeviceTheNextAddress) {
  Wire w(4);
  w.bringUp(4);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(w.emu.address(k), k);
    EXPECT_TRUE(w.emu.addressed(k));
  }
  // DIR0_ADDR is writable only in auto-addressing mode: a stray broadcast changes nothing.
  EXPECT_EQ(w.write(RequestType::BroadcastWrite, 0, kDir0Addr, {9}), Status::Ok);
  for (size_t k = 0; k < 4; ++k)
    EXPECT_EQ(w.emu.address(k), k);
  EXPECT_EQ(w.emu.reg(3, kCommCtrl), 0x03);
  EXPECT_EQ(w.emu.reg(1, kCommCtrl), 0x02);
  EXPECT_EQ(w.emu.reg(0, kCommCtrl), 0x00);
}

TEST(Bq79616Emulator, BroadcastReadAnswersTopOfStackFirstWithTheChainLatency) {
  Wire w(3);
  w.bringUp(3);
  const uint64_t start = w.h.nowUs();
  ASSERT_EQ(w.read(RequestType::BroadcastRead, 0, kDir0Addr, 1, 3), Status::Ok);
  for (size_t i = 0; i < 3; ++i) {
    bq::ResponseFrame f;
    ASSERT_EQ(bq::parseResponse(std::span(w.rx).subspan(i * 7), kDir0Addr, 1, f), Status::Ok);
    EXPECT_EQ(f.device, 2 - i);
    EXPECT_EQ(f.data[0], 2 - i);
  }
  // 6 command bytes, then the top (2 devices up) starts 100 us after the command reached it, its frame comes
  // 2 x 3 us later down the chain, then 21 bytes back to back at 10 us each.
  EXPECT_EQ(w.h.nowUs() - start, 60u + (2 * 2 * 3 + 100) + 21 * 10);
}

TEST(Bq79616Emulator, StackReadLeavesTheBaseOut) {
  Wire w(3);
  w.bringUp(3);
  ASSERT_EQ(w.read(RequestType::StackRead, 0, kDir0Addr, 1, 2), Status::Ok);
  bq::ResponseFrame f;
  ASSERT_EQ(bq::parseResponse(std::span(w.rx).subspan(7), kDir0Addr, 1, f), Status::Ok);
  EXPECT_EQ(f.device, 1);
}

TEST(Bq79616Emulator, UnaddressedDevicesDoNotAnswerReads) {
  Wire w(1);
  w.ping(us(2250));
  w.h.runFor(ms(11));
  EXPECT_EQ(w.read(RequestType::SingleRead, 0, kDir0Addr, 1, 1), Status::NoResponse);
}

TEST(Bq79616Emulator, ACommandWithABadCrcIsDropped) {
  Wire w(1);
  w.bringUp(1);
  const uint8_t before = w.emu.reg(0, kAdcConf1);
  const size_t n =
      bq::encodeWrite(RequestType::BroadcastWrite, 0, kAdcConf1, std::vector<uint8_t>{0x07}, w.tx);
  w.tx[n - 1] ^= 0x01;
  EXPECT_EQ(w.exchange(n, 0), Status::Ok);
  EXPECT_EQ(w.emu.reg(0, kAdcConf1), before);
  EXPECT_EQ(w.emu.counters().badCommandCrc, 1u);
  EXPECT_NE(w.emu.reg(0, r::FaultComm1.address), 0) << "UART_RC latched";
}

TEST(Bq79616Emulator, AStackCommFaultNeedsBaseAndStackCleared) {
  Wire w(3);
  bsp::host::SimEdgeInput nfault(w.h.irq, "nfault", bsp::host::SimEdgeInput::Edge::Falling, true);
  w.bringUp(3);
  EXPECT_EQ(w.write(RequestType::BroadcastWrite, 0, r::FaultRst1.address, {0xFF, 0xFF}),
            Status::Ok);  // wake-up leftovers
  w.emu.attachFaultPin(nfault);
  EXPECT_TRUE(nfault.level());
  w.emu.injectCommFault(2, false);
  EXPECT_FALSE(nfault.level());
  const uint8_t comm = fw::regmap::bq79616::bits::FaultSummary::fault_comm_mask;
  EXPECT_EQ(w.emu.reg(2, kFaultSummary), comm);
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), comm) << "the base sees it through the fault signal";
  EXPECT_EQ(w.write(RequestType::SingleWrite, 0, kFaultRst2, {0x1F}),
            Status::Ok);  // base only: comes back at once
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), comm);
  EXPECT_EQ(w.write(RequestType::StackWrite, 0, kFaultRst2, {0x1F}),
            Status::Ok);  // stack only: the base keeps its latch
  EXPECT_EQ(w.emu.reg(2, kFaultSummary), 0);
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), comm);
  EXPECT_EQ(w.write(RequestType::SingleWrite, 0, kFaultRst2, {0x1F}), Status::Ok);
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), 0);
  EXPECT_TRUE(nfault.level());
}

TEST(Bq79616Emulator, CellsReadNotConvertedUntilTheAdcHasSettled) {
  Wire w(1);
  w.bringUp(1);
  ASSERT_EQ(w.read(RequestType::SingleRead, 0, r::Vcell1Hi.address, 2, 1), Status::Ok);
  EXPECT_EQ(w.rx[4], 0x80);
  EXPECT_EQ(w.rx[5], 0x00);
  EXPECT_EQ(w.write(RequestType::BroadcastWrite, 0, r::AdcCtrl1.address, {0x0E}), Status::Ok);
  w.h.runFor(ms(38));
  w.emu.setCellMicrovolts(0, 1, 1110811);  // 0x16C0 (seed 001, figure 4-5)
  ASSERT_EQ(w.read(RequestType::SingleRead, 0, r::Vcell1Hi.address, 2, 1), Status::Ok);
  EXPECT_EQ(w.rx[4], 0x16);
  EXPECT_EQ(w.rx[5], 0xC0);
}

// SLUSF21 FAULT_SYS (0x536): LFO 7, RSVD 6, GPIO 5, DRST 4, CTL 3, CTS 2, TSHUT 1, TWARN 0. A WAKE is a
// digital reset. Fails on the emulator before the fix, which set bit 5 (GPIO).
TEST(Bq79616Emulator, AWakeLatchesDrstInFaultSysBit4) {
  Wire w(1);
  w.bringUp(1);
  EXPECT_EQ(w.emu.reg(0, r::FaultSys.address), 0x10);
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), fw::regmap::bq79616::bits::FaultSummary::fault_sys_mask);
}

// The customer CRC (SLUSF21 DEV_STAT[CUST_CRC_DONE], CUST_CRC_RSLT, FAULT_OTP[CUST_CRC] = bit 4): the device
// computes it in passes, not at once. Fails on the emulator before the fix, which returned the new CRC at
// once and latched FAULT_OTP bit 0 (GBLOVERR) at once.
struct CrcWire : Wire {
  CrcWire() : Wire(1) {
    bringUp(1);
    EXPECT_EQ(write(RequestType::BroadcastWrite, 0, r::FaultRst1.address, {0xFF, 0xFF}),
              Status::Ok);  // wake-up leftovers
    h.runFor(us(pass));
  }
  uint16_t result() {
    EXPECT_EQ(read(RequestType::SingleRead, 0, r::CustCrcRsltHi.address, 2, 1), Status::Ok);
    return static_cast<uint16_t>(rx[4] << 8 | rx[5]);
  }
  uint8_t devStat() {
    EXPECT_EQ(read(RequestType::SingleRead, 0, r::DevStat.address, 1, 1), Status::Ok);
    return rx[4];
  }
  const uint32_t pass = Bq79616ChainEmulator::Timing{}.custCrcUs;
};

constexpr uint8_t kCustCrcDone = 0x20;  // DEV_STAT bit 5
constexpr uint8_t kOtpCustCrc = 0x10;   // FAULT_OTP bit 4
constexpr uint8_t kSummaryOtp = 0x20;   // FAULT_SUMMARY bit 5

TEST(Bq79616Emulator, TheCustomerCrcResultFollowsAShadowWriteOnlyAfterAPass) {
  CrcWire w;
  const uint16_t before = w.result();
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, kAdcConf1, {0x02}), Status::Ok);
  EXPECT_EQ(w.result(), before) << "no pass over the new contents has ended yet";
  EXPECT_EQ(w.emu.reg(0, r::FaultOtp.address), 0);
  w.h.runFor(us(w.pass));
  const uint16_t after = w.result();
  EXPECT_NE(after, before);
  // CUST_CRC still holds the old value: the pass latched the mismatch, and it reaches the summary.
  EXPECT_EQ(w.emu.reg(0, r::FaultOtp.address), kOtpCustCrc);
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), kSummaryOtp);
}

TEST(Bq79616Emulator, CustCrcDoneIsClearedByReadingDevStatAndSetByTheNextPass) {
  CrcWire w;
  EXPECT_EQ(w.devStat() & kCustCrcDone, kCustCrcDone) << "passes ended since the reset";
  EXPECT_EQ(w.devStat() & kCustCrcDone, 0) << "cleared on read";
  w.h.runFor(us(w.pass));
  EXPECT_EQ(w.devStat() & kCustCrcDone, kCustCrcDone);
  // A write restarts the pass: a flag read right after it still comes from the pass before (stale).
  w.h.runFor(us(w.pass));
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, kAdcConf1, {0x02}), Status::Ok);
  EXPECT_EQ(w.devStat() & kCustCrcDone, kCustCrcDone) << "left from the pass before the write";
  EXPECT_EQ(w.devStat() & kCustCrcDone, 0);
  w.h.runFor(us(w.pass));
  EXPECT_EQ(w.devStat() & kCustCrcDone, kCustCrcDone) << "the pass over the new contents";
}

TEST(Bq79616Emulator, MaskedCrcFaultLatchesButStaysOutOfTheSummaryAndNfault) {
  CrcWire w;
  bsp::host::SimEdgeInput nfault(w.h.irq, "nfault", bsp::host::SimEdgeInput::Edge::Falling, true);
  w.emu.attachFaultPin(nfault);
  ASSERT_TRUE(nfault.level());
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, r::FaultMsk2.address, {0x40}), Status::Ok);
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, kAdcConf1, {0x02}), Status::Ok);
  w.h.runFor(us(w.pass));
  EXPECT_EQ(w.emu.reg(0, r::FaultOtp.address), kOtpCustCrc) << "the flag latches, masked or not";
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), 0);
  EXPECT_TRUE(nfault.level());
  // Refreshed and cleared while masked: unmasking changes FAULT_MSK2, which is inside the CRC again.
  const uint16_t crc = w.result();
  ASSERT_EQ(w.write(RequestType::SingleWrite, 0, r::CustCrcHi.address,
                    {static_cast<uint8_t>(crc >> 8), static_cast<uint8_t>(crc)}),
            Status::Ok);
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, kFaultRst2, {0x40}), Status::Ok);  // RST_OTP_CRC
  w.h.runFor(us(w.pass));
  EXPECT_EQ(w.emu.reg(0, r::FaultOtp.address), 0);
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, r::FaultMsk2.address, {0x00}), Status::Ok);
  w.h.runFor(us(w.pass));
  EXPECT_EQ(w.emu.reg(0, r::FaultOtp.address), kOtpCustCrc);
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), kSummaryOtp);
  EXPECT_FALSE(nfault.level());
}

TEST(Bq79616Emulator, AClearedCrcFaultLatchesAgainUntilCustCrcMatches) {
  CrcWire w;
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, kAdcConf1, {0x02}), Status::Ok);
  w.h.runFor(us(w.pass));
  ASSERT_EQ(w.emu.reg(0, r::FaultOtp.address), kOtpCustCrc);
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, kFaultRst2, {0x40}), Status::Ok);
  EXPECT_EQ(w.emu.reg(0, r::FaultOtp.address), 0);
  w.h.runFor(us(w.pass));
  EXPECT_EQ(w.emu.reg(0, r::FaultOtp.address), kOtpCustCrc) << "the mismatch is still there";
  const uint16_t crc = w.result();
  ASSERT_EQ(w.write(RequestType::SingleWrite, 0, r::CustCrcHi.address,
                    {static_cast<uint8_t>(crc >> 8), static_cast<uint8_t>(crc)}),
            Status::Ok);
  ASSERT_EQ(w.write(RequestType::BroadcastWrite, 0, kFaultRst2, {0x40}), Status::Ok);
  w.h.runFor(us(3 * w.pass));
  EXPECT_EQ(w.emu.reg(0, r::FaultOtp.address), 0);
  EXPECT_EQ(w.emu.reg(0, kFaultSummary), 0);
}

// SLUSF21 ADC_CTRL1: MAIN_GO (bit 2) with MAIN_MODE = 10 starts the main ADC, DEV_STAT[MAIN_RUN] shows it.
TEST(Bq79616Emulator, MainGoInContinuousModeStartsTheAdcAndDevStatShowsIt) {
  Wire w(1);
  w.bringUp(1);
  EXPECT_EQ(w.emu.reg(0, r::DevStat.address) & 0x01, 0);
  EXPECT_EQ(w.write(RequestType::BroadcastWrite, 0, r::AdcCtrl1.address, {0x0A}),
            Status::Ok);  // continuous + LPF, no GO
  EXPECT_EQ(w.emu.reg(0, r::DevStat.address) & 0x01, 0) << "nothing starts without MAIN_GO";
  EXPECT_EQ(w.write(RequestType::BroadcastWrite, 0, r::AdcCtrl1.address, {0x0E}), Status::Ok);
  EXPECT_EQ(w.emu.reg(0, r::DevStat.address) & 0x01, 0x01);
  EXPECT_EQ(w.write(RequestType::BroadcastWrite, 0, r::AdcCtrl1.address, {0x04}),
            Status::Ok);  // MAIN_MODE 00 + GO: stop
  EXPECT_EQ(w.emu.reg(0, r::DevStat.address) & 0x01, 0);
}

}  // namespace
