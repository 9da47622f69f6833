// Shared UART set-up for the two UART drivers (uart_serial_tx, uart_link): 8N1, FIFOs on, 16x
// oversampling from the bus clock, DMA triggers routed (RX: one byte in the FIFO; TX: FIFO at most half
// full). Thread mode, before the driver's interrupt is enabled.
#pragma once

#include <cstdint>

namespace bsp::mspm0 {

// `divisor64` is reg::uart::baudDivisor64(clock, baud), computed at compile time by the board.
void uartConfigure(uintptr_t base, uint32_t divisor64, bool receiver);

}  // namespace bsp::mspm0
