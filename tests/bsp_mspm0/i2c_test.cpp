// Register-level tests of the MSPM0 I2C controller driver (bsp/mspm0/i2c.*) on the twin's I2C controller
// (bsp/twin/periph/i2c.hpp: 8-byte FIFOs, flushes that take time, bursts at the SCL rate, NACKs, the
// clock-low timeout as the TRM counts it, SMBus PEC; its rules) with devices on the bus that ACK, NACK,
// stretch and answer, and the twin's IOMUX and GPIO for the bus recovery. Addresses: I2C0_BASE 0x400F0000 and
// the I2C.* register offsets of mspm0l1306.tsv; bits: the I2C_* field rows of the same file; IOMUX PINCMn at
// IOMUX_BASE + 4n (tsv note "PINCM index").
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "core/crc.hpp"
#include "fixture.hpp"
#include "gpio.hpp"
#include "i2c.hpp"
#include "mmio.hpp"

namespace bsp::mspm0::test {
namespace {

// Register addresses (tsv "reg" rows, I2C0_BASE 0x400F0000).
constexpr uintptr_t kPwren = 0x400F0800;
constexpr uintptr_t kRstctl = 0x400F0804;
constexpr uintptr_t kClkdiv = 0x400F1000;
constexpr uintptr_t kClksel = 0x400F1004;
constexpr uintptr_t kImask = 0x400F1028;
constexpr uintptr_t kMis = 0x400F1038;
constexpr uintptr_t kIclr = 0x400F1048;
constexpr uintptr_t kGfctl = 0x400F1200;
constexpr uintptr_t kTimeoutCtl = 0x400F1204;
constexpr uintptr_t kMsa = 0x400F1210;
constexpr uintptr_t kMctr = 0x400F1214;
constexpr uintptr_t kMtxdata = 0x400F1220;
constexpr uintptr_t kMtpr = 0x400F1224;
constexpr uintptr_t kMcr = 0x400F1228;
constexpr uintptr_t kMfifoctl = 0x400F1238;
constexpr uintptr_t kMfifosr = 0x400F123C;
constexpr uintptr_t kPecctl = 0x400F1240;
constexpr uintptr_t kPincm1 = 0x40428004;  // PA0 = SDA
constexpr uintptr_t kPincm2 = 0x40428008;  // PA1 = SCL
constexpr uintptr_t kGpioaDoutSet = 0x400A1290;
constexpr uintptr_t kGpioaDoutClr = 0x400A12A0;
constexpr uintptr_t kNvicIser = 0xE000E100;
constexpr int kSdaPincm = 1, kSclPincm = 2;

// I2C_CPU_INT_IMASK_* bits.
constexpr uint32_t kTxDone = 1U << 1;
constexpr uint32_t kRxFifoTrig = 1U << 2;
constexpr uint32_t kTxFifoTrig = 1U << 3;
constexpr uint32_t kNack = 1U << 7;
constexpr uint32_t kStop = 1U << 9;
constexpr uint32_t kArbLost = 1U << 10;
constexpr uint32_t kPecRxErr = 1U << 13;
constexpr uint32_t kTimeoutA = 1U << 14;
// MCTR: BURSTRUN 0, START 1, STOP 2, MBLEN 27:16 (tsv note "MCTR = (len<<16)|BURSTRUN|START|STOP").
constexpr uint32_t mctr(uint32_t length, bool stop) {
  return (length << 16) | 0x3 | (stop ? 0x4 : 0);
}
// PINCM for an I2C pin: PC (bit 7) | PF 3 (I2C0_SDA/SCL on PA0/PA1) | INENA (bit 18) | HIZ1 (bit 25).
constexpr uint32_t kPincmI2c = 0x80 | 3 | (1U << 18) | (1U << 25);
constexpr uint32_t kPincmGpioOpenDrain = 0x80 | 1 | (1U << 18) | (1U << 25);

I2cController::Config config(uint32_t bitRate, uint32_t stretchUs) {
  return {0x400F0000,
          24,
          PinFunction{Pin{0, 0, 1}, 3},
          PinFunction{Pin{0, 1, 2}, 3},
          bitRate,
          i2cTiming(32000000, bitRate, stretchUs)};
}

// A device on the bus: ACKs its address (unless nackAddress) and every written byte but the nackByte-th
// (1-based; 0: none), stretches SCL on its address byte by `stretch` (and runs `addressed`), sends `sends` on
// reads (then 0xFF: SDA released).
class Device final : public bsp::host::I2cTarget {
 public:
  bsp::host::I2cReply onStart(bool) override {
    if (addressed) addressed();
    return {!nackAddress, stretch};
  }
  bsp::host::I2cReply onWrite(uint8_t byte) override {
    written.push_back(byte);
    return {written.size() != nackByte, {}};
  }
  uint8_t onRead(fw::Duration&) override { return next < sends.size() ? sends[next++] : 0xFF; }
  void onStop() override { ++stops; }

