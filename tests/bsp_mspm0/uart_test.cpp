// Register-level tests of the UART drivers (bsp/mspm0/uart_link.*, uart_serial.*) on the twin's UART and DMA
// (bsp/twin/periph/uart.hpp, dma.hpp: FIFOs, trigger levels, EOT, DMA transfers at the baud rate; their
// rules, e.g. the TX DMA trigger needs TXIFLSEL = 7); bytes arrive through the twin's UART (Uart::receive)
// and leave through its transmit sink, and the link's timer on the twin's TIMG6. Addresses: UART0_BASE
// 0x40108000 + UART.* offsets, DMA_BASE 0x4042A000 (channel n at +0x1200 + 0x10n, DMATCTL n at +0x1110 + 4n,
// tsv note "DMA"), TIMG6_BASE 0x40868000 + GPTIMER.* offsets, all from mspm0g3507.tsv; DMA triggers from its
// dmatrig rows (UART0 RX 17, TX 18) and mspm0l1306.tsv (UART0 TX 11).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "chip/mspm0l1306.hpp"
#include "fixture.hpp"
#include "gpio.hpp"
#include "mmio.hpp"
#include "regs/uart.hpp"
#include "uart_link.hpp"
#include "uart_serial.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kUart = 0x40108000;
constexpr uintptr_t kImask = kUart + 0x1028;
constexpr uintptr_t kRis = kUart + 0x1030;
constexpr uintptr_t kIclr = kUart + 0x1048;
constexpr uintptr_t kDmaRxImask = kUart + 0x1058;  // DMA_TRIG_RX.IMASK
constexpr uintptr_t kDmaTxImask = kUart + 0x1088;  // DMA_TRIG_TX.IMASK
constexpr uintptr_t kCtl0 = kUart + 0x1100;
constexpr uintptr_t kLcrh = kUart + 0x1104;
constexpr uintptr_t kStat = kUart + 0x1108;
constexpr uintptr_t kIfls = kUart + 0x110C;
constexpr uintptr_t kIbrd = kUart + 0x1110;
constexpr uintptr_t kFbrd = kUart + 0x1114;
constexpr uintptr_t kTxdata = kUart + 0x1120;
constexpr uintptr_t kDma = 0x4042A000;
constexpr uintptr_t dmaCtl(int ch) {
  return kDma + 0x1200 + 0x10 * ch;
}
constexpr uintptr_t dmaSa(int ch) {
  return dmaCtl(ch) + 4;
}
constexpr uintptr_t dmaDa(int ch) {
  return dmaCtl(ch) + 8;
}
constexpr uintptr_t dmaSz(int ch) {
  return dmaCtl(ch) + 12;
}
constexpr uint32_t kStatBusy = 1U << 0, kStatTxff = 1U << 7;  // hw_uart.h STAT
constexpr uintptr_t dmaTctl(int ch) {
  return kDma + 0x1110 + 4 * ch;
}
constexpr uintptr_t kTimer = 0x40868000;  // TIMG6
constexpr uintptr_t kTimerMis = kTimer + 0x1038;
constexpr uintptr_t kTimerCtrctl = kTimer + 0x1804;
constexpr uintptr_t kTimerLoad = kTimer + 0x1808;
constexpr uintptr_t kPincm21 = 0x40428054;  // PA10
constexpr uintptr_t kGpioaDoeSet = 0x400A12D0;
constexpr uintptr_t kGpioaDoeClr = 0x400A12E0;

