// Shared UART set-up for the two UART drivers (uart_serial, uart_link): 8N1, FIFOs on, 16x oversampling
// from the bus clock, DMA triggers routed (RX, when `rxDma`: one byte in the FIFO; TX: one FIFO entry free,
// the TX level the DMA trigger needs, regs/uart.hpp; the same RX level raises RXINT for a receiver without
// DMA). Thread mode, before the driver's interrupt is enabled.
#pragma once

#include <cstdint>

#include "regs/uart.hpp"

namespace bsp::mspm0 {

// `divisor64` is reg::uart::baudDivisor64(clock, baud), computed at compile time by the board. Inline: each
// image has one UART driver, and its constant `receiver` then leaves out the other driver's lines.
inline void uartConfigure(uintptr_t base, uint32_t divisor64, bool receiver, bool rxDma = true) {
  namespace uart = reg::uart;
  reg::resetAndPowerUp(reg::gprcm(base));
  uart::Clock& clock = uart::clock(base);
  clock.clksel.write(uart::kClkselBusclk);
  clock.clkdiv.write(0);
  // CTL0 stays 0 (disabled) while the line and divisors are set (TRM UART "Initialization").
  uart::Line& line = uart::line(base);
  line.ibrd.write(divisor64 >> 6);
  line.fbrd.write(divisor64 & 0x3F);
  line.lcrh.write(uart::kLcrh8N1);
  line.ifls.write(uart::kIflsTxOneFree | uart::kIflsRxOne);
  uart::dmaTrigTx(base).imask.write(uart::kIntTx);
  if (receiver && rxDma) uart::dmaTrigRx(base).imask.write(uart::kIntRx);
  reg::cpuInt(base).iclr.write(0xFFFFFFFF);
  // RXE even without a receiver: EOT, which UartSerialTx completes on, is not raised with TXE alone
  // (UART_ERR_02, SLAZ741/SLAZ742: "Set both CTL0.TXE and CTL0.RXE ... you do not need to assign a pin as
  // UART receive"). No RX interrupt or DMA trigger is enabled without `receiver`.
  line.ctl0.write(uart::kCtl0Enable | uart::kCtl0Txe | uart::kCtl0Fen | uart::kCtl0Rxe);
}

}  // namespace bsp::mspm0