  std::function<void()> addressed;
  bool nackAddress = false;
  size_t nackByte = 0;
  fw::Duration stretch{};
  std::vector<uint8_t> sends;
  size_t next = 0;
  std::vector<uint8_t> written;
  int stops = 0;
};

// SMBus PEC over the bytes on the wire, addresses included (CRC-8, firmware/core/crc.hpp).
uint8_t pec(std::initializer_list<uint8_t> wire) {
  return fw::crc::crc8(wire.begin(), wire.size());
}

class I2cTest : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    // The board: GPIOA powered (the boards' bring-up does it before the I2C), pull-ups on SDA (PA0, PINCM1)
    // and SCL (PA1, PINCM2) as on the EVMs; the twin's IOMUX and GPIO carry the lines during a bus recovery.
    powerGpioPort(kGpioaBase);
    chip().pins().setBoardPullUp(kSdaPincm, true);
    chip().pins().setBoardPullUp(kSclPincm, true);
    chip().i2c0().attach(0x08, device);
    chip().i2c0().attach(0x09, other);
    chip().i2c0().attach(0x0B, gauge);
    chip().i2c0().onTransaction([this](const twin::I2cWireLog& l) { wire.push_back(l.text); });
    i2c.init();
    regs().clearLog();
  }

  // A target holds SDA low (stuck mid-byte) and lets it go after `clocks` SCL pulses (never: -1).
  void holdSda(int clocks) {
    chip().pins().setExternal(kSdaPincm, twin::Drive::Low);
    chip().pins().onChange(kSclPincm, [this, clocks, pulses = 0](bool high) mutable {
      if (high && ++pulses == clocks) chip().pins().setExternal(kSdaPincm, twin::Drive::None);
    });
  }

  // The CPU takes the I2C interrupt whenever the controller raises one (MIS), until the list is done or
  // `maxUs` have passed.
  void serve(uint64_t maxUs = 5000) {
    const int before = done;
    regs().runUntil(
        [&] {
          if (regs().peek(kMis) != 0) i2c.onInterrupt();
          return done != before;
        },
        maxUs);
  }

  // serve(), counting the handler's runs.
  int serveCounting(uint64_t maxUs = 5000) {
    const int before = done;
    int interrupts = 0;
    regs().runUntil(
        [&] {
          if (regs().peek(kMis) != 0) {
            ++interrupts;
            i2c.onInterrupt();
          }
          return done != before;
        },
        maxUs);
    return interrupts;
  }

  // A write the device NACKs after its first byte: the controller stops, the rest stays in the TX FIFO.
  void leaveBytesInTheTxFifo() {
    device.nackByte = 1;
    const std::array<uint8_t, 4> bytes{0x01, 0xAA, 0xBB, 0xCC};
    std::array<fw::hal::I2cTransaction, 1> list{};
    list[0].address = 0x08;
    list[0].write = bytes;
    ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
    serve();
    EXPECT_EQ(list[0].status, fw::Status::DataNack);
    device.nackByte = 0;
    device.written.clear();
    done = 0;
  }

  // Some IMASK write armed `bits`.
  bool anyImaskWith(uint32_t bits) const {
    for (uint32_t v : model().writes(kImask))
      if ((v & bits) == bits) return true;
    return false;
  }

  Device device, other, gauge;
  std::vector<std::string> wire;  // each transaction on the bus, bmsctl trace format (twin I2cWireLog)
  I2cController i2c{config(400000, 2000)};
  int done = 0;
};

TEST_F(I2cTest, InitProgramsClock100kHzTimeoutAndPins) {
  RegisterTest::SetUp();
  I2cController slow(config(100000, 2000));
  slow.init();
  // GPRCM: reset with KEY 0xB1 then enable with KEY 0x26 (tsv note "GPRCM keys").
  EXPECT_TRUE(regs().wroteInOrder({{kRstctl, 0xB1000003}, {kPwren, 0x26000001}}));
  EXPECT_EQ(regs().lastWrite(kClksel), 0x8U);  // BUSCLK_SEL bit 3: 32 MHz functional clock
  EXPECT_EQ(regs().lastWrite(kClkdiv), 0x0U);  // /1
  // SCL = 32 MHz / ((1 + TPR) * 10): TPR 31 is 100 kHz (tsv "I2C0 MTPR.TPR 31 -> 100 kHz").
  EXPECT_EQ(regs().lastWrite(kMtpr), 31U);
  // Timeout A: each TCNTLA count is 16 steps of (1 + TPR) x 12 functional clocks (SLAU847D 21.2; TI's Zephyr
  // driver): 16 x 32 x 12 / 32 MHz = 192 us, so 2 ms is 10.4 -> 11 counts, with TCNTAEN (bit 15).
  EXPECT_EQ(regs().lastWrite(kTimeoutCtl), 0x8000U | 11U);
  EXPECT_FALSE(regs().lastWrite(kGfctl).has_value());  // the glitch filters stay off (reset value 0)
  EXPECT_EQ(regs().lastWrite(kMcr), 0x5U);             // ACTIVE | CLKSTRETCH
  EXPECT_EQ(regs().lastWrite(kPincm1), kPincmI2c);
  EXPECT_EQ(regs().lastWrite(kPincm2), kPincmI2c);
  EXPECT_EQ(regs().lastWrite(kImask), 0x0U);
  EXPECT_EQ(regs().lastWrite(kNvicIser), 1U << 24);  // I2C0 is IRQ 24 (tsv irq rows)
  EXPECT_EQ(slow.bitRate(), 100000U);
}

