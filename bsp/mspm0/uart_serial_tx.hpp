// UartSerialTx: fw::hal::SerialTx on an MSPM0 UART with DMA (the L1306's UART0 back-channel to the
// LaunchPad's XDS110, carrying SLCAN text).
//
// Contract (see hal/serial.hpp)
// - write(bytes, done): Ok, Busy (a write is running) or InvalidArgument (empty, or more than 65535 bytes).
//   The DMA feeds the TX FIFO; `done` runs in ISR context after the last stop bit has left the shift
//   register (EOT), never earlier. The buffer must stay valid until then. Never blocks.
// - onInterrupt(): body of the UART's IRQ handler (MIS -> ICLR -> act -> return).
#pragma once

#include <cstdint>
#include <span>

#include "dma.hpp"
#include "gpio.hpp"
#include "hal/serial.hpp"
#include "pin.hpp"
#include "regs/cpuss.hpp"
#include "uart_common.hpp"

namespace bsp::mspm0 {

class UartSerialTx final : public fw::hal::SerialTx {
 public:
  struct Config {
    uintptr_t base = 0;
    uint8_t irq = 0;
    uint16_t divisor64 = 0;  // reg::uart::baudDivisor64(bus clock, baud)
    PinFunction tx{};
    DmaChannel dma{};
  };

  constexpr explicit UartSerialTx(const Config& config) : config_(config) {}
  // Configures the UART (transmit only), muxes the pin and enables the interrupt. The static form is
  // inline: a board that passes its constant configuration gets constant register writes.
  void init() const { init(config_); }
  static void init(const Config& config) {
    uartConfigure(config.base, config.divisor64, false);
    reg::iomux::pincm(config.tx.pin.pincm).write(reg::iomux::kPc | config.tx.pf);  // as muxPeripheral()
    nvic::enable(config.irq);
  }
  void onInterrupt();

 private:
  fw::Status doWrite(std::span<const uint8_t> bytes, const fw::hal::Notify& done) override;
  void finish();

  Config config_;
  fw::hal::Notify done_{};
  volatile bool busy_ = false;
};

}  // namespace bsp::mspm0
