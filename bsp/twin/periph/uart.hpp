// Uart: an MSPM0 UART (UART0/1 on the L1306; UART0..3 on the G3507), registers and fields from mspm0-sdk
// hw_uart.h: CLKDIV 0x1000, CLKSEL 0x1008, CPU_INT 0x1020, DMA_TRIG_RX 0x1050, DMA_TRIG_TX 0x1080, CTL0
// 0x1100 (ENABLE 0, RXE 3, TXE 4, MODE 10:8, HSE 16:15, FEN 17), LCRH 0x1104 (PEN 1, STP2 3, WLEN 5:4), STAT
// 0x1108 (BUSY 0, RXFE 2, RXFF 3, TXFE 6, TXFF 7), IFLS 0x110C (TXIFLSEL 2:0, RXIFLSEL 6:4), IBRD 0x1110,
// FBRD 0x1114, GFCTL 0x1118, TXDATA 0x1120, RXDATA 0x1124.
//
// Timing: one frame is start + WLEN + parity + stop bits, each bit oversampling x (IBRD + FBRD/64) UART
// clocks, the UART clock being BUSCLK / (CLKDIV.RATIO + 1) (hw_uart.h IBRD/FBRD/HSE; SLAU846B/SLAU847D
// "UART baud-rate generation"). Bytes leave back to back while the TX FIFO has data.
//
// FIFOs of 4 entries ("if the transmit FIFO was filled with four characters", driverlib
// DL_UART_setTXFIFOThreshold); without FEN one entry.
//
// Trigger levels (TXINT, RXINT; the same event sets CPU_INT and DMA_TRIG_TX / DMA_TRIG_RX):
//   "The interrupts are generated based on a transition through a level rather than being based on the
//   level ... if the transmit FIFO was filled with four characters, the interrupt would trigger once there
//   are two or less characters after transmitting" (driverlib DL_UART_setTXFIFOThreshold/RXFIFOThreshold).
//   So TX 3/4, 1/2, 1/4, EMPTY trigger when the fill level drains through 1, 2, 3, 0 entries; RX 1/4, 1/2,
//   3/4, FULL when it rises through 1, 2, 3, 4. The levels made for the DMA, TX "FIFO >= 1 entry free" (7)
//   and RX "FIFO >= 1 entry available" (7) ("esp. required for DMA Trigger", hw_uart.h IFLS), hold as long
//   as their condition does: the flag is raised again after every FIFO change while it holds (TI's
//   uart_tx_multibyte_fifo_dma_interrupts example relies on this: "The UART DMA TX interrupt is set
//   indicating the UART is ready to transmit data, so enabling the DMA will start the transfer").
//   A DMA request is DMA_TRIG_x.MIS; the DMA's acknowledge clears that RIS bit.
// EOT: "the last bit of all transmitted data and flags has left the serializer and without any further
// Data in the TX Fifo" (hw_uart.h CPU_INT RIS EOT), and only with CTL0.RXE set as well: "UART End Of
// Transmission (EOT) interrupt does not trigger when the device is set for transmit only" (UART_ERR_02,
// SLAZ742G; SLAZ741B lists it for the L130x). DMA_DONE_TX/RX when the DMA channel on this UART's
// trigger reaches DMASZ = 0.
// RX: a byte that arrives with the FIFO full is lost and sets OVRERR; a framing error sets FRMERR.
// Anything else (IrDA, LIN, 9-bit, RS485, flow control, loopback, RX timeout) stops the run if enabled.
// Wire agreement (rules.hpp WIRE-UART-BAUD): with a link partner set (the board), the first frame sent or
// received after any change of the divisors, line or clock settings checks the UART's baud,
// BUSCLK / CLKDIV / (oversampling x (IBRD + FBRD / 64)), against the partner's: the error may be at most the
// partner's documented receive tolerance, and at most half the margin the MSPM0's own receiver has at its
// oversampling (it samples mid-bit, (1/2 - 1/oversampling) bit times over the 9.5 bits to the stop bit; the
// other half is the partner's clock's). The same frame checks the frame format (rules.hpp WIRE-UART-FRAME):
// LCRH.WLEN (5:4, 3 = 8 bits) and LCRH.PEN (bit 1) against the partner's data bits and parity (8N1 for both
// partners). A second stop bit (LCRH.STP2) is allowed: the MSPM0 transmits it as idle time an 8N1 receiver
// accepts, and its own receiver checks only the first stop bit ("The receive logic does not check for two
// stop bits being received", hw_uart.h LCRH.STP2).
// End of a DMA transmission (rules.hpp UART-TX-END-UNSEEN, warns): when the last byte a TX DMA transfer
// moved leaves the serializer and the driver still has interrupts of this UART unmasked (an exchange is
// open), one of EOT, DMA_DONE_TX or TXINT must be unmasked in CPU_INT.IMASK: otherwise nothing tells the CPU
// that the transmission ended (an event reaches the CPU only through its IMASK bit, SLAU846B / SLAU847D UART
// interrupts; hw_uart.h CPU_INT IMASK EOT, DMA_DONE_TX), and whatever it starts then (a response timeout)
// never starts.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <string>

