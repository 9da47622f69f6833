#include "uart_serial_tx.hpp"

#include "gpio.hpp"
#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/uart.hpp"
#include "uart_common.hpp"

namespace bsp::mspm0 {

namespace uart = reg::uart;

fw::Status UartSerialTx::doWrite(std::span<const uint8_t> bytes, const fw::hal::Notify& done) {
  if (bytes.empty() || bytes.size() > 0xFFFF) return fw::Status::InvalidArgument;
  if (busy_) return fw::Status::Busy;
  busy_ = true;
  done_ = done;
  reg::EventBlock& events = reg::cpuInt(config_.base);
  events.iclr.write(uart::kIntDmaDoneTx | uart::kIntEot);
  events.imask.write(uart::kIntDmaDoneTx);
  config_.dma.start(DmaChannel::Direction::ToPeripheral, mmio::address(bytes.data()),
                    mmio::address(&uart::line(config_.base).txdata), static_cast<uint32_t>(bytes.size()));
  return fw::Status::Ok;
}

void UartSerialTx::onInterrupt() {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  const uint32_t pending = events.mis.read();
  events.iclr.write(pending);
  if (pending & uart::kIntDmaDoneTx) {
    // The DMA has put the last byte into the FIFO; the line is done at the next EOT. EOT may have been
    // raised by a momentary empty FIFO earlier in the transfer, so clear it before listening for it.
    events.iclr.write(uart::kIntEot);
    events.imask.write(uart::kIntEot);
    if ((uart::line(config_.base).stat.read() & uart::kStatBusy) == 0) finish();
  } else if (pending & uart::kIntEot) {
    finish();
  }
}

void UartSerialTx::finish() {
  reg::cpuInt(config_.base).imask.write(0);
  busy_ = false;
  done_();
}

}  // namespace bsp::mspm0
