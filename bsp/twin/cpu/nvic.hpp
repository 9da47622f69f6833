// Nvic: the ARMv6-M exception state of the twin's core: pending, active and enabled exceptions, their
// priorities, and the choice of the exception to take (ARMv6-M ARM, DDI 0419E, B1.5.4 "Exception priorities
// and preemption" and B3.4 "Nested Vectored Interrupt Controller").
//
// Exception numbers: 1 Reset, 2 NMI, 3 HardFault, 11 SVCall, 14 PendSV, 15 SysTick, 16 + n external IRQ n
// (n = 0..31). Priorities are the architecture's: NMI -2, HardFault -1, every other exception 0..3 from the
// top two bits of its 8-bit priority field (DDI 0419E B3.4.7: ARMv6-M implements bits [7:6] only), lower
// is more urgent; with equal priority the lower exception number wins (B1.5.4).
//
// External interrupt inputs are levels, as the MSPM0 peripherals drive them (an interrupt output is its MIS
// != 0): a line that is asserted while its exception is not active is pending, so a handler that returns
// with its source still asserted is entered again (DDI 0419E B3.4.1; ARM DUI 0662B 4.2.9 "level-sensitive
// interrupts"). A rising level while the exception is active latches pending as well. ISPR/ICPR set and
// clear the latch only: clearing a line that is still asserted leaves it pending.
//
// All calls are plain state updates: the core (core.hpp) asks pendingToTake() at every instruction boundary.
#pragma once

#include <array>
#include <cstdint>

namespace twin {

class Nvic {
 public:
  static constexpr int kExceptions = 48;     // 16 system + 32 external
  static constexpr int kThreadPriority = 4;  // one below the least urgent configurable priority (B1.5.4)

  enum : int { kReset = 1, kNmi = 2, kHardFault = 3, kSvcall = 11, kPendsv = 14, kSystick = 15, kIrq0 = 16 };

  Nvic() { reset(); }
  void reset();

  // --- inputs --------------------------------------------------------------------------------------------
  void setIrqLevel(int irq, bool asserted);
  void setPending(int exception);    // latch (ISPR, ICSR.PENDSVSET/PENDSTSET, SVC, faults)
  void clearPending(int exception);  // clears the latch (ICPR, ICSR.PENDSVCLR/PENDSTCLR)

  // --- NVIC registers (B3.4) -------------------------------------------------------------------------------
  uint32_t enabledIrqs() const { return enabled_; }
  void enableIrqs(uint32_t mask) {
    enabled_ |= mask;
    everEnabled_ |= mask;
  }
  // The lines enabled at any time since the reset (rules.hpp IRQ-UNSERVED).
  uint32_t everEnabledIrqs() const { return everEnabled_; }
  void disableIrqs(uint32_t mask) { enabled_ &= ~mask; }
  uint32_t pendingIrqs() const { return static_cast<uint32_t>(pendingMask() >> kIrq0); }
  // 8-bit priority field as software reads it (bits [7:6] kept, the rest read as zero).
  uint8_t priorityField(int exception) const { return static_cast<uint8_t>(priority_[exception] << 6); }
  void setPriorityField(int exception, uint8_t value);

  // --- state the core uses ---------------------------------------------------------------------------------
  bool pending(int exception) const { return (pendingMask() >> exception) & 1U; }
  bool active(int exception) const { return (active_ >> exception) & 1U; }
  uint64_t activeMask() const { return active_; }
  int priority(int exception) const { return priority_[exception]; }
  // Execution priority (B1.5.4): the most urgent active exception's priority, boosted to 0 by PRIMASK.
  int executionPriority(bool primask) const;
  // The pending, enabled exception that would preempt at `executionPriority`, or 0.
  int pendingToTake(int executionPriority) const;
  void activate(int exception);    // exception entry: pending latch cleared, active set
  void deactivate(int exception);  // exception return
  // Fast check for the core's instruction loop: is any enabled exception pending at all?
  bool anyPending() const { return candidates() != 0; }
  // Highest-priority pending exception regardless of the execution priority (ICSR.VECTPENDING), or 0.
  int highestPending() const { return pendingToTake(kThreadPriority + 1); }

 private:
  uint64_t pendingMask() const { return latch_ | (level_ & ~active_); }
  uint64_t candidates() const;

  uint64_t latch_ = 0;
  uint64_t level_ = 0;
  uint64_t active_ = 0;
  uint32_t enabled_ = 0;
  uint32_t everEnabled_ = 0;
  std::array<int8_t, kExceptions> priority_{};
};

}  // namespace twin