// UART_CPU_INT_IMASK_* bits.
constexpr uint32_t kFrmErr = 1U << 1;
constexpr uint32_t kParErr = 1U << 2;
constexpr uint32_t kBrkErr = 1U << 3;
constexpr uint32_t kOvrErr = 1U << 4;
constexpr uint32_t kEot = 1U << 12;
constexpr uint32_t kDmaDoneRx = 1U << 15;
constexpr uint32_t kDmaDoneTx = 1U << 16;
constexpr uint32_t kErrors = kFrmErr | kParErr | kBrkErr | kOvrErr;
// IFLS: TXIFLSEL 2:0 = 7 (LVL_1, "TX FIFO >= 1 entry free", which hw_uart.h marks as needed for the DMA
// trigger and every TI UART TX DMA example uses), RXIFLSEL 6:4 = 7 (LVL_1, one entry, likewise for RX DMA).
constexpr uint32_t kIflsDma = 0x7 | 0x70;
// DMACTL: DMAEN bit 1, DMADSTINCR 23:20 = 3 (increment), DMASRCINCR 19:16 = 3; byte widths, single mode.
constexpr uint32_t kDmaRxCtl = (1U << 1) | (3U << 20);
constexpr uint32_t kDmaTxCtl = (1U << 1) | (3U << 16);
// GPTIMER CTRCTL: EN bit 0, CM 5:4 = 0 (down), CVAE 29:28 = 0 (start at LOAD), REPEAT 0 (stop at zero).
constexpr uint32_t kOneShotDown = 0x1;

UartLink::Config linkConfig() {
  return {kUart,
          15,
          static_cast<uint16_t>(reg::uart::baudDivisor64(32000000, 1000000)),
          1000000,
          PinFunction{Pin{0, 10, 21}, 2},
          PinFunction{Pin{0, 11, 22}, 2},
          DmaChannel{kDma, 0, 17},
          DmaChannel{kDma, 1, 18},
          TimgOneShot::Config{kTimer, 17, 31}};
}

class UartLinkTest : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    powerGpioPort(kGpioaBase);  // the board's bring-up powers the port before the link takes TX for a ping
    link.init();
    regs().clearLog();
  }
  // The bytes the UART sent, as their stop bits leave.
  void listen() {
    chip().uart(0).onTransmit([this](uint8_t b) { sent.push_back(b); });
  }
  // Bytes arriving from the BQ79616 one frame apart (1 Mbaud: 10 us), the DMA taking each.
  void arrive(std::initializer_list<uint8_t> bytes) {
    for (uint8_t b : bytes) {
      chip().uart(0).receive(b, false);
      regs().advanceUs(10);
    }
  }
  // Waits for the link timer's interrupt on the twin's TIMG6 (its zero event) and takes it; returns the
  // microseconds waited.
  uint64_t timerInterrupt() {
    const uint64_t from = chip().machine().now();
    EXPECT_TRUE(regs().runUntilEvent([this] { return regs().peek(kTimerMis) != 0; }, 200000));
    link.onTimerInterrupt();
    return (chip().machine().now() - from) / 32;
  }

  UartLink link{linkConfig()};
  std::vector<uint8_t> sent;
  int done = 0;
};

TEST_F(UartLinkTest, InitSets1MbaudFromThe32MHzBusClock) {
  RegisterTest::SetUp();
  powerGpioPort(kGpioaBase);
  UartLink fresh(linkConfig());
  fresh.init();
  // 32 MHz / (16 * 1 Mbaud) = 2.0: IBRD 2, FBRD 0 (tsv example "UART1 (to BQ79616) ... IBRD=2 FBRD=0").
  EXPECT_EQ(regs().lastWrite(kIbrd), 2U);
  EXPECT_EQ(regs().lastWrite(kFbrd), 0U);
  EXPECT_EQ(regs().lastWrite(kLcrh), 0x30U);                           // WLEN 8 bits, no parity, 1 stop
  EXPECT_EQ(regs().lastWrite(kCtl0), 0x1U | 0x8U | 0x10U | 0x20000U);  // ENABLE RXE TXE FEN
  EXPECT_EQ(regs().lastWrite(kDmaRxImask), 1U << 10);                  // RXINT triggers the DMA
  EXPECT_EQ(regs().lastWrite(kDmaTxImask), 1U << 11);                  // TXINT triggers the DMA
  EXPECT_EQ(regs().lastWrite(kIfls), kIflsDma);
  EXPECT_LT(regs().findWrite(kIbrd, 2), regs().findWrite(kCtl0, 0x1U | 0x8U | 0x10U | 0x20000U));
  EXPECT_EQ(fresh.baudRate(), 1000000U);
}

