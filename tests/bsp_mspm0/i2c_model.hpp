// I2cModel: the MSPM0 I2C controller's FIFOs and clock-low timeout in the register model, with the rules a
// driver must follow. Offsets: mspm0l1306.tsv "I2C.*" rows; fields: its "I2C_MFIFOCTL_*" / "I2C_MFIFOSR_*"
// rows; FIFO depth I2C_SYS_FENTRIES = 8 (mspm0l130x.h, mspm0g350x.h).
//
// Rules (TI source next to each)
// - The TX FIFO holds 8 bytes. A write to MTXDATA while it is full is lost and flagged: MFIFOSR.TXFIFOCNT
//   is the number of bytes that can still be put into the TX FIFO (hw_i2c.h MFIFOSR), and TI's
//   DL_I2C_fillControllerTXFIFO checks DL_I2C_isControllerTXFIFOFull before every byte it writes.
// - A flush takes time: after MFIFOCTL.TXFLUSH (RXFLUSH) is set, the FIFO reads empty from the second MFIFOSR
//   read on. Clearing the bit before an MFIFOSR read has shown the FIFO empty (TXFIFOCNT = 8, RXFIFOCNT = 0)
//   is flagged, and the flush stops with whatever was not yet flushed still in the FIFO (hw_i2c.h
//   MFIFOCTL.TXFLUSH / RXFLUSH: check the count before clearing the bit; TI's DL_I2C_flushControllerTXFIFO
//   and ...RXFIFO set the bit, poll until empty, then clear it).
// - TIMEOUT_CTL written while MCR.ACTIVE is set is flagged (SLAU847D 21.2 / SLAU846B 20.2, "clock low
//   timeout": configure it during initialisation only, not in the active state).
// - A GPRCM reset (RSTCTL.RESETASSERT) empties both FIFOs and clears MCR and MFIFOCTL (the peripheral
//   returns to its reset state).
// - timeoutUs() turns the programmed CLKDIV, MTPR and TIMEOUT_CTL.TCNTLA into the SCL-low time after which
//   timeout A fires, counted as TI's code counts it: TCNTLA is the upper 8 bits of a 12-bit count (low 4
//   bits 0) stepping every (1 + TPR) x 12 functional clocks (SLAU847D 21.2 / SLAU846B 20.2: 0xDA -> 0xDA0
//   steps of 12 us at 20 MHz, TPR 19 = 41.856 ms; TI's Zephyr driver msp-zephyr drivers/i2c/i2c_mspm0.c
//   i2c_mspm0_configure_timeout). hw_i2c.h's "520 functional clocks" per count is not followed (no TI code
//   uses it; bsp/mspm0/README.md, open questions).
// - GFCTL with the analog glitch filter enabled (AGFEN) but CHAIN clear is flagged: "When 0, chaining is
//   disabled and only digital filter output is available to IP logic" (hw_i2c.h GFCTL.CHAIN), so the
//   filter would do nothing. The driver leaves GFCTL at 0, as TI's examples do.
// - Controller receive (MSA.DIR = read, MCTR.BURSTRUN) against a scripted target (targetSends): the burst
//   takes MBLEN bytes into the RX FIFO, holding SCL while the FIFO is full; every byte but the last is
//   ACKed; the last is ACKed per MCTR.ACK, then STOP if MCTR.STOP (SLAU846A controller transfer table;
//   hw_i2c.h MCTR.ACK). RXDONE at the end of the burst, RXFIFOTRG at the MFIFOCTL.RXTRIG level, STOP at STOP.
//   A controller receiver that ACKs the last byte before a STOP is flagged (UM10204 3.1.6: the controller
//   signals the end of the data with a NACK; SLAU846A "acknowledge": "signals the end of data to the target
//   transmitter by not generating an acknowledge on the last data byte").
// - A receive burst that ended without STOP keeps the bus; the next burst without START continues the
//   receive (SLAU846A I2C controller transfer table; TI's SMBus library reads a block read's count byte so,
//   smbus_nwk.c SMBus_NWK_startRxBlockPayloadTransfer).
// - MCTR.MACKOEN (controller ACK override) is flagged: no TI example or library uses it and no TRM text
//   describes it beyond hw_i2c.h's field description (bsp/mspm0/README.md, open questions).
// - MCTR.BURSTRUN written while a burst runs (not waiting at an override ACK) is flagged: "HW will ignore new
//   transfer requests while a transfer is active" (TI SMBus library, smbus_phy.c
//   SMBus_PHY_controllerStartRx).
#pragma once

#include <cstdint>
#include <deque>
#include <initializer_list>
#include <string>
#include <vector>

namespace bsp::mspm0::test {

class I2cModel {
 public:
  static constexpr uint32_t kFifoDepth = 8;

  explicit I2cModel(uintptr_t base) : base_(base) {}
  void attach();

  // Bytes already in the TX FIFO (e.g. left there by a write that ended with a NACK).
  void leftInTxFifo(std::initializer_list<uint8_t> bytes);
  // The controller sends up to `n` bytes from the TX FIFO on the wire.
  void shiftOut(uint32_t n);
  // Bytes received from the target into the RX FIFO.
  void receive(std::initializer_list<uint8_t> bytes);
  // What the target drives on the following controller reads (0xFF once they run out: SDA released).
  void targetSends(std::initializer_list<uint8_t> bytes) { target_.assign(bytes); }
  // Interrupt flags raised since the last call, masked by IMASK (what the ISR would see in MIS).
  uint32_t takeRaised();
  // The receive side of the wire: "S 17 03 A 01 A ... N P" (address+R, each byte and its ACK/NACK, STOP).
  const std::string& readWire() const { return readWire_; }
  // Fault: a flush never empties the FIFOs (only a GPRCM reset does).
  void flushNeverCompletes() { flushStuck_ = true; }

  const std::vector<uint8_t>& wire() const { return wire_; }
  uint32_t txLevel() const { return static_cast<uint32_t>(tx_.size()); }
  uint64_t timeoutUs(uint32_t busClockHz) const;

 private:
  struct Flush {
    bool active = false;
    uint32_t reads = 0;      // MFIFOSR reads since the flush bit was set
    bool seenEmpty = false;  // one of them showed the FIFO empty
  };
  uint32_t readStatus();
  void writeMctr(uint32_t value);
  void receive();  // runs the burst until it ends, waits, or the RX FIFO is full
  void log(const std::string& token);
  void writeFifoCtl(uint32_t value);
  static void stopFlush(Flush& flush, const char* rule);

  uintptr_t base_;
  std::deque<uint8_t> tx_;
  std::deque<uint8_t> rx_;
  std::vector<uint8_t> wire_;
  Flush txFlush_;
  Flush rxFlush_;
  bool flushStuck_ = false;
  std::vector<uint8_t> target_;
  size_t targetNext_ = 0;
  std::string readWire_;
  uint32_t raised_ = 0;
  uint32_t burstLeft_ = 0;  // bytes of the running receive burst still to come
  bool receiving_ = false;  // a receive burst runs (or waits)
  bool busHeld_ = false;    // a burst ended without STOP: the controller keeps the bus
  uint32_t mctr_ = 0;       // the running burst's MCTR
};

}  // namespace bsp::mspm0::test
