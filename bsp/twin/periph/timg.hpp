// Timg: a 16-bit general-purpose timer (TIMG0/1/2/4 on the L1306, TIMG0/6/7/8 on the G3507), registers from
// mspm0-sdk hw_gptimer.h (CLKDIV 0x1000, CLKSEL 0x1008, CCLKCTL 0x1108, CPS 0x110C, CTR 0x1800, CTRCTL
// 0x1804, LOAD 0x1808, CC0/1 0x1810/0x1814, CCCTL0/1 0x1830/0x1834) and their field descriptions.
//
// Counting (hw_gptimer.h CTRCTL descriptions; SLAU846B/SLAU847D "TIMx" chapter, counter operation):
// - The counter clock is BUSCLK (CLKSEL.BUSCLK_SEL) / (CLKDIV.RATIO + 1) / (CPS.PCNT + 1), running only with
//   CCLKCTL.CLKEN. Other clock sources stop the run (not modelled).
// - EN 0 -> 1 sets the counter from CVAE: LOAD (0), unchanged (1) or zero (2).
// - Up (CM = 2): 0, 1, ..., LOAD, 0, ...; the LOAD event when the counter becomes LOAD, the ZERO event
//   when it wraps to 0, CCUn when it becomes CCn counting up. With REPEAT = 0 the counter stays at 0 after
//   that wrap (the same REPEAT text as below: the wrap is a zero event), so it runs one period only.
// - Down (CM = 0): LOAD, ..., 1, 0; the ZERO event at 0, then with REPEAT = 1 a load at the next advance
//   (LOAD event), with REPEAT = 0 the counter stays at 0 ("Does not automatically advance following a zero
//   event"). CCDn when it becomes CCn counting down.
// - The counter advances on every timer clock only if the CCCTL that CTRCTL.CAC selects has ACOND = TIMCLK,
//   and its LCOND/ZCOND have no effect; any other advance/load/zero control, up/down counting, a reserved
//   CAC/CLC/CZC (their reset value 7) on an enabled counter, or capture mode (CCCTL.COC) stops the run.
// - Event flags (CPU_INT RIS) are exact to the timer clock: every event is scheduled on the timeline,
//   masked or not.
// - Tick (rules.hpp TIMER-TICK, image runs only): a counter enabled with a clock other than 1 MHz stops the
//   run: the product's timers count the firmware's microseconds.
#pragma once

#include <cstdint>

#include "periph/peripheral.hpp"
#include "timeline.hpp"

namespace twin {

class Timg final : public Peripheral {
 public:
  Timg(Machine& machine, const char* name);

  // CPU_INT bits (hw_gptimer.h GPTIMER_CPU_INT_IMASK_*).
  static constexpr uint32_t kZero = 1U << 0, kLoad = 1U << 1, kCcd0 = 1U << 4, kCcu0 = 1U << 8;
  // The counter counts, from BUSCLK (the only clock the model runs: TIMER-TICK), with an interrupt that can
  // still fire: a deadline the firmware waits for (the power-mode rule, rules.hpp SLEEP-EVENT-LOST).
  bool deadlineArmed() const { return eventsPossible() && cpuInt_.imask != 0; }

 private:
  bool readRegister(uint32_t offset, uint32_t& value) override;
  bool writeRegister(uint32_t offset, uint32_t value) override;
  void resetRegisters() override;

  bool running() const;
  bool eventsPossible() const override { return running() && !stoppedAtZero_; }
  uint64_t tickCycles() const;
  uint32_t counterNow() const;  // value at timeline now
  void rebase();                // counter value at now becomes the new base
  void schedule();
  void onTick();
  void checkControl();
  void checkTick();  // rules.hpp TIMER-TICK, when the counter is enabled

  TimedEvent event_;
  ClockRegs clock_{0x1008};
  uint32_t cclkctl_ = 0, cps_ = 0;
  uint32_t ctrctl_ = 0, load_ = 0;
  uint32_t cc_[2] = {0, 0}, ccctl_[2] = {0, 0};
  uint32_t baseValue_ = 0;  // counter value at baseCycle_
  uint64_t baseCycle_ = 0;
  bool stoppedAtZero_ = false;
};

}  // namespace twin