TEST_F(UartLinkTest, DmaReceiveArmsReceiverFirstAndCompletesWhenFull) {
  const std::array<uint8_t, 6> frame{0xC0, 0x05, 0x68, 0x1F, 0x42, 0x2D};
  std::array<uint8_t, 38> reply{};
  fw::hal::UartExchange ex;
  ex.tx = frame;
  ex.rx = reply;
  regs().dmaBuffer(std::span<const uint8_t>(frame));
  regs().dmaBuffer(std::span<uint8_t>(reply));
  ASSERT_EQ(link.start(ex, counter(done)), fw::Status::Ok);

  EXPECT_EQ(regs().lastWrite(dmaSa(0)), kUart + 0x1124U);  // RXDATA
  EXPECT_EQ(regs().lastWrite(dmaDa(0)), mmio::address(reply.data()));
  EXPECT_EQ(regs().lastWrite(dmaSz(0)), 38U);
  EXPECT_EQ(regs().lastWrite(dmaTctl(0)), 17U);  // DMA_UART0_RX_TRIG
  EXPECT_EQ(regs().lastWrite(dmaCtl(0)), kDmaRxCtl);
  EXPECT_EQ(regs().lastWrite(dmaSa(1)), mmio::address(frame.data()));
  EXPECT_EQ(regs().lastWrite(dmaDa(1)), kUart + 0x1120U);  // TXDATA
  EXPECT_EQ(regs().lastWrite(dmaSz(1)), 6U);
  EXPECT_EQ(regs().lastWrite(dmaTctl(1)), 18U);  // DMA_UART0_TX_TRIG
  EXPECT_EQ(regs().lastWrite(dmaCtl(1)), kDmaTxCtl);
  // The receiver is armed before the transmitter starts.
  EXPECT_LT(regs().findWrite(dmaCtl(0), kDmaRxCtl), regs().findWrite(dmaCtl(1), kDmaTxCtl));
  EXPECT_EQ(regs().lastWrite(kImask), kErrors | kDmaDoneRx | kEot);

  regs().advanceUs(70);    // six frames at 1 Mbaud
  link.onUartInterrupt();  // EOT, last stop bit sent: the first-byte timeout starts
  EXPECT_EQ(regs().lastWrite(kIclr), kEot);
  EXPECT_EQ(regs().lastWrite(kTimerLoad), 2000U);  // UartExchange default firstByteTimeout = 2 ms
  EXPECT_EQ(regs().lastWrite(kTimerCtrctl), kOneShotDown);

  for (uint8_t i = 0; i < 38; ++i)
    arrive({static_cast<uint8_t>(0xA0 + i)});
  link.onUartInterrupt();  // DMA_DONE_RX
  EXPECT_EQ(done, 1);
  EXPECT_EQ(ex.status, fw::Status::Ok);
  EXPECT_EQ(ex.received, 38U);
  EXPECT_EQ(reply[0], 0xA0);
  EXPECT_EQ(reply[37], 0xA0 + 37);
  EXPECT_EQ(regs().lastWrite(dmaCtl(0)), 0U);  // channels stopped
  EXPECT_EQ(regs().lastWrite(dmaCtl(1)), 0U);
  EXPECT_EQ(regs().lastWrite(kTimerCtrctl), 0U);
}

TEST_F(UartLinkTest, TransmitRunsOnTheTxDmaTriggerAndEndsAtEndOfTransmission) {
  // BQ79616 TX path: DMA channel 1 on DMA_UART0_TX_TRIG (18), fed one byte per free FIFO entry.
  const std::array<uint8_t, 7> frame{0x90, 0x00, 0x03, 0x09, 0x20, 0x13, 0x95};
  fw::hal::UartExchange ex;
  ex.tx = frame;  // a write: nothing to receive
  regs().dmaBuffer(std::span<const uint8_t>(frame));
  listen();
  ASSERT_EQ(link.start(ex, counter(done)), fw::Status::Ok);
  regs().advanceUs(100);
  EXPECT_EQ(sent, std::vector<uint8_t>(frame.begin(), frame.end()));
  link.onUartInterrupt();  // EOT
  EXPECT_EQ(done, 1);
  EXPECT_EQ(ex.status, fw::Status::Ok);
}