#include "periph/dma.hpp"
#include "periph/peripheral.hpp"
#include "timeline.hpp"

namespace twin {

class Uart final : public Peripheral, public DmaRequester {
 public:
  static constexpr uint32_t kRtout = 1U << 0, kFrmErr = 1U << 1, kOvrErr = 1U << 4;
  static constexpr uint32_t kRxInt = 1U << 10, kTxInt = 1U << 11, kEot = 1U << 12;
  static constexpr uint32_t kDmaDoneRx = 1U << 15, kDmaDoneTx = 1U << 16;
  static constexpr uint32_t kTxdataOffset = 0x1120, kRxdataOffset = 0x1124;

  Uart(Machine& machine, const char* name, Dma& dma, int rxTrigger, int txTrigger);

  // Each byte as its last stop bit leaves the shift register (the board forwards it if the pin is routed).
  void onTransmit(std::function<void(uint8_t byte)> sink) { txSink_ = std::move(sink); }
  // A byte whose stop bit has just arrived on the RX pin.
  void receive(uint8_t byte, bool framingError);
  // The device on this UART's pins: its name, rate and the baud error it accepts (ppm), with the source.
  struct Link {
    std::string partner;
    uint32_t baud = 0;
    uint32_t tolerancePpm = 0;
    std::string source;
    uint32_t dataBits = 8;  // the partner's frame: data bits, and whether it sends and expects a parity bit
    bool parity = false;
  };
  void setLink(Link link) { link_ = std::move(link), linkChecked_ = false; }
  // The baud the settings give, in 1/64 Bd (0 if not configured).
  uint64_t baud64() const;
  // Cycles one frame takes with the current settings (0 if not configured).
  uint64_t frameCycles64() const;  // in 1/64 cycles
  bool enabled() const;

  bool dmaRequested(int trigger) const override;
  void dmaAcknowledge(int trigger) override;
  void dmaDone(int trigger) override;
  // UART-DMA-LEVEL (rules.hpp): a DMA channel paced by this UART needs IFLS level 7 in its direction.
  std::string dmaTriggerProblem(int trigger, Rule& rule) const override;
  // The receiver samples its RX pin (the board asks before it delivers a byte: PIN-UNROUTED).
  bool receiving() const;
  // A frame is leaving (shift register or TX FIFO not empty): its baud needs the functional clock it was
  // configured for (the power-mode rule, rules.hpp SLEEP-EVENT-LOST).
  bool transmitting() const { return shifting_ || !txFifo_.empty(); }

 private:
  bool readRegister(uint32_t offset, uint32_t& value) override;
  bool writeRegister(uint32_t offset, uint32_t value) override;
  void resetRegisters() override;

  size_t depth() const;
  void raiseEvent(uint32_t bit);  // CPU_INT and the matching DMA trigger block
  void txFillChanged(size_t before);
  void rxFillChanged(size_t before);
  void startNextFrame();
  void frameDone();
  void checkMode();
  void checkLink();
  void checkTxEndSeen();

  Dma& dma_;
  int rxTrigger_, txTrigger_;
  EventRegs dmaRx_, dmaTx_;
  TimedEvent frameEnd_;
  std::function<void(uint8_t)> txSink_;
  std::deque<uint8_t> txFifo_;
  std::deque<uint16_t> rxFifo_;  // data | error flags (RXDATA layout)
  bool shifting_ = false;
  uint8_t shiftByte_ = 0;
  uint64_t frameRemainder64_ = 0;  // fractional cycles carried between frames
  ClockRegs clock_{0x1008};
  uint32_t ctl0_ = 0, lcrh_ = 0, ifls_ = 0, ibrd_ = 0, fbrd_ = 0, gfctl_ = 0;
  Link link_;
  bool linkChecked_ = false;
  bool txDmaDone_ = false;  // a TX DMA transfer completed; its last byte has not left yet
};

}  // namespace twin