TEST_F(I2cTest, InitFastModeUsesTpr7) {
  RegisterTest::SetUp();
  I2cController fast(config(400000, 2000));
  fast.init();
  EXPECT_EQ(regs().lastWrite(kMtpr), 7U);  // 32 MHz / (8 * 10) = 400 kHz
}

TEST_F(I2cTest, SmbusStretchLimitFitsTheFullClockInsideTTimeout) {
  // 25 ms at 100 kHz from 32 MHz (TPR 31): 192 us per count, 131 counts = 25.15 ms, inside the SMBus
  // tTIMEOUT of 25..35 ms. (The header's 520 clocks per count needed /8 and 193 counts, which TI's count
  // makes 37.1 ms, past 35 ms.)
  constexpr I2cTiming t = i2cTiming(32000000, 100000, 25000);
  EXPECT_TRUE(t.valid);
  EXPECT_EQ(t.clkdivRatio, 0);
  EXPECT_EQ(t.tpr, 31);
  EXPECT_EQ(t.timeoutCount, 131);
  EXPECT_EQ(i2cTimeoutUs(t, 32000000), 25152U);
  // Beyond 255 counts at every divider that gives an exact SCL: no timing.
  EXPECT_FALSE(i2cTiming(32000000, 400000, 60000).valid);
}

// The images' bus settings (images/<preset>/board_config.hpp): the timeout the controller runs on the twin
// is never shorter than the device may stretch SCL, and at most one count (and the START's SCL period)
// longer; the SMBus one stays inside tTIMEOUT max 35 ms.
struct BusSetting {
  const char* image;
  uint32_t bitRate;
  uint32_t stretchLimitUs;
  uint32_t maxUs;
};
constexpr BusSetting kImageBuses[] = {
    {"lp-mspm0l1306-bq76952 / -bq76907, lp-mspm0g3507-bq76952: BQ769x2 4 ms", 400000, 4000, 4000 + 48},
    {"lp-mspm0g3507-bq4050: SMBus tTIMEOUT 25..35 ms", 100000, 25000, 35000},
};

TEST_F(I2cTest, ImageTimeoutsAreTheStretchLimitWithinOneCount) {
  for (const BusSetting& bus : kImageBuses) {
    SCOPED_TRACE(bus.image);
    SetUp();
    I2cController c(config(bus.bitRate, bus.stretchLimitUs));
    c.init();
    const uint64_t us = i2cTimeoutOnTheTwinUs(c);
    EXPECT_GE(us, bus.stretchLimitUs);
    EXPECT_LE(us, bus.maxUs);
    regs().takeViolations();  // the controller left waiting on the held SCL
  }
}

TEST_F(I2cTest, TimingHoldsTheLimitWithinOneCountAtEveryClock) {
  for (uint32_t bus : {32000000U, 16000000U, 8000000U, 4000000U}) {
    for (uint32_t rate : {100000U, 400000U}) {
      for (uint32_t limit : {2000U, 4000U, 25000U}) {
        const I2cTiming t = i2cTiming(bus, rate, limit);
        if (!t.valid) continue;
        SCOPED_TRACE(::testing::Message() << bus << " Hz, " << rate << " bit/s, " << limit << " us");
        // Each TCNTLA count is 16 steps of (1 + TPR) x 12 functional clocks (SLAU847D 21.2).
        const uint64_t countUs = 16ULL * (1 + t.tpr) * 12 * 1000000 / (bus / (t.clkdivRatio + 1U));
        EXPECT_GE(i2cTimeoutUs(t, bus), limit);
        EXPECT_LE(i2cTimeoutUs(t, bus), limit + countUs);
        if (bus != 32000000) continue;  // the twin's BUSCLK
        SetUp();
        I2cController c(
            {0x400F0000, 24, PinFunction{Pin{0, 0, 1}, 3}, PinFunction{Pin{0, 1, 2}, 3}, rate, t});
        c.init();
        const uint64_t measured = i2cTimeoutOnTheTwinUs(c);
        const uint64_t startUs = 1000000 / rate + 1;  // the START's SCL period, rounded up
        EXPECT_GE(measured, i2cTimeoutUs(t, bus));
        EXPECT_LE(measured, i2cTimeoutUs(t, bus) + startUs);
        regs().takeViolations();
      }
    }
  }
  EXPECT_TRUE(i2cTiming(8000000, 400000, 4000).valid);
}

