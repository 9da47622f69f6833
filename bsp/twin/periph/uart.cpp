#include "periph/uart.hpp"

#include <algorithm>
#include <cstdio>

#include "machine.hpp"

namespace twin {

namespace {

constexpr uint32_t kClksel = 0x1008, kDmaTrigRx = 0x1050, kDmaTrigTx = 0x1080;
constexpr uint32_t kCtl0 = 0x1100, kLcrh = 0x1104, kStat = 0x1108, kIfls = 0x110C, kIbrd = 0x1110;
constexpr uint32_t kFbrd = 0x1114, kGfctl = 0x1118, kTxdata = 0x1120, kRxdata = 0x1124;

constexpr uint32_t kEnable = 1U << 0, kLbe = 1U << 2, kRxe = 1U << 3, kTxe = 1U << 4, kMenc = 1U << 7;
constexpr uint32_t kModeMask = 0x700, kRtsen = 1U << 13, kCtsen = 1U << 14, kHseShift = 15, kFen = 1U << 17;
constexpr uint32_t kPen = 1U << 1, kStp2 = 1U << 3;
constexpr uint32_t kStatBusy = 1U << 0, kStatRxfe = 1U << 2, kStatRxff = 1U << 3, kStatTxfe = 1U << 6;
constexpr uint32_t kStatTxff = 1U << 7;
constexpr size_t kFifoDepth = 4;
constexpr uint32_t kLevelDma = 7;  // "TX FIFO >= 1 entry free" / "RX FIFO >= 1 entry available"

// Fill level a transition through which raises the trigger (IFLS encodings, hw_uart.h). Undefined settings
// use the default (1/2): "for undefined settings the default configuration is used".
size_t txThreshold(uint32_t level) {
  switch (level) {
    case 1:
      return 1;  // 3/4 empty
    case 3:
      return 3;  // 1/4 empty
    case 5:
      return 0;  // empty
    default:
      return 2;
  }
}
size_t rxThreshold(uint32_t level) {
  switch (level) {
    case 0:
    case 1:
      return 1;
    case 3:
      return 3;
    case 4:
    case 5:
      return 4;  // full
    default:
      return 2;
  }
}

}  // namespace

Uart::Uart(Machine& machine, const char* name, Dma& dma, int rxTrigger, int txTrigger)
    : Peripheral(machine, name),
      dma_(dma),
      rxTrigger_(rxTrigger),
      txTrigger_(txTrigger),
      frameEnd_(machine.timeline(), [this] { frameDone(); }) {
  if (rxTrigger_ > 0) dma.connect(rxTrigger_, *this);
  if (txTrigger_ > 0) dma.connect(txTrigger_, *this);
}

void Uart::resetRegisters() {
  clock_ = ClockRegs(kClksel);
  ctl0_ = lcrh_ = ibrd_ = fbrd_ = gfctl_ = 0;
  ifls_ = 0x22;  // TX 1/2 and RX 1/2: "(default)" in hw_uart.h IFLS
  dmaRx_ = {};
  dmaTx_ = {};
  txFifo_.clear();
  rxFifo_.clear();
  shifting_ = false;
  frameRemainder64_ = 0;
  frameEnd_.cancel();
  linkChecked_ = false;
  txDmaDone_ = false;
}

bool Uart::enabled() const {
  return powered() && (ctl0_ & kEnable);
}

bool Uart::receiving() const {
  return enabled() && (ctl0_ & kRxe) != 0;
}

size_t Uart::depth() const {
  return (ctl0_ & kFen) ? kFifoDepth : 1;
}

uint64_t Uart::frameCycles64() const {
  const uint64_t divisor64 = 64ULL * (ibrd_ & 0xFFFF) + (fbrd_ & 0x3F);
  const uint32_t hse = (ctl0_ >> kHseShift) & 3U;
  const uint64_t oversampling = hse == 0 ? 16 : hse == 1 ? 8 : 3;
  const uint64_t bits = 1 + (5 + ((lcrh_ >> 4) & 3U)) + ((lcrh_ & kPen) ? 1 : 0) + ((lcrh_ & kStp2) ? 2 : 1);
  return bits * oversampling * divisor64 * clock_.divider();
}

uint64_t Uart::baud64() const {
  const uint64_t divisor64 = 64ULL * (ibrd_ & 0xFFFF) + (fbrd_ & 0x3F);
  const uint32_t hse = (ctl0_ >> kHseShift) & 3U;
  const uint64_t oversampling = hse == 0 ? 16 : hse == 1 ? 8 : 3;
  if (divisor64 == 0) return 0;
  return static_cast<uint64_t>(machine_.clockHz()) * 64 * 64 / (clock_.divider() * oversampling * divisor64);
}

void Uart::checkLink() {
  if (linkChecked_ || link_.baud == 0) return;
  linkChecked_ = true;
  const uint32_t dataBits = 5 + ((lcrh_ >> 4) & 3U);
  const bool parity = (lcrh_ & kPen) != 0;
  if (dataBits != link_.dataBits || parity != link_.parity) {
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "%s: LCRH 0x%02X frames %u data bits%s against the %s's %u data bits%s: every byte is "
                  "misread on both sides",
                  name(), lcrh_ & 0xFF, dataBits, parity ? " with parity" : ", no parity",
                  link_.partner.c_str(), link_.dataBits, link_.parity ? " with parity" : ", no parity");
    machine_.violate(Rule::UartFrame, buf);
    return;
  }
  const uint32_t hse = (ctl0_ >> kHseShift) & 3U;
  const int64_t oversampling = hse == 0 ? 16 : hse == 1 ? 8 : 3;
  // The MSPM0 receiver's margin in ppm: (1/2 - 1/oversampling) / 9.5 of a bit; half of it is ours.
  const int64_t ownPpm = (1000000 * (oversampling - 2) / (2 * oversampling)) * 10 / 95 / 2;
  const int64_t tolerance = std::min<int64_t>(link_.tolerancePpm, ownPpm);
  const auto actual64 = static_cast<int64_t>(baud64());
  const int64_t target64 = static_cast<int64_t>(link_.baud) * 64;
  const int64_t errorPpm = (actual64 - target64) * 1000000 / target64;
  if (errorPpm <= tolerance && errorPpm >= -tolerance) return;
  char buf[240];
  std::snprintf(
      buf, sizeof buf,
      "%s: %.0f Bd (IBRD %u, FBRD %u, %dx oversampling, CLKDIV /%u) against the %s's %u Bd: %+.2f %%, "
      "beyond the +-%.2f %% the receivers allow (%s)",
      name(), static_cast<double>(actual64) / 64.0, ibrd_ & 0xFFFF, fbrd_ & 0x3F,
      static_cast<int>(oversampling), clock_.divider(), link_.partner.c_str(), link_.baud,
      static_cast<double>(errorPpm) / 1e4, static_cast<double>(tolerance) / 1e4, link_.source.c_str());
  machine_.violate(Rule::UartBaud, buf);
}