TEST_F(UartLinkTest, ReceiveTimeoutAfterAGapIsTruncated) {
  const std::array<uint8_t, 1> tx{0x80};
  std::array<uint8_t, 8> rx{};
  fw::hal::UartExchange ex;
  ex.tx = tx;
  ex.rx = rx;
  ex.firstByteTimeout = fw::us(1500);
  ex.gapTimeout = fw::us(100);
  regs().dmaBuffer(std::span<const uint8_t>(tx));
  regs().dmaBuffer(std::span<uint8_t>(rx));
  ASSERT_EQ(link.start(ex, counter(done)), fw::Status::Ok);
  regs().advanceUs(20);
  link.onUartInterrupt();  // EOT
  EXPECT_EQ(regs().lastWrite(kTimerLoad), 1500U);
  arrive({0x01, 0x02, 0x03});  // three bytes arrive before the first-byte timeout
  timerInterrupt();
  EXPECT_EQ(done, 0);
  EXPECT_EQ(regs().lastWrite(kTimerLoad), 100U);  // now watching the inter-byte gap
  timerInterrupt();                               // no progress for one gap
  EXPECT_EQ(done, 1);
  EXPECT_EQ(ex.status, fw::Status::Truncated);
  EXPECT_EQ(ex.received, 3U);
  EXPECT_EQ(rx[2], 0x03);
}

TEST_F(UartLinkTest, SilenceIsNoResponse) {
  std::array<uint8_t, 4> rx{};
  fw::hal::UartExchange ex;
  ex.rx = rx;  // receive only: the first-byte timeout starts at once
  regs().dmaBuffer(std::span<uint8_t>(rx));
  ASSERT_EQ(link.start(ex, counter(done)), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kTimerLoad), 2000U);
  regs().advanceUs(2000);  // nothing arrives
  timerInterrupt();
  EXPECT_EQ(ex.status, fw::Status::NoResponse);
  EXPECT_EQ(ex.received, 0U);
  EXPECT_EQ(done, 1);
}

TEST_F(UartLinkTest, LineErrorIsCommFault) {
  const std::array<uint8_t, 1> tx{0x80};
  std::array<uint8_t, 4> rx{};
  fw::hal::UartExchange ex;
  ex.tx = tx;
  ex.rx = rx;
  regs().dmaBuffer(std::span<const uint8_t>(tx));
  regs().dmaBuffer(std::span<uint8_t>(rx));
  ASSERT_EQ(link.start(ex, counter(done)), fw::Status::Ok);
  regs().advanceUs(20);
  link.onUartInterrupt();  // EOT
  arrive({0x55});
  chip().uart(0).receive(0x00, true);  // a byte with a framing error: FRMERR, and the DMA moves it too
  link.onUartInterrupt();
  EXPECT_EQ(ex.status, fw::Status::CommFault);
  EXPECT_EQ(ex.received, 2U);  // what reached the buffer; the status says the frame is bad
  EXPECT_EQ(regs().lastWrite(kIclr), kFrmErr);
}