TEST_F(I2cTest, TheTrmWorkedExampleIsTheDriversCount) {
  // SLAU847D 21.2: TCNTLA 0xDA with TPR 19 at a 20 MHz functional clock times out after 41.856 ms.
  EXPECT_EQ(i2cTimeoutUs(I2cTiming{0, 19, 0xDA, true}, 20000000), 41856U);
}

TEST_F(I2cTest, WriteSendsAddressBytesAndStopThenCompletesOnStop) {
  const std::array<uint8_t, 3> bytes{0x3E, 0x22, 0x00};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = bytes;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);

  EXPECT_EQ(regs().writes(kMtxdata), (std::vector<uint32_t>{0x3E, 0x22, 0x00}));
  EXPECT_EQ(regs().lastWrite(kMsa), 0x10U);  // address 0x08 << 1, DIR 0 (tsv note "MSA = (addr7<<1)|DIR")
  EXPECT_EQ(regs().lastWrite(kMctr), mctr(3, true));
  EXPECT_EQ(regs().lastWrite(kPecctl), 0x0U);
  // MCTR last: everything is armed before the controller starts.
  EXPECT_LT(regs().findWrite(kImask, regs().lastWrite(kImask).value()),
            regs().findWrite(kMctr, mctr(3, true)));
  const uint32_t armed = regs().lastWrite(kImask).value();
  EXPECT_EQ(armed & (kNack | kStop | kArbLost | kTimeoutA), kNack | kStop | kArbLost | kTimeoutA);
  EXPECT_EQ(armed & kTxFifoTrig, 0U);  // all 3 bytes fit the 8-byte FIFO
  EXPECT_EQ(armed & kTxDone, 0U);      // no read follows: the STOP ends it

  serve();
  EXPECT_EQ(done, 1);
  EXPECT_EQ(list[0].status, fw::Status::Ok);
  EXPECT_EQ(device.written, (std::vector<uint8_t>{0x3E, 0x22, 0x00}));
  EXPECT_EQ(wire, (std::vector<std::string>{"S 10 3E 22 00 P"}));
  EXPECT_EQ(regs().lastWrite(kImask), 0x0U);
  EXPECT_EQ(regs().readCount(0x400F1020), 0U);  // IIDX is never read: reading it clears a flag
}

TEST_F(I2cTest, WriteReadUsesRepeatedStartAndStoresTheBytes) {
  const std::array<uint8_t, 1> command{0x14};
  std::array<uint8_t, 2> data{};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = command;
  list[0].read = data;
  device.sends = {0x68, 0x33};
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  // First burst without STOP: the controller keeps the bus for the repeated START.
  EXPECT_EQ(regs().lastWrite(kMctr), mctr(1, false));
  serve();
  EXPECT_EQ(regs().writes(kMsa), (std::vector<uint32_t>{0x10, 0x11}));  // then address + R
  EXPECT_EQ(regs().writes(kMctr), (std::vector<uint32_t>{mctr(1, false), mctr(2, true)}));
  EXPECT_EQ(done, 1);
  EXPECT_EQ(list[0].status, fw::Status::Ok);
  EXPECT_EQ(list[0].readCount, 2);
  EXPECT_EQ(data, (std::array<uint8_t, 2>{0x68, 0x33}));
  EXPECT_EQ(wire, (std::vector<std::string>{"S 10 14 Sr 11 [68 33] P"}));
}

TEST_F(I2cTest, LongReadDrainsTheFifoAtItsTrigger) {
  std::array<uint8_t, 12> data{};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x0B;
  list[0].read = data;
  gauge.sends = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kMctr), mctr(12, true));
  serve();
  EXPECT_EQ(list[0].readCount, 12);
  EXPECT_EQ(data[7], 7);
  EXPECT_EQ(data[11], 11);
  EXPECT_EQ(done, 1);
}

// Issue 32 (busy cycles): each interrupt costs the CPU its entry, exit and dispatch, so the driver asks for
// as few as the transfer allows.
TEST_F(I2cTest, AWriteAloneTakesOneInterruptItsStop) {
  const std::array<uint8_t, 3> bytes{0x3E, 0x22, 0x00};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = bytes;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  EXPECT_EQ(serveCounting(), 1);
  EXPECT_EQ(list[0].status, fw::Status::Ok);
  EXPECT_EQ(wire, (std::vector<std::string>{"S 10 3E 22 00 P"}));
}

