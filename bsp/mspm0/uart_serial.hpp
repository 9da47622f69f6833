// UartSerial: fw::hal::SerialPort on an MSPM0 UART: transmit by DMA, receive by interrupt (the L1306's UART0
// back-channel to the LaunchPad's XDS110: SLCAN text out, SLCAN commands in).
//
// Contract (see hal/serial.hpp)
// - write(bytes, done): Ok, Busy (a write is running) or InvalidArgument (empty, or more than 65535 bytes).
//   The DMA feeds the TX FIFO; `done` runs in ISR context after the last stop bit has left the shift
//   register (EOT), never earlier. The buffer must stay valid until then. Never blocks.
// - Reception (when Config::rx names a pin): RX FIFO at one entry raises RXINT; the handler clears it first
//   and then empties the FIFO into a kRxBuffer-byte ring (TI's uart_echo examples take the byte after reading
//   the interrupt index, which clears it, the same order), and calls the receive Notify. A byte the UART
//   flags (framing, parity, break or overrun error in RXDATA bits 8..11, hw_uart.h UART_RXDATA) or that finds
//   the ring full is dropped and counted (lost()); an OVRERR interrupt (a byte the FIFO had no room for)
//   counts one too. read() takes from the ring in task context.
// - onInterrupt(): body of the UART's IRQ handler: each direction clears and handles only its own flags
//   (MIS -> ICLR -> act -> return), so TX completion and reception share one interrupt.
#pragma once

#include <cstdint>
#include <span>

#include "core/spsc_queue.hpp"
#include "dma.hpp"
#include "gpio.hpp"
#include "hal/serial.hpp"
#include "pin.hpp"
#include "regs/cpuss.hpp"
#include "regs/gpio.hpp"
#include "regs/uart.hpp"
#include "uart_common.hpp"

namespace bsp::mspm0 {

class UartSerial final : public fw::hal::SerialPort {
 public:
  static constexpr size_t kRxBuffer = 64;  // about 5.6 ms of bytes at 115 200 Bd
  using RxBuffer = fw::SpscQueue<uint8_t, kRxBuffer>;
  static constexpr uint32_t kRxInterrupts = reg::uart::kIntRx | reg::uart::kIntOvrErr;

  struct Config {
    uintptr_t base = 0;
    uint8_t irq = 0;
    uint16_t divisor64 = 0;  // reg::uart::baudDivisor64(bus clock, baud)
    PinFunction tx{};
    DmaChannel dma{};
    PinFunction rx{};  // pin 0 (PINCM 0): no receiver
  };

  // `rxBuffer`: the receive ring, a zero-initialised object of its own (it lives in .bss, not in this
  // object's initialised data); null without a receiver.
  constexpr UartSerial(const Config& config, RxBuffer* rxBuffer = nullptr)
      : config_(config), rx_(rxBuffer), rxMask_(rxBuffer != nullptr ? kRxInterrupts : 0) {}
  // Configures the UART, muxes the pins and enables the interrupt. The static form is inline: a board that
  // passes its constant configuration gets constant register writes. RX: input enabled with the internal
  // pull-up (IOMUX PINCM INENA bit 18, PIPU bit 17), so a line left open (jumpers off) idles high instead of
  // floating into noise; the XDS110 drives it otherwise.
  void init() const { init(config_); }
  static void init(const Config& config) {
    const bool receiver = config.rx.pin.pincm != 0;
    uartConfigure(config.base, config.divisor64, receiver, false);
    reg::iomux::pincm(config.tx.pin.pincm).write(reg::iomux::kPc | config.tx.pf);  // as muxPeripheral()
    if (receiver) {
      reg::iomux::pincm(config.rx.pin.pincm)
          .write(reg::iomux::kPc | config.rx.pf | reg::iomux::kInputEnable | reg::iomux::kPullUp);
      reg::cpuInt(config.base).imask.write(kRxInterrupts);
    }
    nvic::enable(config.irq);
  }
  void onInterrupt();

 private:
  fw::Status doWrite(std::span<const uint8_t> bytes, const fw::hal::Notify& done) override;
  bool doRead(uint8_t& byte) override { return rx_ != nullptr && rx_->pop(byte); }
  void doOnReceive(const fw::hal::Notify& notify) override { rxNotify_ = notify; }
  uint32_t doLost() const override { return lost_; }
  void finish();
  void receive(uint32_t pending);
  uint32_t rxMask() const { return rxMask_; }

  Config config_;
  fw::hal::Notify done_{};
  fw::hal::Notify rxNotify_{};
  volatile bool busy_ = false;
  volatile uint32_t lost_ = 0;
  RxBuffer* rx_;
  uint32_t rxMask_;
};

}  // namespace bsp::mspm0
