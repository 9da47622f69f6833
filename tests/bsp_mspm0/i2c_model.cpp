#include "i2c_model.hpp"

#include <cstdio>

#include "mmio_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kRstctl = 0x0804;
constexpr uintptr_t kClkdiv = 0x1000;
constexpr uintptr_t kGfctl = 0x1200;
constexpr uintptr_t kTimeoutCtl = 0x1204;
constexpr uintptr_t kMrxdata = 0x121C;
constexpr uintptr_t kMtxdata = 0x1220;
constexpr uintptr_t kMtpr = 0x1224;
constexpr uintptr_t kMcr = 0x1228;
constexpr uintptr_t kMfifoctl = 0x1238;
constexpr uintptr_t kMfifosr = 0x123C;
constexpr uintptr_t kImask = 0x1028;
constexpr uintptr_t kMsa = 0x1210;
constexpr uintptr_t kMctr = 0x1214;

constexpr uint32_t kBurstRun = 1U << 0, kStart = 1U << 1, kStop = 1U << 2, kAck = 1U << 3;  // MCTR
constexpr uint32_t kAckOverride = 1U << 4;                                                  // MCTR.MACKOEN
constexpr uint32_t kRxDone = 1U << 0, kRxFifoTrig = 1U << 2, kStopEvent = 1U << 9;          // CPU_INT

constexpr uint32_t kMcrActive = 1U << 0;
constexpr uint32_t kGfctlAgfen = 1U << 8, kGfctlChain = 1U << 11;  // hw_i2c.h GFCTL.AGFEN, CHAIN
constexpr uint32_t kCtlTxFlush = 1U << 7;                          // I2C_MFIFOCTL_TXFLUSH
constexpr uint32_t kCtlRxFlush = 1U << 15;                         // I2C_MFIFOCTL_RXFLUSH
constexpr uint32_t kSrRxFlush = 1U << 7;                           // I2C_MFIFOSR_RXFLUSH: flush active
constexpr uint32_t kSrTxFlush = 1U << 15;                          // I2C_MFIFOSR_TXFLUSH
constexpr uint32_t kSrTxCountShift = 8;   // I2C_MFIFOSR_TXFIFOCNT 11:8, RXFIFOCNT 3:0
constexpr uint32_t kFlushDoneAtRead = 2;  // the flush shows at this MFIFOSR read after the bit is set

}  // namespace

void I2cModel::attach() {
  tx_.clear();
  rx_.clear();
  wire_.clear();
  txFlush_ = rxFlush_ = Flush{};
  flushStuck_ = false;
  target_.clear();
  targetNext_ = 0;
  readWire_.clear();
  raised_ = burstLeft_ = mctr_ = 0;
  receiving_ = busHeld_ = false;
  RegisterModel& m = model();
  m.onWrite(base_ + kMctr, [this](uint32_t v) { writeMctr(v); });
  m.onWrite(base_ + kRstctl, [this](uint32_t v) {
    if ((v & 1U) == 0) return;  // RESETASSERT
    tx_.clear();
    rx_.clear();
    txFlush_ = rxFlush_ = Flush{};
    model().set(base_ + kMcr, 0);
    model().set(base_ + kMfifoctl, 0);
  });
  m.onWrite(base_ + kMtxdata, [this](uint32_t v) {
    if (tx_.size() == kFifoDepth) {
      model().flag(
          "I2C: MTXDATA written with the TX FIFO full (MFIFOSR.TXFIFOCNT = 0): byte lost (hw_i2c.h "
          "MFIFOSR; DL_I2C_fillControllerTXFIFO checks for a full FIFO before each byte)");
      return;
    }
    tx_.push_back(static_cast<uint8_t>(v));
  });
  m.onRead(base_ + kMrxdata, [this] {
    if (rx_.empty()) return 0U;
    const uint8_t byte = rx_.front();
    rx_.pop_front();
    if (receiving_) receive();  // a full FIFO held SCL: the burst goes on
    return uint32_t{byte};
  });
  m.onRead(base_ + kMfifosr, [this] { return readStatus(); });
  m.onWrite(base_ + kMfifoctl, [this](uint32_t v) { writeFifoCtl(v); });
  m.onWrite(base_ + kGfctl, [](uint32_t v) {
    if ((v & kGfctlAgfen) && !(v & kGfctlChain)) {
      model().flag(
          "I2C: GFCTL.AGFEN without CHAIN: only the digital filter's output reaches the controller (hw_i2c.h "
          "GFCTL.CHAIN), the analog filter does nothing");
    }
  });
  m.onWrite(base_ + kTimeoutCtl, [this](uint32_t) {
    if (model().value(base_ + kMcr) & kMcrActive) {
      model().flag(
          "I2C: TIMEOUT_CTL written while MCR.ACTIVE (SLAU847D 21.2 clock low timeout: set it during "
          "initialisation only)");
    }
  });
}

void I2cModel::leftInTxFifo(std::initializer_list<uint8_t> bytes) {
  for (uint8_t b : bytes)
    tx_.push_back(b);
}

void I2cModel::shiftOut(uint32_t n) {
  for (; n != 0 && !tx_.empty(); --n) {
    wire_.push_back(tx_.front());
    tx_.pop_front();
  }
}

void I2cModel::receive(std::initializer_list<uint8_t> bytes) {
  for (uint8_t b : bytes)
    rx_.push_back(b);
}

