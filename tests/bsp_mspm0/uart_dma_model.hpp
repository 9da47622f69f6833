// UartTxDmaModel: an MSPM0 UART transmitter fed by one DMA channel, in the register model. Offsets: the
// tsv "UART.*" rows and note "DMA" (channel n at DMA_BASE + 0x1200 + 0x10 n, DMATCTL n at + 0x1110 + 4 n).
//
// Rules (TI source next to each)
// - The UART raises its TX DMA trigger (DMA_TRIG_TX, TXINT) only with IFLS.TXIFLSEL = 7, "TX FIFO has at
//   least one entry free", which hw_uart.h (UART_IFLS_TXIFLSEL_LVL_1) marks as the setting the DMA trigger
//   needs, and which every TI UART TX DMA example selects (DL_UART_TX_FIFO_LEVEL_ONE_ENTRY in the
//   uart_tx_multibyte_fifo_dma_interrupts and uart_tx_console_multibyte_repeated_fifo_dma examples of both
//   LaunchPads). TI documents no DMA behaviour for the other levels, so the model raises no trigger with
//   them: the transfer stalls, and enabling the channel that way is flagged.
// - With the trigger, each free FIFO entry takes one byte from the channel (DMACTL.DMATM = 0, single transfer
//   per trigger); when DMASZ reaches 0 the channel disables itself and the UART sets DMA_DONE_TX.
// - The FIFO holds 4 bytes. transmit() shifts bytes out one at a time; EOT is set once the FIFO and the
//   shift register are empty, and STAT.BUSY reads 1 while any byte is still queued.
// - EOT is not set when the UART transmits with CTL0.TXE but not CTL0.RXE: "UART End Of Transmission (EOT)
//   interrupt does not trigger when the device is set for transmit only (CTL0.TXE = 1, CTL0.RXE = 0)"
//   (UART_ERR_02, SLAZ742G; in SLAZ741B's table for the L130x too).
// - CPU_INT MIS = RIS & IMASK; ICLR clears RIS bits.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

namespace bsp::mspm0::test {

class UartTxDmaModel {
 public:
  static constexpr uint32_t kFifoDepth = 4;

  UartTxDmaModel(uintptr_t uartBase, uintptr_t dmaBase, uint32_t channel, uint32_t trigger)
      : uart_(uartBase), dma_(dmaBase), channel_(channel), trigger_(trigger) {}
  void attach();

  // The line sends up to `bytes` bytes (the DMA refills the FIFO as its trigger allows).
  void transmit(uint32_t bytes);
  // Source addresses of the bytes sent, in order (the DMA's SA, counted up).
  const std::vector<uint32_t>& sent() const { return sent_; }
  uint32_t fifoLevel() const { return static_cast<uint32_t>(fifo_.size()); }

 private:
  uintptr_t channelReg(uintptr_t offset) const { return dma_ + 0x1200 + 0x10 * channel_ + offset; }
  bool triggerRaised() const;
  void pump();

  uintptr_t uart_;
  uintptr_t dma_;
  uint32_t channel_;
  uint32_t trigger_;
  bool armed_ = false;
  uint32_t source_ = 0;
  uint32_t remaining_ = 0;
  uint32_t ris_ = 0;
  std::deque<uint32_t> fifo_;  // source addresses of the bytes in the TX FIFO
  std::vector<uint32_t> sent_;
};

}  // namespace bsp::mspm0::test
