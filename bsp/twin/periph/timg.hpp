// Timg: a 16-bit general-purpose timer (TIMG0/1/2/4 on the L1306, TIMG0/6/7/8 on the G3507), registers from
// mspm0-sdk hw_gptimer.h (CLKDIV 0x1000, CLKSEL 0x1008, CCLKCTL 0x1108, CPS 0x110C, CTR 0x1800, CTRCTL
// 0x1804, LOAD 0x1808, CC0/1 0x1810/0x1814, CCCTL0/1 0x1830/0x1834) and their field descriptions.
//
// Counting (hw_gptimer.h CTRCTL descriptions; SLAU846B/SLAU847D "TIMx" chapter, counter operation):
// - The counter clock is BUSCLK (CLKSEL.BUSCLK_SEL) or LFCLK (CLKSEL.LFCLK_SEL, 32 768 Hz from LFOSC)
//   / (CLKDIV.RATIO + 1) / (CPS.PCNT + 1), running only with CCLKCTL.CLKEN. MFCLK stops the run (not
//   modelled). LFCLK edges are counted from power-on on one machine-wide grid (edge n at the first cycle at
//   or after n x clockHz / 32 768), so two LFCLK timers tick together and no rounding accumulates.
// - Low-power modes: LFCLK runs in RUN, SLEEP, STOP and STANDBY (SLAU846A / SLAU847D 2 "LFCLK"), so an LFCLK
//   timer keeps counting and its interrupt wakes the core, where the instance keeps its clock (StandbyClock
//   below). A BUSCLK timer does not count as configured in STOP or STANDBY (rules.hpp SLEEP-EVENT-LOST).
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
// - Tick (rules.hpp TIMER-TICK, image runs only): a BUSCLK counter enabled at other than 1 MHz stops the
//   run: the product's timers count the firmware's microseconds. An LFCLK counter is not checked: its
//   32 768 Hz is what a deep-sleep wake timer counts (bsp/mspm0/README.md "Low-power modes").
// - Compare events (rules.hpp TIMER-COMPARE-UNSEEN, image runs only): a written CCn whose event comes 3 times
//   masked, never once unmasked, on a counter whose interrupt serves other events, is named (a warning).
// - Arming a compare (rules.hpp TIMER-COMPARE-PASSED, image runs only): a CCn written while the counter runs,
//   its event unmasked, must be re-checked (a CTR read after the write and after the last ICLR of the event,
//   or an ISET of it) before the core sleeps, unless the event is already pending: a compare the counter
//   passed while it was being armed fires only a wrap later.
#pragma once

#include <cstdint>
#include <string>

#include "periph/peripheral.hpp"
#include "power_mode.hpp"
#include "timeline.hpp"

namespace twin {

// Which deep modes still clock an instance from LFCLK (data sheets' "supported functionality in each
// operating mode" tables: MSPM0L130x SLASEX0D table 8-1, MSPM0G350x SLAU846A table 2-14 and 2 "LFCLK").
enum class StandbyClock : uint8_t {
  AllModes,      // TIMG0/TIMG1: PD0 and clocked in STANDBY1 too (STOPCLKSTBY leaves them LFCLK)
  UpToStandby0,  // other PD0 timers (L1306 TIMG2/TIMG4): STOP and STANDBY0, not STANDBY1
  RunSleepOnly,  // PD1 timers (G3507 TIMG6/TIMG7): "forced to a disabled state" in STOP and STANDBY
};

class Timg final : public Peripheral {
 public:
  Timg(Machine& machine, const char* name, StandbyClock standby = StandbyClock::RunSleepOnly);

  // CPU_INT bits (hw_gptimer.h GPTIMER_CPU_INT_IMASK_*).
  static constexpr uint32_t kZero = 1U << 0, kLoad = 1U << 1, kCcd0 = 1U << 4, kCcu0 = 1U << 8;
  // The counter counts with an interrupt that can still fire: a deadline the firmware waits for.
  bool deadlineArmed() const { return eventsPossible() && cpuInt_.imask != 0; }
  // Why a deadline armed now would not arrive as configured if the core slept in `mode` (empty if it would):
  // a BUSCLK count in any deep mode, an LFCLK count on an instance `mode` does not clock (rules.hpp
  // SLEEP-EVENT-LOST).
  std::string deadlineLostIn(PowerMode mode) const;
  // TIMER-COMPARE-PASSED (rules.hpp): called whenever the core is asleep; stops the run for a compare armed
  // while the counter ran and not re-checked since.
  void checkArmedCompares();

 private:
  bool readRegister(uint32_t offset, uint32_t& value) override;
  bool writeRegister(uint32_t offset, uint32_t value) override;
  void resetRegisters() override;

  bool running() const;
  bool eventsPossible() const override { return running() && !stoppedAtZero_; }
  // The counter's source clock in edges since power-on: cycles for BUSCLK, LFCLK edges for LFCLK.
  uint64_t edgesAt(uint64_t cycle) const;
  uint64_t cycleOfEdge(uint64_t edge) const;  // the first cycle at which `edge` has happened
  uint64_t tickEdges() const;                 // source edges per counter tick
  uint32_t counterNow() const;                // value at timeline now
  void rebase();                              // counter value at now becomes the new base
  void schedule();
  void onTick();
  void checkControl();
  void checkTick();  // rules.hpp TIMER-TICK, when the counter is enabled

  TimedEvent event_;
  ClockRegs clock_{0x1008};
  uint32_t cclkctl_ = 0, cps_ = 0;
  uint32_t ctrctl_ = 0, load_ = 0;
  uint32_t cc_[2] = {0, 0}, ccctl_[2] = {0, 0};
  uint32_t baseValue_ = 0;  // counter value at source edge baseEdge_
  uint64_t baseEdge_ = 0;
  StandbyClock standby_;
  bool stoppedAtZero_ = false;
  // TIMER-COMPARE-UNSEEN (rules.hpp): per compare register, written by the firmware, its event seen unmasked
  // once, and how often it came masked.
  bool ccWritten_[2] = {false, false}, ccSeen_[2] = {false, false};
  uint32_t ccUnseen_[2] = {0, 0};
  void checkCompareSeen(int n, uint32_t bit);
  // TIMER-COMPARE-PASSED (rules.hpp): the firmware's last CTR read, and per compare register an arming (a
  // write of CCn while counting, or an ICLR of its event after one) that no CTR read or ISET followed yet.
  struct CounterRead {
    bool valid = false;
    uint32_t value = 0;
    uint64_t cycle = 0;
  };
  struct Arming {
    bool open = false;
    CounterRead from;  // the read before the write: the value the firmware computed CCn from
    uint64_t armedAt = 0;
  };
  CounterRead lastRead_;
  Arming arming_[2];
  uint32_t compareBit(int n) const;  // CCUn counting up, CCDn counting down
  void onCpuIntWrite(uint32_t offset, uint32_t value) override;
};

}  // namespace twin