TEST_F(UartLinkTest, PingHoldsTxLowForAHardwareTimedInterval) {
  ASSERT_EQ(link.ping(fw::ms(2), counter(done)), fw::Status::Ok);
  // TX (PA10) becomes a GPIO driving its preset low level: DOE set, PINCM21 = PC | PF 1 (GPIO).
  EXPECT_EQ(regs().lastWrite(kGpioaDoeSet), 1U << 10);
  EXPECT_EQ(regs().lastWrite(kPincm21), 0x80U | 1U);
  EXPECT_EQ(regs().lastWrite(kTimerLoad), 2000U);
  EXPECT_EQ(regs().lastWrite(kTimerCtrctl), kOneShotDown);
  EXPECT_EQ(regs().spinCount(), 0U);  // no busy loop: the timer measures the pulse
  EXPECT_EQ(link.ping(fw::ms(2), counter(done)), fw::Status::Busy);
  EXPECT_EQ(done, 0);

  const uint64_t pulseUs = timerInterrupt();
  EXPECT_GE(pulseUs, 1999U);
  EXPECT_LE(pulseUs, 2001U);
  EXPECT_EQ(regs().lastWrite(kPincm21), 0x80U | 2U);  // back to UART0_TX (PF 2)
  EXPECT_EQ(regs().lastWrite(kGpioaDoeClr), 1U << 10);
  EXPECT_EQ(done, 1);
  EXPECT_EQ(link.ping(fw::Duration{}, {}), fw::Status::InvalidArgument);
}

TEST_F(UartLinkTest, LongPingRunsInTimerChunks) {
  ASSERT_EQ(link.ping(fw::ms(100), counter(done)), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kTimerLoad), 0xFFFFU);
  uint64_t pulseUs = timerInterrupt();
  EXPECT_EQ(done, 0);
  EXPECT_EQ(regs().lastWrite(kTimerLoad), 100000U - 0xFFFFU);
  pulseUs += timerInterrupt();
  EXPECT_EQ(done, 1);
  EXPECT_GE(pulseUs, 99999U);
  EXPECT_LE(pulseUs, 100001U);
}

TEST_F(UartLinkTest, AbortStopsEverythingWithoutDone) {
  std::array<uint8_t, 4> rx{};
  fw::hal::UartExchange ex;
  ex.rx = rx;
  regs().dmaBuffer(std::span<uint8_t>(rx));
  ASSERT_EQ(link.start(ex, counter(done)), fw::Status::Ok);
  link.abort();
  EXPECT_EQ(regs().lastWrite(kImask), 0U);
  EXPECT_EQ(regs().lastWrite(dmaCtl(0)), 0U);
  EXPECT_EQ(done, 0);
  EXPECT_EQ(link.start(ex, counter(done)), fw::Status::Ok);  // idle again
}

TEST_F(UartLinkTest, StartRejectsEmptyAndBusy) {
  fw::hal::UartExchange empty;
  EXPECT_EQ(link.start(empty, {}), fw::Status::InvalidArgument);
  ASSERT_EQ(link.ping(fw::us(250), counter(done)), fw::Status::Ok);
  std::array<uint8_t, 1> rx{};
  fw::hal::UartExchange ex;
  ex.rx = rx;
  EXPECT_EQ(link.start(ex, {}), fw::Status::Busy);
}

class SerialTxTest : public RegisterTest {
 protected:
  SerialTxTest() : RegisterTest(twin::Part::L1306) {}
  void listen() {
    chip().uart(0).onTransmit([this](uint8_t b) { sent.push_back(b); });
  }
  std::vector<uint8_t> sent;
  // L1306 back-channel: UART0 (same base on both parts) on its back-channel TX pin, DMA channel 0, trigger 11
  // (mspm0l1306.tsv dmatrig DMA_UART0_TX_TRIG).
  UartSerial serial{{kUart, 15, static_cast<uint16_t>(reg::uart::baudDivisor64(32000000, 115200)),
                     chip::Mspm0l1306::kUart0TxPa8, DmaChannel{kDma, 0, 11}}};
  int done = 0;
};

TEST_F(SerialTxTest, InitSets115200BaudOnTheBackChannelPin) {
  serial.init();
  // 32 MHz / (16 * 115200) = 17.361: IBRD 17, FBRD round(0.361 * 64) = 23.
  EXPECT_EQ(regs().lastWrite(kIbrd), 17U);
  EXPECT_EQ(regs().lastWrite(kFbrd), 23U);
  EXPECT_EQ(regs().lastWrite(kIfls), kIflsDma);
  // PINCM9 = PA8, PF 2 = UART0_TX (mspm0l130x.h IOMUX_PINCM9_PF_UART0_TX; the LP-MSPM0L1306 back-channel,
  // tsv note "LP-MSPM0L1306 backchannel UART").
  EXPECT_EQ(regs().lastWrite(0x40428024), 0x80U | 2U);
  EXPECT_EQ(regs().lastWrite(0xE000E100), 1U << 15);  // UART0 is IRQ 15
}

