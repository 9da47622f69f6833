// Core: an ARMv6-M (Cortex-M0+) instruction interpreter, exact to the architecture for everything the
// MSPM0 images execute, and cycle counted with the Cortex-M0+ timing table (cpu/timing.hpp).
//
// Architecture: ARM DDI 0419E (ARMv6-M Architecture Reference Manual). What it models:
// - every 16-bit Thumb encoding of A5.2 and the 32-bit BL, MSR, MRS, DSB, DMB, ISB (A5.3); anything else
//   is UNDEFINED and raises HardFault, as does an unaligned access (A3.2.1), the instruction after a
//   BX/BLX/POP or exception return to an address with bit 0 clear (EPSR.T = 0: INVSTATE at the target, the
//   stacked xPSR with T clear, B1.4.2), BKPT without a debugger (C1.7) and an SVC that cannot be taken at
//   the current priority (B1.5.6 escalation);
// - the registers of B1.4: R0-R12, MSP/PSP selected by CONTROL.SPSEL in Thread mode, LR, PC, APSR (NZCV),
//   IPSR, PRIMASK, CONTROL;
// - exception entry and return (B1.5.6-B1.5.8): the eight-word frame with 8-byte alignment (xPSR bit 9),
//   EXC_RETURN 0xFFFFFFF1/9/D, vector fetch from VTOR; priorities and PRIMASK through Nvic;
// - WFI (B1.5.19): the core sleeps until an exception would preempt if PRIMASK were 0; WFE/SEV with the
//   event register (B1.5.18); sleep-on-exit (SCR.SLEEPONEXIT, B3.2.7): a return to Thread mode sleeps the
//   same way.
// Memory: flash and SRAM windows are read directly; every other access goes to the CoreBus (peripherals,
// the System Control Space). An access nobody answers halts the core with the PC and the address: the
// twin stops rather than guess (bsp/twin/README.md).
//
// Lockup (a fault in HardFault or NMI, B1.5.13) halts the core with a message too.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "cpu/nvic.hpp"

namespace twin {

class CoreBus {
 public:
  // `bytes` is 1, 2 or 4 and the address is aligned to it. False: no device answers at that address.
  virtual bool load(uint32_t address, unsigned bytes, uint32_t& value) = 0;
  virtual bool store(uint32_t address, unsigned bytes, uint32_t value) = 0;
  // What lives at `address`, for the message that stops the run.
  virtual std::string describe(uint32_t address) const = 0;

 protected:
  ~CoreBus() = default;
};

// Told about exception entry and return (interrupt latency and ISR time measurements), and WFI (the idle
// rule, rules.hpp IDLE-WFI).
class CoreObserver {
 public:
  virtual void onExceptionEntry(int exception) = 0;
  virtual void onExceptionReturn(int exception) = 0;
  virtual void onHardFault(const std::string& why) = 0;
  virtual void onWfi() {}

 protected:
  ~CoreObserver() = default;
};

// Told about every SRAM access an instruction makes (not the exception entry's stacking or the return's
// unstacking): the data-race rule (race_watch.hpp). Null by default: the interpreter's hot path pays one
// branch.
class SramWatch {
 public:
  virtual void onSramLoad(uint32_t address, unsigned bytes) = 0;
  virtual void onSramStore(uint32_t address, unsigned bytes) = 0;

 protected:
  ~SramWatch() = default;
};

class Core {
 public:
  Core(CoreBus& bus, Nvic& nvic) : bus_(bus), nvic_(nvic) {}

  void setFlash(const uint8_t* data, uint32_t size) { flash_ = data, flashSize_ = size; }
  void setSram(uint8_t* data, uint32_t base, uint32_t size) {
    sram_ = data, sramBase_ = base, sramSize_ = size;
  }
  void setObserver(CoreObserver* observer) { observer_ = observer; }
  // FLASHCTL programs or erases: the one flash bank answers no read, instruction fetch or data load
  // (Machine::stallFlashUntil). An instruction whose load hits the flash then does not execute: step()
  // returns 0 with waitingForFlash() set, and runs it again once the bank is free (the machine waits).
  void setFlashBusy(bool busy) { flashBusy_ = busy; }
  bool waitingForFlash() const { return waitingForFlash_; }
  void setSramWatch(SramWatch* watch) { watch_ = watch; }

  // Reset (B1.5.5): MSP and PC from the vector table at VTOR = 0, Thread mode, PRIMASK 0, NVIC reset.
  void reset();

  // Takes a pending exception (returns its entry cycles) or executes one instruction (its cycles). While
  // asleep it wakes if an exception would preempt with PRIMASK 0 and returns 0 either way.
  uint32_t step();

  bool halted() const { return halted_; }
  const std::string& haltReason() const { return haltReason_; }
  void halt(const std::string& why);
  bool sleeping() const { return sleeping_; }
  // An event for WFE (SEV from another agent, or an exception entry/return: B1.5.18).
  void signalEvent() { event_ = true; }

