#include "i2c_model.hpp"

#include "mmio_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kRstctl = 0x0804;
constexpr uintptr_t kClkdiv = 0x1000;
constexpr uintptr_t kTimeoutCtl = 0x1204;
constexpr uintptr_t kMrxdata = 0x121C;
constexpr uintptr_t kMtxdata = 0x1220;
constexpr uintptr_t kMtpr = 0x1224;
constexpr uintptr_t kMcr = 0x1228;
constexpr uintptr_t kMfifoctl = 0x1238;
constexpr uintptr_t kMfifosr = 0x123C;

constexpr uint32_t kMcrActive = 1U << 0;
constexpr uint32_t kCtlTxFlush = 1U << 7;   // I2C_MFIFOCTL_TXFLUSH
constexpr uint32_t kCtlRxFlush = 1U << 15;  // I2C_MFIFOCTL_RXFLUSH
constexpr uint32_t kSrRxFlush = 1U << 7;    // I2C_MFIFOSR_RXFLUSH: flush active
constexpr uint32_t kSrTxFlush = 1U << 15;   // I2C_MFIFOSR_TXFLUSH
constexpr uint32_t kSrTxCountShift = 8;     // I2C_MFIFOSR_TXFIFOCNT 11:8, RXFIFOCNT 3:0
constexpr uint32_t kFlushDoneAtRead = 2;    // the flush shows at this MFIFOSR read after the bit is set

}  // namespace

void I2cModel::attach() {
  tx_.clear();
  rx_.clear();
  wire_.clear();
  txFlush_ = rxFlush_ = Flush{};
  flushStuck_ = false;
  RegisterModel& m = model();
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
    return uint32_t{byte};
  });
  m.onRead(base_ + kMfifosr, [this] { return readStatus(); });
  m.onWrite(base_ + kMfifoctl, [this](uint32_t v) { writeFifoCtl(v); });
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

uint64_t I2cModel::timeoutUs(Reading reading, uint32_t busClockHz) const {
  const RegisterModel& m = model();
  const uint64_t functionalHz = busClockHz / ((m.value(base_ + kClkdiv) & 0x7) + 1);
  const uint64_t count = m.value(base_ + kTimeoutCtl) & 0xFF;  // TCNTLA
  const uint64_t tpr = m.value(base_ + kMtpr) & 0x7F;
  const uint64_t clocks = reading == Reading::Header ? count * 520 : (count << 4) * (1 + tpr) * 12;
  return clocks * 1000000 / functionalHz;
}

}  // namespace bsp::mspm0::test