void Uart::checkMode() {
  if ((ctl0_ & kEnable) == 0) return;
  if ((ctl0_ & (kLbe | kMenc | kModeMask | kRtsen | kCtsen)) != 0 || ((ctl0_ >> kHseShift) & 3U) > 2) {
    char buf[112];
    std::snprintf(buf, sizeof buf, "CTL0 0x%08X enables a mode the twin does not model (only plain UART)",
                  ctl0_);
    stop(buf);
  }
  if (!clock_.busclk()) stop("enabled without BUSCLK as its clock (CLKSEL)");
  if ((ibrd_ & 0xFFFF) == 0) stop("enabled with IBRD = 0");
}

void Uart::raiseEvent(uint32_t bit) {
  raise(bit);
  if (bit == kTxInt) {
    dmaTx_.ris |= bit;
    if (dmaTx_.mis() & bit) dma_.requestRaised(txTrigger_);
  } else if (bit == kRxInt) {
    dmaRx_.ris |= bit;
    if (dmaRx_.mis() & bit) dma_.requestRaised(rxTrigger_);
  }
}

void Uart::txFillChanged(size_t before) {
  const size_t after = txFifo_.size();
  const uint32_t level = ifls_ & 7U;
  if (level == kLevelDma) {
    if (after < depth()) raiseEvent(kTxInt);
    return;
  }
  const size_t threshold = (ctl0_ & kFen) ? txThreshold(level) : 0;
  if (before > threshold && after <= threshold) raiseEvent(kTxInt);
}

