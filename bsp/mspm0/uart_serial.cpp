#include "uart_serial.hpp"

#include "gpio.hpp"
#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/uart.hpp"
#include "uart_common.hpp"

namespace bsp::mspm0 {

namespace uart = reg::uart;

namespace {
// RXDATA: the byte in 7:0, its error flags FRMERR 8, PARERR 9, BRKERR 10, OVRERR 11 (hw_uart.h UART_RXDATA).
constexpr uint32_t kRxDataErrors = 0xF00;
constexpr uint32_t kTxInterrupts = uart::kIntDmaDoneTx | uart::kIntEot;
}  // namespace

fw::Status UartSerial::doWrite(std::span<const uint8_t> bytes, const fw::hal::Notify& done) {
  if (bytes.empty() || bytes.size() > 0xFFFF) return fw::Status::InvalidArgument;
  if (busy_) return fw::Status::Busy;
  busy_ = true;
  done_ = done;
  reg::EventBlock& events = reg::cpuInt(config_.base);
  events.iclr.write(kTxInterrupts);
  events.imask.write(rxMask() | uart::kIntDmaDoneTx);
  config_.dma.start(DmaChannel::Direction::ToPeripheral, mmio::address(bytes.data()),
                    mmio::address(&uart::line(config_.base).txdata), static_cast<uint32_t>(bytes.size()));
  return fw::Status::Ok;
}

void UartSerial::onInterrupt() {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  const uint32_t pending = events.mis.read();
  if (const uint32_t rx = pending & rxMask()) receive(rx);
  const uint32_t tx = pending & kTxInterrupts;
  if (tx == 0) return;
  events.iclr.write(tx);
  if (tx & uart::kIntDmaDoneTx) {
    // The DMA has put the last byte into the FIFO; the line is done at the next EOT. EOT may have been
    // raised by a momentary empty FIFO earlier in the transfer, so clear it before listening for it.
    events.iclr.write(uart::kIntEot);
    events.imask.write(rxMask() | uart::kIntEot);
    if ((uart::line(config_.base).stat.read() & uart::kStatBusy) == 0) finish();
  } else if (tx & uart::kIntEot) {
    finish();
  }
}

// The flags first, then the FIFO until empty: a byte that arrives after the clear raises RXINT again.
void UartSerial::receive(uint32_t pending) {
  reg::cpuInt(config_.base).iclr.write(pending);
  if (pending & uart::kIntOvrErr) lost_ = lost_ + 1;
  uart::Line& line = uart::line(config_.base);
  bool any = false;
  while ((line.stat.read() & uart::kStatRxfe) == 0) {
    const uint32_t data = line.rxdata.read();
    if ((data & kRxDataErrors) != 0 || !rx_->push(static_cast<uint8_t>(data))) {
      lost_ = lost_ + 1;
    } else {
      any = true;
    }
  }
  if (any) rxNotify_();
}

void UartSerial::finish() {
  reg::cpuInt(config_.base).imask.write(rxMask());
  busy_ = false;
  done_();
}

}  // namespace bsp::mspm0