TEST_F(I2cTest, AReadTakesOneInterruptPerSevenBytesAndItsStop) {
  // The BQ76952 scan's longest read (26 bytes): the RX FIFO drained at 7 of its 8 entries (hw_i2c.h
  // MFIFOCTL.RXTRIG LEVEL_7), and the rest at the STOP; at level 4 it took 6 + 1, and 2 + 6 + 1 with the
  // write before it.
  const std::array<uint8_t, 1> command{0x14};
  std::array<uint8_t, 26> data{};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = command;
  list[0].read = data;
  for (uint8_t i = 0; i < data.size(); ++i)
    device.sends.push_back(static_cast<uint8_t>(0xA0 + i));
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  EXPECT_EQ(serveCounting(), 1 + 3 + 1) << "TXDONE for the repeated START, 3 at 7 bytes, the STOP";
  EXPECT_EQ(list[0].status, fw::Status::Ok);
  EXPECT_EQ(list[0].readCount, 26);
  for (uint8_t i = 0; i < data.size(); ++i)
    EXPECT_EQ(data[i], 0xA0 + i);
}

TEST_F(I2cTest, StartFlushesBothFifosAndWaitsUntilTheyReadEmpty) {
  // A write that ended with a NACK left bytes in the TX FIFO; the next transaction must not send them.
  leaveBytesInTheTxFifo();
  EXPECT_NE(regs().peek(0x400F123C) & 0xF00, 0x800U) << "bytes left in the TX FIFO";
  regs().clearLog();
  const std::array<uint8_t, 2> bytes{0x01, 0x02};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = bytes;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  // Flush bits set, MFIFOSR polled until TXFIFOCNT = 8 free and RXFIFOCNT = 0, then the bits cleared
  // (hw_i2c.h MFIFOCTL.TXFLUSH/RXFLUSH; TI's DL_I2C_flushControllerTXFIFO / ...RXFIFO).
  constexpr uint32_t kFlushBoth = 0x8080;
  const long set = regs().findWrite(kMfifoctl, 0x604 | kFlushBoth);
  const long cleared = regs().findWrite(kMfifoctl, 0x604, static_cast<size_t>(set));
  ASSERT_GE(set, 0);
  ASSERT_GT(cleared, set);
  bool sawEmpty = false;
  for (long i = set; i < cleared; ++i) {
    const Access& a = regs().log()[static_cast<size_t>(i)];
    if (a.kind == Access::Kind::Read && a.address == kMfifosr && (a.value & 0xF0F) == 0x800) sawEmpty = true;
  }
  EXPECT_TRUE(sawEmpty);
  serve();
  EXPECT_EQ(device.written, (std::vector<uint8_t>{0x01, 0x02}));
}

TEST_F(I2cTest, AFlushThatNeverEndsIsFinishedByAControllerReset) {
  leaveBytesInTheTxFifo();
  chip().i2c0().holdFlush();
  const std::array<uint8_t, 1> bytes{0x01};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = bytes;
  regs().clearLog();
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  // The wait is bounded; then the GPRCM reset empties the FIFOs and the controller is configured again.
  EXPECT_LE(regs().readCount(kMfifosr), 100U + 1U);
  EXPECT_GE(regs().findWrite(kRstctl, 0xB1000003), 0);
  EXPECT_EQ(regs().lastWrite(kMctr), mctr(1, true));
  serve();
  EXPECT_EQ(device.written, (std::vector<uint8_t>{0x01}));
}

TEST_F(I2cTest, LongWriteRefillsTheFifoAsItDrains) {
  std::array<uint8_t, 12> bytes{};
  for (uint8_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<uint8_t>(0x40 + i);
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = bytes;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kMctr), mctr(12, true));
  EXPECT_EQ(regs().writes(kMtxdata).size(), 8U);  // the flushed FIFO takes 8
  EXPECT_NE(regs().lastWrite(kImask).value() & kTxFifoTrig, 0U);
  // The rest as the FIFO drains; a write to a full FIFO would stop the twin (i2c.hpp).
  serve();
  EXPECT_EQ(regs().writes(kMtxdata).size(), 12U);
  EXPECT_EQ(regs().lastWrite(kImask), 0x0U);
  EXPECT_EQ(done, 1);
  EXPECT_EQ(list[0].status, fw::Status::Ok);
  EXPECT_EQ(device.written, std::vector<uint8_t>(bytes.begin(), bytes.end()));
}

TEST_F(I2cTest, AddressNackEndsTheListAndAbortsTheRest) {
  const std::array<uint8_t, 1> command{0x14};
  std::array<fw::hal::I2cTransaction, 2> list{};
  list[0].address = 0x08;
  list[0].write = command;
  list[1].address = 0x08;
  list[1].write = command;
  device.nackAddress = true;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  serve();  // the controller sends STOP itself after the NACK; the list ends at STOP
  EXPECT_EQ(list[0].status, fw::Status::Nack);
  EXPECT_EQ(list[1].status, fw::Status::Aborted);
  EXPECT_EQ(done, 1);
  EXPECT_EQ(regs().writes(kMctr).size(), 1U);  // the second transaction never started
}