void Uart::rxFillChanged(size_t before) {
  const size_t after = rxFifo_.size();
  const uint32_t level = (ifls_ >> 4) & 7U;
  if (level == kLevelDma) {
    if (after >= 1) raiseEvent(kRxInt);
    return;
  }
  const size_t threshold = (ctl0_ & kFen) ? rxThreshold(level) : 1;
  if (before < threshold && after >= threshold) raiseEvent(kRxInt);
}

void Uart::startNextFrame() {
  if (shifting_ || txFifo_.empty() || !enabled() || (ctl0_ & kTxe) == 0) return;
  checkLink();
  const size_t before = txFifo_.size();
  shiftByte_ = txFifo_.front();
  txFifo_.pop_front();
  shifting_ = true;
  const uint64_t cycles64 = frameCycles64() + frameRemainder64_;
  frameRemainder64_ = cycles64 % 64;
  frameEnd_.after(cycles64 / 64);
  txFillChanged(before);
}

void Uart::frameDone() {
  shifting_ = false;
  if (txSink_) txSink_(shiftByte_);
  if (!txFifo_.empty()) {
    startNextFrame();
    return;
  }
  if (ctl0_ & kRxe) raise(kEot);  // not with TXE alone: UART_ERR_02 (SLAZ742G, SLAZ741B)
  checkTxEndSeen();
}

void Uart::checkTxEndSeen() {
  if (!txDmaDone_) return;
  txDmaDone_ = false;
  const uint32_t imask = cpuInt_.imask;
  // IMASK 0: the driver has closed the exchange (nothing waits for the end); a TX-end source unmasked: it
  // hears of it.
  if (imask == 0 || (imask & (kEot | kDmaDoneTx | kTxInt)) != 0) return;
  char buf[240];
  std::snprintf(buf, sizeof buf,
                "%s: a DMA transmission ended (last stop bit sent) with CPU_INT.IMASK 0x%05X: neither EOT, "
                "DMA_DONE_TX nor TXINT is unmasked, so nothing tells the CPU the transmission is over",
                name(), imask);
  machine_.violate(Rule::UartTxEndUnseen, buf);
}

void Uart::receive(uint8_t byte, bool framingError) {
  if (!enabled() || (ctl0_ & kRxe) == 0) return;  // the receiver is off: the byte is not sampled
  checkLink();
  if (framingError) raise(kFrmErr);
  if (rxFifo_.size() >= depth()) {
    raise(kOvrErr);  // the FIFO is full: this byte is lost
    return;
  }
  const size_t before = rxFifo_.size();
  rxFifo_.push_back(static_cast<uint16_t>(byte | (framingError ? 1U << 8 : 0U)));
  rxFillChanged(before);
}

bool Uart::dmaRequested(int trigger) const {
  if (trigger == txTrigger_) return (dmaTx_.mis() & kTxInt) != 0;
  if (trigger == rxTrigger_) return (dmaRx_.mis() & kRxInt) != 0;
  return false;
}

void Uart::dmaAcknowledge(int trigger) {
  if (trigger == txTrigger_) dmaTx_.ris &= ~kTxInt;
  if (trigger == rxTrigger_) dmaRx_.ris &= ~kRxInt;
}

std::string Uart::dmaTriggerProblem(int trigger, Rule& rule) const {
  const bool tx = trigger == txTrigger_;
  const uint32_t level = tx ? (ifls_ & 7U) : ((ifls_ >> 4) & 7U);
  if (level == kLevelDma) return "";
  rule = Rule::UartDmaLevel;
  char buf[200];
  std::snprintf(
      buf, sizeof buf,
      "IFLS.%s %u, not 7 (\"%s\", the level made for the DMA): the trigger fires only on a transition "
      "through its level, which an idle FIFO never makes",
      tx ? "TXIFLSEL" : "RXIFLSEL", level, tx ? "TX FIFO >= 1 entry free" : "RX FIFO >= 1 entry available");
  return buf;
}