TEST_F(SerialTxTest, SlcanTextLeavesByDmaAtOneFreeEntryAndIsDoneAtEndOfTransmission) {
  serial.init();
  const std::array<uint8_t, 12> text{'t', '1', '0', '0', '2', '1', '6', 'C', '0', '1', '6', '\r'};
  regs().dmaBuffer(std::span<const uint8_t>(text));
  listen();
  ASSERT_EQ(serial.write(text, counter(done)), fw::Status::Ok);
  ASSERT_TRUE(regs().runUntil([this] { return sent.size() == 5; }, 1000));
  // The DMA keeps the 4-entry FIFO topped up while the line sends.
  EXPECT_NE(regs().peek(kStat) & kStatTxff, 0U);
  ASSERT_TRUE(regs().runUntil([this] { return (regs().peek(kStat) & kStatBusy) == 0; }, 2000));
  EXPECT_EQ(sent, std::vector<uint8_t>(text.begin(), text.end()));
  serial.onInterrupt();  // DMA_DONE_TX: the line is already idle
  EXPECT_EQ(done, 1);
}

TEST_F(SerialTxTest, WriteFeedsTheFifoByDmaAndCompletesAtEndOfTransmission) {
  serial.init();
  regs().clearLog();
  const std::array<uint8_t, 5> line{'t', '7', 'F', 'F', '\r'};
  regs().dmaBuffer(std::span<const uint8_t>(line));
  ASSERT_EQ(serial.write(line, counter(done)), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(dmaSa(0)), mmio::address(line.data()));
  EXPECT_EQ(regs().lastWrite(dmaDa(0)), kUart + 0x1120U);
  EXPECT_EQ(regs().lastWrite(dmaSz(0)), 5U);
  EXPECT_EQ(regs().lastWrite(dmaTctl(0)), 11U);
  EXPECT_EQ(regs().lastWrite(kImask), kDmaDoneTx);
  EXPECT_EQ(serial.write(line, {}), fw::Status::Busy);

  // DMA_DONE_TX comes with the last bytes still shifting out (STAT.BUSY)...
  ASSERT_TRUE(regs().runUntil([this] { return (regs().peek(kRis) & kDmaDoneTx) != 0; }, 1000));
  serial.onInterrupt();
  EXPECT_EQ(done, 0);
  EXPECT_EQ(regs().lastWrite(kImask), kEot);
  // ... and the line is done at EOT.
  ASSERT_TRUE(regs().runUntil([this] { return (regs().peek(kRis) & kEot) != 0; }, 1000));
  serial.onInterrupt();
  EXPECT_EQ(done, 1);
  EXPECT_EQ(serial.write({}, {}), fw::Status::InvalidArgument);
  EXPECT_EQ(serial.write(line, {}), fw::Status::Ok);
}

// The same UART receiving too: PA9 (PINCM10, PF 2, mspm0l130x.h IOMUX_PINCM10_PF_UART0_RX), by interrupt.
class SerialRxTest : public RegisterTest {
 protected:
  SerialRxTest() : RegisterTest(twin::Part::L1306) {}
  static constexpr uint32_t kRx = 1U << 10;  // CPU_INT RXINT (hw_uart.h UART_CPU_INT_IMASK_RXINT, bit 10)
  static constexpr uint32_t kRxFrmErr = 1U << 8;  // RXDATA.FRMERR (hw_uart.h UART_RXDATA_FRMERR)
  UartSerial::RxBuffer ring;
  UartSerial serial{{kUart, 15, static_cast<uint16_t>(reg::uart::baudDivisor64(32000000, 115200)),
                     chip::Mspm0l1306::kUart0TxPa8, DmaChannel{kDma, 0, 11}, chip::Mspm0l1306::kUart0RxPa9},
                    &ring};
  // Bytes arriving at 115200 Bd (87 us a frame) into the 4-entry RX FIFO; bit 8: with a framing error.
  void arrive(std::initializer_list<uint32_t> data) {
    for (uint32_t d : data) {
      chip().uart(0).receive(static_cast<uint8_t>(d), (d & kRxFrmErr) != 0);
      regs().advanceUs(87);
    }
  }
  int received = 0;
  int done = 0;
};

