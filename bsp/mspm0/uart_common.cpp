#include "uart_common.hpp"

#include "regs/uart.hpp"

namespace bsp::mspm0 {

namespace uart = reg::uart;

void uartConfigure(uintptr_t base, uint32_t divisor64, bool receiver) {
  reg::resetAndPowerUp(reg::gprcm(base));
  uart::Clock& clock = uart::clock(base);
  clock.clksel.write(uart::kClkselBusclk);
  clock.clkdiv.write(0);
  // CTL0 stays 0 (disabled) while the line and divisors are set (TRM UART "Initialization").
  uart::Line& line = uart::line(base);
  line.ibrd.write(divisor64 >> 6);
  line.fbrd.write(divisor64 & 0x3F);
  line.lcrh.write(uart::kLcrh8N1);
  line.ifls.write(uart::kIflsTxHalf | uart::kIflsRxOne);
  uart::dmaTrigTx(base).imask.write(uart::kIntTx);
  if (receiver) uart::dmaTrigRx(base).imask.write(uart::kIntRx);
  reg::cpuInt(base).iclr.write(0xFFFFFFFF);
  line.ctl0.write(uart::kCtl0Enable | uart::kCtl0Txe | uart::kCtl0Fen | (receiver ? uart::kCtl0Rxe : 0));
}

}  // namespace bsp::mspm0