  // --- state (tests, the System Control Space, diagnostics) ------------------------------------------------
  uint32_t pc() const { return pc_; }
  uint32_t reg(int n) const;
  void setReg(int n, uint32_t value);
  uint32_t apsr() const;
  void setApsr(uint32_t value);
  bool primask() const { return primask_; }
  // Critical sections entered so far: +1 each time PRIMASK goes from 0 to 1 (CPSID, MSR). Two accesses with
  // PRIMASK set and the same count lie in one unbroken section.
  uint32_t maskSections() const { return maskSections_; }
  // MSP when the outermost exception now active was taken, before its frame: handlers' own stack lies
  // below it (the data-race rule tells their locals from the Thread's data, race_watch.hpp).
  uint32_t handlerStackTop() const { return handlerStackTop_; }
  uint32_t ipsr() const { return ipsr_; }
  bool handlerMode() const { return ipsr_ != 0; }
  uint32_t control() const { return (spsel_ ? 2U : 0U) | (npriv_ ? 1U : 0U); }
  uint32_t msp() const { return msp_; }
  uint32_t psp() const { return psp_; }
  uint32_t vtor() const { return vtor_; }
  void setVtor(uint32_t value) { vtor_ = value & 0xFFFFFF80U; }
  // SCR.SLEEPONEXIT (B3.2.7), written through the System Control Space: while set, an exception return to
  // Thread mode puts the core to sleep as WFI would, the Thread resuming only after a later handler clears
  // it and returns (TI's MSPM0 SDK: DL_SYSCTL_enableSleepOnExit, SCB->SCR bit 1, used by its low-power
  // examples with a __WFI loop).
  void setSleepOnExit(bool on) { sleepOnExit_ = on; }
  uint64_t instructions() const { return instructions_; }
  uint32_t hardFaults() const { return hardFaults_; }

 private:
  uint32_t& sp() { return (ipsr_ != 0 || !spsel_) ? msp_ : psp_; }
  uint32_t execute(uint16_t op);
  uint32_t execute32(uint16_t hw1, uint16_t hw2);
  bool load(uint32_t address, unsigned bytes, uint32_t& value);
  bool store(uint32_t address, unsigned bytes, uint32_t value);
  bool fetch(uint32_t address, uint16_t& op);
  uint32_t addWithCarry(uint32_t x, uint32_t y, bool carry);  // sets NZCV
  void setNz(uint32_t result) { n_ = result >> 31, z_ = result == 0; }
  bool condition(uint32_t cond) const;
  void branchWritePc(uint32_t address) { next_ = address & ~1U; }
  void bxWritePc(uint32_t address);
  void takeException(int exception, uint32_t returnAddress);
  void exceptionReturn(uint32_t excReturn);
  // Raises HardFault for the current instruction (it returns to itself), or, `completed`, after it (an SVC
  // that escalates: its return address is the next instruction, as SVCall's would be).
  void fault(const std::string& why, bool completed = false);
  std::string where() const;

  CoreBus& bus_;
  Nvic& nvic_;
  CoreObserver* observer_ = nullptr;
  SramWatch* watch_ = nullptr;
  bool stacking_ = false;  // exception entry or return moves the frame: not an instruction's access
  bool flashBusy_ = false;
  bool waitingForFlash_ = false;  // the current instruction's load hit the busy flash bank
  bool vectorFetch_ =
      false;  // exception entry's vector load: the machine charges its wait (onExceptionEntry)
  uint32_t maskSections_ = 0;
  uint32_t handlerStackTop_ = 0;
  const uint8_t* flash_ = nullptr;
  uint32_t flashSize_ = 0;
  uint8_t* sram_ = nullptr;
  uint32_t sramBase_ = 0, sramSize_ = 0;

  std::array<uint32_t, 13> r_{};
  uint32_t msp_ = 0, psp_ = 0, lr_ = 0;
  uint32_t pc_ = 0;    // address of the instruction being executed
  uint32_t next_ = 0;  // address of the next one (a branch overwrites it)
  bool n_ = false, z_ = false, c_ = false, v_ = false;
  uint32_t ipsr_ = 0;
  bool primask_ = false, spsel_ = false, npriv_ = false;
  bool thumb_ = true;  // EPSR.T: a BX/POP/exception return to an even address clears it (B1.4.2)
  uint32_t vtor_ = 0;
  bool sleeping_ = false, waitForEvent_ = false, event_ = false;
  bool sleepOnExit_ = false;
  bool faulted_ = false;      // the current instruction raised HardFault
  uint32_t extraCycles_ = 0;  // an exception return inside the current instruction (its frame pop)
  void setPrimask(bool on) {
    if (on && !primask_) ++maskSections_;
    primask_ = on;
  }
  bool halted_ = false;
  std::string haltReason_;
  uint64_t instructions_ = 0;
  uint32_t hardFaults_ = 0;
};

}  // namespace twin