uint32_t I2cModel::readStatus() {
  if (txFlush_.active && ++txFlush_.reads >= kFlushDoneAtRead && !flushStuck_) tx_.clear();
  if (rxFlush_.active && ++rxFlush_.reads >= kFlushDoneAtRead && !flushStuck_) rx_.clear();
  if (txFlush_.active && tx_.empty()) txFlush_.seenEmpty = true;
  if (rxFlush_.active && rx_.empty()) rxFlush_.seenEmpty = true;
  return static_cast<uint32_t>(rx_.size()) | (rxFlush_.active ? kSrRxFlush : 0U) |
         ((kFifoDepth - static_cast<uint32_t>(tx_.size())) << kSrTxCountShift) |
         (txFlush_.active ? kSrTxFlush : 0U);
}

void I2cModel::stopFlush(Flush& flush, const char* rule) {
  if (!flush.seenEmpty) model().flag(rule);
  flush = Flush{};
}

void I2cModel::writeFifoCtl(uint32_t value) {
  const bool tx = (value & kCtlTxFlush) != 0;
  const bool rx = (value & kCtlRxFlush) != 0;
  if (tx && !txFlush_.active) txFlush_ = Flush{true, 0, false};
  if (!tx && txFlush_.active) {
    stopFlush(txFlush_,
              "I2C: MFIFOCTL.TXFLUSH cleared before MFIFOSR.TXFIFOCNT read 8 (hw_i2c.h MFIFOCTL.TXFLUSH; "
              "DL_I2C_flushControllerTXFIFO)");
  }
  if (rx && !rxFlush_.active) rxFlush_ = Flush{true, 0, false};
  if (!rx && rxFlush_.active) {
    stopFlush(rxFlush_,
              "I2C: MFIFOCTL.RXFLUSH cleared before MFIFOSR.RXFIFOCNT read 0 (hw_i2c.h MFIFOCTL.RXFLUSH; "
              "DL_I2C_flushControllerRXFIFO)");
  }
}

void I2cModel::log(const std::string& token) {
  if (!readWire_.empty()) readWire_ += ' ';
  readWire_ += token;
}

uint32_t I2cModel::takeRaised() {
  const uint32_t pending = raised_ & model().value(base_ + kImask);
  raised_ = 0;
  return pending;
}

void I2cModel::writeMctr(uint32_t value) {
  // Transmit bursts are not modelled, nor receive bursts of tests that script the FIFO themselves.
  if (value & kAckOverride) {
    model().flag(
        "I2C: MCTR.MACKOEN (controller ACK override) set: no TI example or library uses it (README, open "
        "questions); TI's SMBus library reads the count byte with MBLEN 1 and ACK, then continues");
  }
  if (target_.empty() || (model().value(base_ + kMsa) & 1U) == 0 || (value & kBurstRun) == 0) return;
  if (receiving_) {
    model().flag(
        "I2C: MCTR.BURSTRUN written while a receive burst runs: ignored by the hardware (TI SMBus library "
        "smbus_phy.c SMBus_PHY_controllerStartRx)");
    return;
  }
  if ((value & kStart) == 0 && !busHeld_) {
    model().flag("I2C: receive burst without START on an idle bus (SLAU846A controller transfer table)");
    return;
  }
  if (value & kStart) {
    char address[8];
    std::snprintf(address, sizeof address, "%s %02X", busHeld_ ? "Sr" : "S",
                  model().value(base_ + kMsa) & 0xFF);
    log(address);
  }
  busHeld_ = false;
  receiving_ = true;
  mctr_ = value;
  burstLeft_ = (value >> 16) & 0xFFF;
  receive();
}

void I2cModel::receive() {
  while (burstLeft_ != 0 && rx_.size() < kFifoDepth) {
    const uint8_t byte = targetNext_ < target_.size() ? target_[targetNext_] : 0xFF;
    ++targetNext_;
    rx_.push_back(byte);
    --burstLeft_;
    char text[4];
    std::snprintf(text, sizeof text, "%02X", byte);
    log(text);
    const uint32_t trig = ((model().value(base_ + kMfifoctl) >> 8) & 7U) + 1;
    if (rx_.size() >= trig) raised_ |= kRxFifoTrig;
    if (burstLeft_ != 0) log("A");
  }
  if (burstLeft_ != 0) return;  // RX FIFO full: SCL held until MRXDATA is read
  raised_ |= kRxDone;
  const bool ack = (mctr_ & kAck) != 0;
  log(ack ? "A" : "N");
  receiving_ = false;
  if ((mctr_ & kStop) == 0) {
    busHeld_ = true;  // keeps the bus: a repeated START or a continuation follows
    return;
  }
  if (ack) {
    model().flag(
        "I2C: the last byte before STOP was ACKed (MCTR.ACK = 1): a controller receiver NACKs it (UM10204 "
        "3.1.6; SLAU846A acknowledge)");
  }
  log("P");
  raised_ |= kStopEvent;
}

uint64_t I2cModel::timeoutUs(uint32_t busClockHz) const {
  const RegisterModel& m = model();
  const uint64_t functionalHz = busClockHz / ((m.value(base_ + kClkdiv) & 0x7) + 1);
  const uint64_t count = m.value(base_ + kTimeoutCtl) & 0xFF;  // TCNTLA, the counter's upper 8 of 12 bits
  const uint64_t tpr = m.value(base_ + kMtpr) & 0x7F;
  return (count << 4) * (1 + tpr) * 12 * 1000000 / functionalHz;
}

}  // namespace bsp::mspm0::test
