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
//   timeout A fires, under each of TI's two readings (bsp/mspm0/README.md, open questions):
//     Header: TCNTLA x 520 functional clocks (hw_i2c.h TIMEOUT_CTL.TCNTLA, DL_I2C_setTimeoutACount);
//     Trm:    TCNTLA is the upper 8 bits of a 12-bit count stepping every (1 + TPR) x 12 functional clocks
//             (SLAU847D 21.2 / SLAU846B 20.2: 0xDA -> 0xDA0 steps of 12 us at 20 MHz, TPR 19 = 41.856 ms).
#pragma once

#include <cstdint>
#include <deque>
#include <initializer_list>
#include <vector>

namespace bsp::mspm0::test {

class I2cModel {
 public:
  enum class Reading : uint8_t { Header, Trm };
  static constexpr uint32_t kFifoDepth = 8;

  explicit I2cModel(uintptr_t base) : base_(base) {}
  void attach();

  // Bytes already in the TX FIFO (e.g. left there by a write that ended with a NACK).
  void leftInTxFifo(std::initializer_list<uint8_t> bytes);
  // The controller sends up to `n` bytes from the TX FIFO on the wire.
  void shiftOut(uint32_t n);
  // Bytes received from the target into the RX FIFO.
  void receive(std::initializer_list<uint8_t> bytes);
  // Fault: a flush never empties the FIFOs (only a GPRCM reset does).
  void flushNeverCompletes() { flushStuck_ = true; }

  const std::vector<uint8_t>& wire() const { return wire_; }
  uint32_t txLevel() const { return static_cast<uint32_t>(tx_.size()); }
  uint64_t timeoutUs(Reading reading, uint32_t busClockHz) const;

 private:
  struct Flush {
    bool active = false;
    uint32_t reads = 0;      // MFIFOSR reads since the flush bit was set
    bool seenEmpty = false;  // one of them showed the FIFO empty
  };
  uint32_t readStatus();
  void writeFifoCtl(uint32_t value);
  static void stopFlush(Flush& flush, const char* rule);

  uintptr_t base_;
  std::deque<uint8_t> tx_;
  std::deque<uint8_t> rx_;
  std::vector<uint8_t> wire_;
  Flush txFlush_;
  Flush rxFlush_;
  bool flushStuck_ = false;
};

}  // namespace bsp::mspm0::test
