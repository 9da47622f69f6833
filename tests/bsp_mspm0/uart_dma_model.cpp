#include "uart_dma_model.hpp"

#include "mmio_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kRstctl = 0x0804;
constexpr uintptr_t kImask = 0x1028;
constexpr uintptr_t kRis = 0x1030;
constexpr uintptr_t kMis = 0x1038;
constexpr uintptr_t kIclr = 0x1048;
constexpr uintptr_t kDmaTrigTxImask = 0x1088;
constexpr uintptr_t kCtl0 = 0x1100;
constexpr uint32_t kCtl0Rxe = 1U << 3;  // UART_CTL0_RXE
constexpr uintptr_t kStat = 0x1108;
constexpr uintptr_t kIfls = 0x110C;
constexpr uintptr_t kTxdata = 0x1120;

constexpr uint32_t kTxint = 1U << 11;      // UART_DMA_TRIG_TX_IMASK_TXINT
constexpr uint32_t kEot = 1U << 12;        // UART_CPU_INT_IMASK_EOT
constexpr uint32_t kDmaDoneTx = 1U << 16;  // UART_CPU_INT_IMASK_DMA_DONE_TX
constexpr uint32_t kStatBusy = 1U << 0;
constexpr uint32_t kTxiflselMask = 0x7;
constexpr uint32_t kTxiflselOneFree = 0x7;  // UART_IFLS_TXIFLSEL_LVL_1
constexpr uint32_t kDmaEnable = 1U << 1;    // DMACTL.DMAEN

}  // namespace

void UartTxDmaModel::attach() {
  armed_ = false;
  source_ = remaining_ = ris_ = 0;
  fifo_.clear();
  sent_.clear();
  RegisterModel& m = model();
  m.onWrite(uart_ + kRstctl, [this](uint32_t v) {
    if ((v & 1U) == 0) return;  // RESETASSERT
    fifo_.clear();
    ris_ = 0;
    for (uintptr_t r : {kImask, kDmaTrigTxImask, kIfls})
      model().set(uart_ + r, 0);
  });
  m.onWrite(channelReg(0x0), [this](uint32_t ctl) {
    const RegisterModel& regs = model();
    armed_ = (ctl & kDmaEnable) != 0 && regs.value(dma_ + 0x1110 + 4 * channel_) == trigger_ &&
             regs.value(channelReg(0x8)) == static_cast<uint32_t>(uart_ + kTxdata);
    if (!armed_) return;
    source_ = regs.value(channelReg(0x4));
    remaining_ = regs.value(channelReg(0xC)) & 0xFFFF;
    if ((regs.value(uart_ + kIfls) & kTxiflselMask) != kTxiflselOneFree) {
      model().flag(
          "UART: TX DMA started with IFLS.TXIFLSEL != 7; hw_uart.h requires LVL_1 (one entry free) "
          "for the DMA trigger, so no byte moves");
    }
    pump();
  });
  m.onRead(channelReg(0xC), [this] { return remaining_; });
  m.onRead(uart_ + kStat,
           [this] { return (model().value(uart_ + kStat) & ~kStatBusy) | (fifo_.empty() ? 0U : kStatBusy); });
  m.onRead(uart_ + kRis, [this] { return ris_; });
  m.onRead(uart_ + kMis, [this] { return ris_ & model().value(uart_ + kImask); });
  m.onWrite(uart_ + kIclr, [this](uint32_t v) { ris_ &= ~v; });
}

bool UartTxDmaModel::triggerRaised() const {
  const RegisterModel& m = model();
  return (m.value(uart_ + kIfls) & kTxiflselMask) == kTxiflselOneFree &&
         (m.value(uart_ + kDmaTrigTxImask) & kTxint) != 0 && fifo_.size() < kFifoDepth;
}

void UartTxDmaModel::pump() {
  while (armed_ && remaining_ != 0 && triggerRaised()) {
    fifo_.push_back(source_++);
    if (--remaining_ == 0) {
      armed_ = false;  // the channel disables itself and signals done to the UART
      model().set(channelReg(0x0), model().value(channelReg(0x0)) & ~kDmaEnable);
      ris_ |= kDmaDoneTx;
    }
  }
}

void UartTxDmaModel::transmit(uint32_t bytes) {
  pump();
  for (; bytes != 0 && !fifo_.empty(); --bytes) {
    sent_.push_back(fifo_.front());
    fifo_.pop_front();
    pump();
    // Last stop bit out, nothing queued: EOT, but only with the receiver enabled too (UART_ERR_02).
    if (fifo_.empty() && (model().value(uart_ + kCtl0) & kCtl0Rxe) != 0) ris_ |= kEot;
  }
}

}  // namespace bsp::mspm0::test
