// Peripheral: what every MSPM0 peripheral model shares, from the common register layout of the TI headers
// (mspm0-sdk source/ti/devices/msp/peripherals/hw_*.h, e.g. UART_Regs) and the TRMs' "Peripheral power
// enable control" and "Interrupt and event" sections (SLAU846B for the MSPM0G, SLAU847D for the MSPM0L):
//
//   +0x800  GPRCM.PWREN   KEY 31:24 must be 0x26 for a write to count; ENABLE bit 0
//   +0x804  GPRCM.RSTCTL  KEY 31:24 must be 0xB1; RESETSTKYCLR bit 1, RESETASSERT bit 0 (write only)
//   +0x814  GPRCM.STAT    RESETSTKY bit 16: the peripheral was reset since the last RESETSTKYCLR
//   +0x1020 CPU_INT       IIDX +0x00, IMASK +0x08, RIS +0x10, MIS +0x18, ISET +0x20, ICLR +0x28
//
// Rules every model enforces (each stops the run when broken, because the real part would not do what the
// firmware expects and the twin must not paper over it):
// - a register access other than GPRCM while PWREN.ENABLE is 0 ("a peripheral's registers are accessible
//   only when its power is enabled", TRM "Peripheral power enable control");
// - an access that is not at a register's address (the register files are 32-bit, hw_*.h declare every
//   register uint32_t); a byte or halfword access at the register's address (the DMA's byte transfers to
//   TXDATA, from RXDATA) reads or writes its low bits;
// - an offset the model does not implement.
// RESETASSERT puts the peripheral's registers back to their reset values (resetRegisters()) and sets
// RESETSTKY; a system reset does the same and also removes power (PWREN resets to 0).
//
// The interrupt output (CPU_INT) is a level, MIS != 0, driven to whatever the chip wires it to (an NVIC line
// or an INT_GROUP member). IIDX reads return the lowest pending MIS bit's index + 1 and clear that RIS bit
// ("A read clears the corresponding interrupt flag in RIS and MIS", hw_uart.h UART_CPU_INT_IIDX_STAT).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "address_map.hpp"
#include "race_watch.hpp"

namespace twin {

class Machine;

// One IIDX/IMASK/RIS/MIS/ISET/ICLR block (CPU_INT, DMA_TRIGx, GEN_EVENTx).
struct EventRegs {
  uint32_t ris = 0, imask = 0;
  uint32_t mis() const { return ris & imask; }
  // `offset` within the block; false for offsets the block does not have.
  bool read(uint32_t offset, uint32_t& value);
  bool write(uint32_t offset, uint32_t value);
};

// CLKDIV (+0x1000, RATIO 2:0 divides the functional clock by RATIO + 1) and CLKSEL (BUSCLK_SEL bit 3) of
// the peripherals clocked from BUSCLK; CLKSEL is at +0x1004 in hw_i2c.h, +0x1008 in hw_uart.h and
// hw_gptimer.h. Each model decides what it refuses (a clock the twin does not model stops the run).
struct ClockRegs {
  explicit ClockRegs(uint32_t selOffset) : selOffset(selOffset) {}
  uint32_t selOffset;
  uint32_t div = 0, sel = 0;
  uint32_t divider() const { return (div & 7U) + 1; }
  bool busclk() const { return (sel & (1U << 3)) != 0; }
  bool lfclk() const { return (sel & (1U << 1)) != 0; }  // LFCLK_SEL (hw_gptimer.h CLKSEL bit 1)
  // False for offsets other than CLKDIV and CLKSEL.
  bool read(uint32_t offset, uint32_t& value) const;
  bool write(uint32_t offset, uint32_t value);
};

class Peripheral : public Device {
 public:
  Peripheral(Machine& machine, std::string name, uint32_t gprcmOffset = 0x800,
             uint32_t cpuIntOffset = 0x1020);
  const char* name() const override { return name_.c_str(); }
  bool read(uint32_t offset, unsigned bytes, uint32_t& value) final;
  bool write(uint32_t offset, unsigned bytes, uint32_t value) final;

  // System reset (SYSRST and above): power off, registers to reset values.
  void systemReset();
  bool powered() const { return powered_; }
  // Where the CPU_INT output goes (an NVIC line, a group member); called with the new level.
  void connectInterrupt(std::function<void(bool)> line) { line_ = std::move(line); }
  // Which CPU_INT events can raise the interrupt output now (IMASK bits, or pending ones) and which are
  // pending (MIS): the data-race rule asks which handlers can preempt, for which source (race_watch.hpp).
  // A model whose events stop at times (a stopped timer) says so in eventsPossible().
  InterruptSources interruptSources() const {
    return {cpuInt_.mis() | (eventsPossible() ? cpuInt_.imask : 0), cpuInt_.mis()};
  }

 protected:
  // Registers beyond GPRCM and CPU_INT. False: no such register (the run stops).
  virtual bool readRegister(uint32_t offset, uint32_t& value) = 0;
  virtual bool writeRegister(uint32_t offset, uint32_t value) = 0;
  virtual void resetRegisters() = 0;  // reset values, no event armed
  // Whether the peripheral can raise an interrupt event at all now (a timer only while it counts).
  virtual bool eventsPossible() const { return true; }
  // The firmware wrote CPU_INT's register at `offset` (ISET +0x20, ICLR +0x28, ...) with `value`, after the
  // block took it: for a model's rules that watch how the firmware arms its events.
  virtual void onCpuIntWrite(uint32_t /*offset*/, uint32_t /*value*/) {}
  // CPU_INT changed (the ISR cleared or masked something, or an event set a flag): recompute the output.
  void updateInterrupt();
  void raise(uint32_t bits) {
    cpuInt_.ris |= bits;
    updateInterrupt();
  }
  // Stops the run with "<name>: <why>".
  void stop(const std::string& why);

  Machine& machine_;
  EventRegs cpuInt_;

 private:
  std::string name_;
  uint32_t gprcmOffset_;
  uint32_t cpuIntOffset_;
  bool powered_ = false;
  bool resetSticky_ = false;
  bool lineLevel_ = false;
  std::function<void(bool)> line_;
};

}  // namespace twin