TEST_F(I2cTest, DataNackIsReportedSeparately) {
  const std::array<uint8_t, 2> bytes{0x66, 0x82};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = bytes;
  device.nackByte = 1;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  serve();
  EXPECT_EQ(list[0].status, fw::Status::DataNack);
}

TEST_F(I2cTest, ListRunsBackToBackFromTheInterrupt) {
  const std::array<uint8_t, 1> a{0x01};
  const std::array<uint8_t, 1> b{0x02};
  std::array<fw::hal::I2cTransaction, 2> list{};
  list[0].address = 0x08;
  list[0].write = a;
  list[1].address = 0x09;
  list[1].write = b;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  serve();
  EXPECT_EQ(regs().writes(kMsa), (std::vector<uint32_t>{0x10, 0x12}));  // second target started from the ISR
  EXPECT_EQ(done, 1);
  EXPECT_EQ(list[0].status, fw::Status::Ok);
  EXPECT_EQ(list[1].status, fw::Status::Ok);
  EXPECT_EQ(wire, (std::vector<std::string>{"S 10 01 P", "S 12 02 P"}));
}

TEST_F(I2cTest, ArbitrationLossEndsWithoutStop) {
  const std::array<uint8_t, 1> a{0x01};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = a;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  chip().pins().setExternal(kSdaPincm, twin::Drive::Low);  // another controller drives SDA at the START
  serve(100);
  EXPECT_EQ(list[0].status, fw::Status::ArbitrationLost);
  EXPECT_EQ(done, 1);
  EXPECT_EQ(device.stops, 0);
}

TEST_F(I2cTest, TimeoutRecoversTheBusWithClocksAndStop) {
  const std::array<uint8_t, 1> a{0x01};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = a;
  device.stretch = fw::ms(3);  // past the 2 ms limit: timeout A
  // Stuck mid-byte, the device also holds SDA, and lets it go at the second recovery clock.
  device.addressed = [this] { holdSda(2); };
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  regs().clearLog();
  serve();

  EXPECT_EQ(list[0].status, fw::Status::Timeout);
  EXPECT_EQ(done, 1);
  // The controller is reset before the pins become GPIOs, the pins are open-drain GPIOs (PF 1) while SCL
  // is clocked, then they return to I2C (PF 3) and the controller is configured again.
  EXPECT_TRUE(regs().wroteInOrder({{kRstctl, 0xB1000003},
                                   {kPincm1, kPincmGpioOpenDrain},
                                   {kPincm2, kPincmGpioOpenDrain},
                                   {kGpioaDoutClr, 0x2},
                                   {kGpioaDoutSet, 0x2},
                                   {kPincm1, kPincmI2c},
                                   {kPincm2, kPincmI2c},
                                   {kMcr, 0x5}}));
  // Two recovery clocks plus the STOP's SCL low phase pull SCL (mask 0x2) low; the STOP pulls SDA (0x1) low
  // once and releases it last.
  const auto clr = regs().writes(kGpioaDoutClr);
  EXPECT_EQ(std::count(clr.begin(), clr.end(), 0x2U), 3);
  EXPECT_EQ(std::count(clr.begin(), clr.end(), 0x1U), 1);
  EXPECT_EQ(regs().lastWrite(kGpioaDoutSet), 0x1U);
  EXPECT_GT(regs().spinCount(), 0U);
}

TEST_F(I2cTest, StuckSdaAfterNineClocksIsBusStuck) {
  const std::array<uint8_t, 1> a{0x01};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = a;
  device.stretch = fw::ms(3);
  device.addressed = [this] { holdSda(-1); };  // SDA never released
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  regs().clearLog();
  serve();
  EXPECT_EQ(list[0].status, fw::Status::BusStuck);
  const auto clr = regs().writes(kGpioaDoutClr);
  EXPECT_EQ(std::count(clr.begin(), clr.end(), 0x2U), 9 + 1);  // nine clocks, then the STOP
}

TEST_F(I2cTest, IdleBusWithSdaLowIsRecoveredBeforeStarting) {
  holdSda(1);  // SDA low on an idle bus; the first recovery clock frees it
  const std::array<uint8_t, 1> a{0x01};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = a;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  EXPECT_GE(regs().findWrite(kPincm1, kPincmGpioOpenDrain), 0);
  EXPECT_EQ(regs().lastWrite(kMctr), mctr(1, true));
  serve();
  EXPECT_EQ(list[0].status, fw::Status::Ok);
}