TEST_F(SerialRxTest, InitEnablesTheReceiverOnPa9WithItsInterruptAndNoDma) {
  serial.init();
  // PINCM10: PC (bit 7), PF 2, INENA (bit 18) and the pull-up PIPU (bit 17): an open line idles high.
  EXPECT_EQ(regs().lastWrite(0x40428028), 0x80U | 2U | (1U << 18) | (1U << 17));
  EXPECT_EQ(regs().lastWrite(kCtl0).value_or(0) & 0x8U, 0x8U);  // CTL0.RXE
  EXPECT_EQ(regs().lastWrite(kImask), kRx | kOvrErr);
  EXPECT_FALSE(regs().lastWrite(kDmaRxImask).has_value());  // no RX DMA trigger: the CPU takes the bytes
}

TEST_F(SerialRxTest, BytesAreTakenAfterTheFlagIsClearedAndErroredOnesAreDropped) {
  serial.init();
  serial.onReceive(counter(received));
  regs().clearLog();
  arrive({'O', 0x100 | 'x', '\r'});  // the middle byte came with a framing error
  serial.onInterrupt();
  EXPECT_EQ(received, 1);
  // ICLR of RXINT before the first RXDATA read: a byte arriving after the clear interrupts again.
  EXPECT_EQ(regs().lastWrite(kIclr), kRx);
  uint8_t b = 0;
  ASSERT_TRUE(serial.read(b));
  EXPECT_EQ(b, 'O');
  ASSERT_TRUE(serial.read(b));
  EXPECT_EQ(b, '\r');
  EXPECT_FALSE(serial.read(b));
  EXPECT_EQ(serial.lost(), 1U);
  static_assert(kRxFrmErr == 0x100);
}

TEST_F(SerialRxTest, AFullRingDropsAndCountsAndAnOverrunCountsToo) {
  serial.init();
  for (int i = 0; i < 70; ++i)
    arrive({static_cast<uint32_t>('a' + i % 26)}), serial.onInterrupt();
  EXPECT_EQ(serial.lost(), 70U - UartSerial::kRxBuffer);
  uint8_t b = 0;
  while (serial.read(b)) {
  }
  arrive({'1', '2', '3', '4', '5'});  // five bytes while the CPU is away: the fifth overruns the FIFO
  serial.onInterrupt();
  EXPECT_EQ(serial.lost(), 70U - UartSerial::kRxBuffer + 1);
}

TEST_F(SerialRxTest, TransmittingKeepsTheReceiveInterruptsEnabled) {
  serial.init();
  serial.onReceive(counter(received));
  const std::array<uint8_t, 2> line{'z', '\r'};
  regs().dmaBuffer(std::span<const uint8_t>(line));
  ASSERT_EQ(serial.write(line, counter(done)), fw::Status::Ok);
  EXPECT_EQ(regs().lastWrite(kImask), kRx | kOvrErr | kDmaDoneTx);
  // A byte and the end of the DMA in one interrupt: each side clears only its own flags.
  arrive({'C'});
  ASSERT_TRUE(regs().runUntil([this] { return (regs().peek(kStat) & kStatBusy) == 0; }, 1000));
  serial.onInterrupt();  // the line is idle: done at once
  EXPECT_EQ(received, 1);
  EXPECT_EQ(done, 1);
  EXPECT_EQ(regs().lastWrite(kImask), kRx | kOvrErr);
  EXPECT_TRUE(regs().wroteInOrder({{kIclr, kRx}, {kIclr, kDmaDoneTx}}));
}

}  // namespace
}  // namespace bsp::mspm0::test