void Uart::dmaDone(int trigger) {
  if (trigger == txTrigger_) txDmaDone_ = true;
  raise(trigger == txTrigger_ ? kDmaDoneTx : kDmaDoneRx);
}

bool Uart::readRegister(uint32_t offset, uint32_t& value) {
  if (offset - kDmaTrigRx < 0x30) return dmaRx_.read(offset - kDmaTrigRx, value);
  if (offset - kDmaTrigTx < 0x30) return dmaTx_.read(offset - kDmaTrigTx, value);
  if (clock_.read(offset, value)) return true;
  switch (offset) {
    case kCtl0:
      value = ctl0_;
      return true;
    case kLcrh:
      value = lcrh_;
      return true;
    case kIfls:
      value = ifls_;
      return true;
    case kIbrd:
      value = ibrd_;
      return true;
    case kFbrd:
      value = fbrd_;
      return true;
    case kGfctl:
      value = gfctl_;
      return true;
    case kTxdata:
      value = 0;
      return true;
    case kStat:
      value = ((shifting_ || !txFifo_.empty()) ? kStatBusy : 0) | (rxFifo_.empty() ? kStatRxfe : 0) |
              (rxFifo_.size() >= depth() ? kStatRxff : 0) | (txFifo_.empty() ? kStatTxfe : 0) |
              (txFifo_.size() >= depth() ? kStatTxff : 0);
      return true;
    case kRxdata: {
      if (rxFifo_.empty()) {
        value = 0;
        return true;
      }
      const size_t before = rxFifo_.size();
      value = rxFifo_.front();
      rxFifo_.pop_front();
      rxFillChanged(before);
      return true;
    }
    default:
      return false;
  }
}

bool Uart::writeRegister(uint32_t offset, uint32_t value) {
  if (offset - kDmaTrigRx < 0x30) {
    const bool ok = dmaRx_.write(offset - kDmaTrigRx, value);
    if (dmaRx_.mis() & kRxInt) dma_.requestRaised(rxTrigger_);
    return ok;
  }
  if (offset - kDmaTrigTx < 0x30) {
    const bool ok = dmaTx_.write(offset - kDmaTrigTx, value);
    if (dmaTx_.mis() & kTxInt) dma_.requestRaised(txTrigger_);
    return ok;
  }
  if (clock_.write(offset, value)) {
    linkChecked_ = false;
    return true;  // BUSCLK is checked when the UART is enabled
  }
  if (offset == kLcrh || offset == kIbrd || offset == kFbrd || offset == kCtl0) linkChecked_ = false;
  switch (offset) {
    case kLcrh:
      lcrh_ = value;
      return true;
    case kIfls:
      ifls_ = value;
      return true;
    case kIbrd:
      ibrd_ = value;
      return true;
    case kFbrd:
      fbrd_ = value;
      return true;
    case kGfctl:
      gfctl_ = value;
      return true;
    case kStat:
    case kRxdata:
      return true;  // read-only
    case kCtl0: {
      const bool wasTx = enabled() && (ctl0_ & kTxe);
      ctl0_ = value;
      checkMode();
      const bool isTx = enabled() && (ctl0_ & kTxe);
      // The DMA levels are conditions: a transmitter that comes up with room in its FIFO requests at once.
      if (isTx && !wasTx) {
        if ((ifls_ & 7U) == kLevelDma && txFifo_.size() < depth()) raiseEvent(kTxInt);
        startNextFrame();
      }
      return true;
    }
    case kTxdata: {
      if (txFifo_.size() >= depth()) {
        char buf[96];
        std::snprintf(buf, sizeof buf,
                      "TXDATA written (0x%02X) with the TX FIFO full: the byte would be lost", value & 0xFF);
        stop(buf);
        return true;
      }
      const size_t before = txFifo_.size();
      txFifo_.push_back(static_cast<uint8_t>(value));
      txFillChanged(before);
      startNextFrame();
      return true;
    }
    default:
      return false;
  }
}

}  // namespace twin