TEST_F(I2cTest, IdleBusThatStaysStuckIsReportedFromTheInterrupt) {
  holdSda(-1);  // SDA low on an idle bus, and recovery cannot free it
  const std::array<uint8_t, 1> a{0x01};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x08;
  list[0].write = a;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  EXPECT_EQ(done, 0);  // `done` is never called from start() itself
  EXPECT_FALSE(regs().lastWrite(kMctr).has_value());
  EXPECT_EQ(regs().lastWrite(0xE000E200), 1U << 24);  // NVIC ISPR: the I2C0 interrupt is pended
  i2c.onInterrupt();                                  // the pended interrupt, nothing in MIS
  EXPECT_EQ(done, 1);
  EXPECT_EQ(list[0].status, fw::Status::BusStuck);
}

TEST_F(I2cTest, HardwarePecOnWriteCountsThePecByteAndQueuesADummy) {
  const std::array<uint8_t, 3> bytes{0x00, 0x44, 0x00};  // BQ4050 ManufacturerAccess word write
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x0B;
  list[0].write = bytes;
  list[0].pec = true;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  // CONTROLLER_I2CPECCTL: PECEN bit 12, PECCNT 8:0 = data bytes including the PEC byte (TRM PECCNT).
  EXPECT_EQ(regs().lastWrite(kPecctl), (1U << 12) | 4U);
  EXPECT_EQ(regs().writes(kMtxdata), (std::vector<uint32_t>{0x00, 0x44, 0x00, 0x00}));
  EXPECT_EQ(regs().lastWrite(kMctr), mctr(4, true));
  serve();
  EXPECT_EQ(list[0].status, fw::Status::Ok);
  // The controller sends the PEC in place of the dummy.
  EXPECT_EQ(gauge.written, (std::vector<uint8_t>{0x00, 0x44, 0x00, pec({0x16, 0x00, 0x44, 0x00})}));
}

TEST_F(I2cTest, HardwarePecOnReadSpansTheRepeatedStartAndReportsAMismatch) {
  const std::array<uint8_t, 1> command{0x09};  // SBS Voltage
  std::array<uint8_t, 2> word{};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x0B;
  list[0].write = command;
  list[0].read = word;
  list[0].pec = true;
  gauge.sends = {0x10, 0x3A, static_cast<uint8_t>(pec({0x16, 0x09, 0x17, 0x10, 0x3A}) ^ 0xFF)};
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kPecctl), (1U << 12) | 4U);  // 1 command + 2 data + PEC
  serve();
  EXPECT_EQ(regs().lastWrite(kMctr), mctr(3, true));  // the PEC byte is read too
  EXPECT_TRUE(anyImaskWith(kPecRxErr));
  EXPECT_EQ(list[0].status, fw::Status::Pec);
  EXPECT_EQ(list[0].readCount, 2);  // the PEC byte is not stored
  EXPECT_EQ(word, (std::array<uint8_t, 2>{0x10, 0x3A}));
}

// SMBus block reads (hal/i2c_bus.hpp blockRead) against the twin's controller (a receive burst without STOP
// keeps the bus, the next burst without START continues; MCTR.MACKOEN is refused) and a BQ4050-like target:
// ManufacturerBlockAccess (0x44) answers with a count, that many bytes and the PEC, then releases SDA (0xFF).
// The sequence is TI's SMBus library's (smbus_nwk.c).
constexpr uint32_t kRxDone = 1U << 0;
constexpr uint32_t kAckBit = 1U << 3;      // MCTR.ACK
constexpr uint32_t kPecEnable = 1U << 12;  // CONTROLLER_I2CPECCTL.PECEN

struct BlockRead {
  std::array<uint8_t, 1> command{0x44};
  std::array<uint8_t, 33> data{};
  std::array<fw::hal::I2cTransaction, 1> list{};
  BlockRead() {
    list[0].address = 0x0B;
    list[0].write = command;
    list[0].read = data;
    list[0].pec = true;
    list[0].blockRead = true;
  }
};

TEST_F(I2cTest, BlockReadTakesTheCountThenExactlyThatManyBytesAndThePec) {
  BlockRead b;
  const uint8_t p = pec({0x16, 0x44, 0x17, 0x03, 0xA1, 0xA2, 0xA3});
  gauge.sends = {0x03, 0xA1, 0xA2, 0xA3, p};
  ASSERT_EQ(i2c.start(b.list, counter(done)), fw::Status::Ok);
  // PECCNT 0 while the length is unknown (the CRC runs from the START on; TI's SMBus library likewise).
  EXPECT_EQ(regs().lastWrite(kPecctl), kPecEnable);
  serve();
  EXPECT_EQ(regs().writes(kMsa).back(), 0x17U);
  // The count byte alone, ACKed, no STOP, no ACK override (TI's SMBus library: MBLEN 1, ACK, START).
  EXPECT_GE(regs().findWrite(kMctr, (1U << 16) | kAckBit | 0x3U), 0);
  EXPECT_TRUE(anyImaskWith(kRxDone));
  EXPECT_EQ(done, 1);
  EXPECT_EQ(b.list[0].status, fw::Status::Ok);
  EXPECT_EQ(b.list[0].readCount, 4);  // the count and 3 bytes; the PEC is checked, not stored
  EXPECT_EQ((std::vector<uint8_t>(b.data.begin(), b.data.begin() + 5)),
            (std::vector<uint8_t>{0x03, 0xA1, 0xA2, 0xA3, 0x00}));
  // PECCNT = 3 + 1 from the count on, then one burst without START for 3 + PEC bytes, the PEC NACKed, STOP.
  EXPECT_TRUE(regs().wroteInOrder({{kPecctl, kPecEnable | 4U}, {kMctr, (4U << 16) | 0x4U | 0x1U}}));
  char expected[48];
  std::snprintf(expected, sizeof expected, "S 16 44 Sr 17 [03 A1 A2 A3 %02X] P", p);
  EXPECT_EQ(wire, (std::vector<std::string>{expected}));
}

TEST_F(I2cTest, BlockReadWithACountOfZeroOrBeyondTheBufferEndsWithLength) {
  // Room for 32 bytes after the count: 0, 33 and 255 do not fit. The count was already ACKed (the target
  // sends on), so one more byte is read and NACKed before the STOP, and not stored.
  for (uint8_t count : {uint8_t{0}, uint8_t{33}, uint8_t{0xFF}}) {
    SCOPED_TRACE(count);
    SetUp();
    done = 0;
    wire.clear();
    BlockRead b;
    gauge.sends = {count, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99};
    gauge.next = 0;
    ASSERT_EQ(i2c.start(b.list, counter(done)), fw::Status::Ok);
    serve();
    EXPECT_EQ(done, 1);
    EXPECT_EQ(b.list[0].status, fw::Status::Length);
    EXPECT_EQ(b.list[0].readCount, 1);
    char expected[40];
    std::snprintf(expected, sizeof expected, "S 16 44 Sr 17 [%02X 11] P", count);
    EXPECT_EQ(wire, (std::vector<std::string>{expected}));
  }
}

TEST_F(I2cTest, BlockReadOf32BytesDrainsTheFifoOnTheWay) {
  BlockRead b;
  gauge.sends = {0x20};
  for (uint8_t i = 0; i < 32; ++i)
    gauge.sends.push_back(i);
  uint8_t crc = fw::crc::crc8Update(fw::crc::crc8Update(fw::crc::crc8Update(0, 0x16), 0x44), 0x17);
  for (uint8_t byte : gauge.sends)
    crc = fw::crc::crc8Update(crc, byte);
  gauge.sends.push_back(crc);
  ASSERT_EQ(i2c.start(b.list, counter(done)), fw::Status::Ok);
  serve();
  EXPECT_EQ(b.list[0].status, fw::Status::Ok);
  EXPECT_EQ(b.list[0].readCount, 33);
  EXPECT_EQ(b.data[32], 31);
  EXPECT_GE(regs().findWrite(kPecctl, kPecEnable | 33U), 0);
  ASSERT_EQ(wire.size(), 1U);
  EXPECT_EQ(wire[0].substr(0, 20), "S 16 44 Sr 17 [20 00");
}

TEST_F(I2cTest, StartRejectsBadListsAndBusy) {
  std::array<fw::hal::I2cTransaction, 1> empty{};
  empty[0].address = 0x08;
  EXPECT_EQ(i2c.start(empty, {}), fw::Status::InvalidArgument);  // nothing to write or read
  EXPECT_EQ(i2c.start({}, {}), fw::Status::InvalidArgument);
  const std::array<uint8_t, 1> a{0x01};
  std::array<fw::hal::I2cTransaction, 1> list{};
  list[0].address = 0x80;
  list[0].write = a;
  EXPECT_EQ(i2c.start(list, {}), fw::Status::InvalidArgument);  // not a 7-bit address
  list[0].address = 0x08;
  ASSERT_EQ(i2c.start(list, counter(done)), fw::Status::Ok);
  EXPECT_EQ(i2c.start(list, counter(done)), fw::Status::Busy);
  EXPECT_EQ(i2c.recover(), fw::Status::Busy);
  EXPECT_TRUE(regs().log().size() > 0);
  serve();
}

TEST_F(I2cTest, RecoverWhenIdleReportsTheBusState) {
  EXPECT_EQ(i2c.recover(), fw::Status::Ok);
  holdSda(-1);
  EXPECT_EQ(i2c.recover(), fw::Status::BusStuck);
}

}  // namespace
}  // namespace bsp::mspm0::test
