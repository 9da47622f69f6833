#include "periph/timg.hpp"

#include <cstdio>

#include "machine.hpp"

namespace twin {

namespace {

constexpr uint32_t kClksel = 0x1008, kCclkctl = 0x1108, kCps = 0x110C;
constexpr uint32_t kCtr = 0x1800, kCtrctl = 0x1804, kLoadReg = 0x1808, kCc0 = 0x1810, kCcctl0 = 0x1830;

constexpr uint32_t kEn = 1U << 0;
constexpr uint32_t kRepeatMask = 0xE;
constexpr uint32_t kCmMask = 0x30, kCmDown = 0x00, kCmUp = 0x20;
constexpr uint32_t kCvaeMask = 0x30000000, kCvaeLoad = 0x00000000, kCvaeZero = 0x20000000;
constexpr uint32_t kCounterMask = 0xFFFF;  // TIMGx here are 16-bit timers
constexpr uint32_t kCcctlCoc = 1U << 17;   // capture (1) or compare (0)
constexpr uint32_t kCcctlAcond = 0x70, kCcctlLcond = 0x700, kCcctlZcond = 0x7000;
// LFCLK from LFOSC after BOOTRST, 32 768 Hz (SLAU846A / SLAU847D 2 "LFCLK"; SLASEX0D 7.9.2 LFOSC).
constexpr uint64_t kLfclkHz = 32768;

}  // namespace

Timg::Timg(Machine& machine, const char* name, StandbyClock standby)
    : Peripheral(machine, name), event_(machine.timeline(), [this] { onTick(); }), standby_(standby) {}

void Timg::resetRegisters() {
  clock_ = ClockRegs(kClksel);
  cclkctl_ = cps_ = load_ = 0;
  ctrctl_ = (7U << 7) | (7U << 10) | (7U << 13);  // CLC/CAC/CZC reset to 7 (reserved encodings)
  cc_[0] = cc_[1] = ccctl_[0] = ccctl_[1] = 0;
  ccWritten_[0] = ccWritten_[1] = ccSeen_[0] = ccSeen_[1] = false;
  ccUnseen_[0] = ccUnseen_[1] = 0;
  lastRead_ = {};
  arming_[0] = arming_[1] = {};
  baseValue_ = 0;
  baseEdge_ = edgesAt(machine_.now());
  stoppedAtZero_ = false;
  event_.cancel();
}

bool Timg::running() const {
  return (ctrctl_ & kEn) && (cclkctl_ & 1U) && (clock_.busclk() || clock_.lfclk()) && powered();
}

uint64_t Timg::edgesAt(uint64_t cycle) const {
  if (!clock_.lfclk() || clock_.busclk()) return cycle;
  return cycle * kLfclkHz / machine_.clockHz();
}

uint64_t Timg::cycleOfEdge(uint64_t edge) const {
  if (!clock_.lfclk() || clock_.busclk()) return edge;
  return (edge * machine_.clockHz() + kLfclkHz - 1) / kLfclkHz;
}

uint64_t Timg::tickEdges() const {
  return static_cast<uint64_t>(clock_.divider()) * ((cps_ & 0xFFU) + 1);
}

std::string Timg::deadlineLostIn(PowerMode mode) const {
  if (!isDeepSleep(mode) || !deadlineArmed()) return {};
  const std::string n(name());
  if (!clock_.lfclk() || clock_.busclk())
    return n + " counts a deadline from the 32 MHz BUSCLK this mode stops (an LFCLK timer keeps counting)";
  if (standby_ == StandbyClock::RunSleepOnly)
    return n + " is in PD1: disabled in STOP and STANDBY even on LFCLK (SLAU846A TIMx, low-power modes)";
  if (standby_ == StandbyClock::UpToStandby0 && mode == PowerMode::Standby1)
    return n + " gets no LFCLK in STANDBY1: only TIMG0/TIMG1 do (SLASEX0D table 8-1, SLAU846A 2 LFCLK)";
  return {};
}

uint32_t Timg::counterNow() const {
  if (!running() || stoppedAtZero_) return baseValue_;
  const uint64_t ticks = (edgesAt(machine_.now()) - baseEdge_) / tickEdges();
  const uint64_t period = static_cast<uint64_t>(load_ & kCounterMask) + 1;
  if ((ctrctl_ & kCmMask) == kCmUp) return static_cast<uint32_t>((baseValue_ + ticks) % period);
  // Down: baseValue_, ..., 0, then LOAD again if repeating.
  if (ticks <= baseValue_) return baseValue_ - static_cast<uint32_t>(ticks);
  if ((ctrctl_ & kRepeatMask) == 0) return 0;
  const uint64_t after = (ticks - baseValue_ - 1) % period;
  return static_cast<uint32_t>((load_ & kCounterMask) - after);
}

void Timg::rebase() {
  // Keep the tick phase: the new base is the last tick boundary at or before now.
  if (running() && !stoppedAtZero_) {
    const uint64_t ticks = (edgesAt(machine_.now()) - baseEdge_) / tickEdges();
    baseValue_ = counterNow();
    baseEdge_ += ticks * tickEdges();
  } else {
    baseEdge_ = edgesAt(machine_.now());
  }
}

void Timg::checkTick() {
  // The product's timers count microseconds: fw::Duration's unit, TimgClock and TimgOneShot at 1 MHz
  // (bsp/mspm0/README.md); the counter clock as SLAU846B / SLAU847D TIMx give it (periph/timg.hpp).
  if (!machine_.imageRules() || !clock_.busclk()) return;
  const uint64_t divider = tickEdges();
  if (divider * 1000000 == machine_.clockHz()) return;
  char buf[240];
  std::snprintf(buf, sizeof buf,
                "%s: counts at %u Hz (BUSCLK %u Hz / CLKDIV %u / CPS.PCNT+1 %u), not the 1 MHz of the "
                "firmware's microsecond time base: every period and timeout is off by %+.2f %%",
                name(), static_cast<unsigned>(machine_.clockHz() / divider),
                static_cast<unsigned>(machine_.clockHz()), clock_.divider(), (cps_ & 0xFFU) + 1,
                (static_cast<double>(divider) * 1e6 / machine_.clockHz() - 1.0) * 100.0);
  machine_.violate(Rule::TimerTick, buf);
}

void Timg::checkControl() {
  if ((ctrctl_ & kEn) == 0) return;
  char buf[128];
  const uint32_t cac = (ctrctl_ >> 10) & 7U, clc = (ctrctl_ >> 7) & 7U, czc = (ctrctl_ >> 13) & 7U;
  const uint32_t cm = ctrctl_ & kCmMask;
  if (cac > 1 || clc > 1 || czc > 1 || (cm != kCmUp && cm != kCmDown)) {
    std::snprintf(buf, sizeof buf, "CTRCTL 0x%08X enables the counter with a control the twin does not model",
                  ctrctl_);
    stop(buf);
    return;
  }
  const uint32_t cc = ccctl_[cac];
  if ((cc & kCcctlCoc) || (cc & kCcctlAcond) != 0 || (ccctl_[clc] & kCcctlLcond) != 0 ||
      (ccctl_[czc] & kCcctlZcond) != 0) {
    std::snprintf(buf, sizeof buf, "CCCTL 0x%08X: capture mode or CCP-driven counting, not modelled", cc);
    stop(buf);
  }
}

void Timg::schedule() {
  event_.cancel();
  if (!running() || stoppedAtZero_) return;
  const uint32_t v = counterNow();
  const uint64_t period = static_cast<uint64_t>(load_ & kCounterMask) + 1;
  const bool up = (ctrctl_ & kCmMask) == kCmUp;
  const bool repeat = (ctrctl_ & kRepeatMask) != 0;
  // Ticks until the counter next shows `x` (strictly in the future).
  auto until = [&](uint32_t x) -> uint64_t {
    if (x > (load_ & kCounterMask)) return UINT64_MAX;
    if (up) {
      const uint64_t d = (static_cast<uint64_t>(x) + period - v) % period;
      return d == 0 ? period : d;
    }
    if (x < v) return v - x;  // still on the way down
    if (!repeat) return UINT64_MAX;
    return v + 1 + ((load_ & kCounterMask) - x);  // after the zero, via LOAD
  };
  uint64_t d = std::min(until(0), until(load_ & kCounterMask));
  for (uint32_t c : cc_)
    d = std::min(d, until(c & kCounterMask));
  if (d == UINT64_MAX) return;
  // The tick boundary d ticks after the one the counter showed v on.
  const uint64_t ticksSoFar = (edgesAt(machine_.now()) - baseEdge_) / tickEdges();
  event_.at(cycleOfEdge(baseEdge_ + (ticksSoFar + d) * tickEdges()));
}

void Timg::checkCompareSeen(int n, uint32_t bit) {
  // TIMER-COMPARE-UNSEEN (rules.hpp): the firmware set CCn up, the counter's interrupt serves other events,
  // and this event never once reached the CPU (hw_gptimer.h CPU_INT IMASK; SLAU846B / SLAU847D TIMx
  // interrupts). Three times, so that an alarm armed just after its compare passed is not named.
  if (!machine_.imageRules() || !ccWritten_[n] || ccSeen_[n] || cpuInt_.imask == 0) return;
  if (cpuInt_.imask & bit) {
    ccSeen_[n] = true;
    return;
  }
  if (++ccUnseen_[n] != 3) return;
  char buf[240];
  std::snprintf(buf, sizeof buf,
                "%s: CC%d (0x%04X) reached 3 times with its event masked (IMASK 0x%X) while the timer's "
                "interrupt serves other events: the compare the firmware set up never reaches the CPU",
                name(), n, static_cast<unsigned>(cc_[n] & kCounterMask),
                static_cast<unsigned>(cpuInt_.imask));
  machine_.violate(Rule::TimerCompareUnseen, buf);
}

void Timg::onTick() {
  const uint32_t v = counterNow();
  const bool up = (ctrctl_ & kCmMask) == kCmUp;
  uint32_t bits = 0;
  if (v == 0) bits |= kZero;
  // Up: the counter reached LOAD; down: it was reloaded with LOAD after a zero (an enable sets it to LOAD
  // without a tick, so a tick that shows LOAD is always a reload).
  if (v == (load_ & kCounterMask)) bits |= kLoad;
  for (int n = 0; n < 2; ++n) {
    if (v != (cc_[n] & kCounterMask)) continue;
    bits |= (up ? kCcu0 : kCcd0) << n;
    checkCompareSeen(n, (up ? kCcu0 : kCcd0) << n);
  }
  // Without REPEAT the counter holds at zero after its zero event, counting down (at 0) and up (the wrap from
  // LOAD to 0) alike: hw_gptimer.h CTRCTL.REPEAT 0 "Does not automatically advance following a zero event";
  // SLAU846B / SLAU847D TIMx counter operation (periph/timg.hpp).
  if (v == 0 && (ctrctl_ & kRepeatMask) == 0) {
    baseValue_ = 0;
    stoppedAtZero_ = true;
  }
  raise(bits);
  schedule();
}

uint32_t Timg::compareBit(int n) const {
  return ((ctrctl_ & kCmMask) == kCmUp ? kCcu0 : kCcd0) << n;
}

void Timg::onCpuIntWrite(uint32_t offset, uint32_t value) {
  constexpr uint32_t kIset = 0x20, kIclr = 0x28;  // hw_gptimer.h CPU_INT ISET, ICLR
  for (int n = 0; n < 2; ++n) {
    if (!arming_[n].open || (value & compareBit(n)) == 0) continue;
    // ICLR wipes a match that came before it, so the window the re-check must cover ends here; ISET pends
    // the event: the firmware itself made sure the wake-up comes.
    if (offset == kIclr) arming_[n].armedAt = machine_.now();
    if (offset == kIset) arming_[n].open = false;
  }
}

void Timg::checkArmedCompares() {
  // TIMER-COMPARE-PASSED (rules.hpp): the compare event comes only when the counter becomes CCn (SLAU847D
  // 23 TIMx, shadow compare table 23-16: "TIMx.CTR value equals TIMx.CC"; hw_gptimer.h CPU_INT CCU0), so
  // an alarm armed while the counter moves needs a look at the counter after the arming. An event already
  // pending (RIS) is not lost: the core does not sleep through it.
  if (!machine_.imageRules() || !eventsPossible()) return;
  for (int n = 0; n < 2; ++n) {
    const Arming& a = arming_[n];
    const uint32_t bit = compareBit(n);
    if (!a.open || (cpuInt_.imask & bit) == 0 || (cpuInt_.ris & bit) != 0) continue;
    const uint64_t wrapCycles =
        cycleOfEdge(baseEdge_ + (static_cast<uint64_t>(load_ & kCounterMask) + 1) * tickEdges()) -
        cycleOfEdge(baseEdge_);
    char from[96] = "without a read of CTR before it";
    if (a.from.valid)
      std::snprintf(from, sizeof from, "from CTR read as 0x%04X %llu cycles before the arming",
                    static_cast<unsigned>(a.from.value),
                    static_cast<unsigned long long>(a.armedAt - a.from.cycle));
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "%s: CC%d (0x%04X) armed for a wake-up (IMASK 0x%X) %s, and the core sleeps with no read "
                  "of CTR since and no ISET of the event: the compare fires only when the counter becomes "
                  "CC%d, so a deadline the counter passes while it is armed (one that close, or already "
                  "due) wakes the core a wrap, %.1f ms, late",
                  name(), n, static_cast<unsigned>(cc_[n] & kCounterMask),
                  static_cast<unsigned>(cpuInt_.imask), from, n,
                  static_cast<double>(wrapCycles) * 1000.0 / static_cast<double>(machine_.clockHz()));
    machine_.violate(Rule::TimerComparePassed, buf);
    return;
  }
}

bool Timg::readRegister(uint32_t offset, uint32_t& value) {
  if (clock_.read(offset, value)) return true;
  switch (offset) {
    case kCclkctl:
      value = cclkctl_;
      return true;
    case kCps:
      value = cps_;
      return true;
    case kCtr:
      value = counterNow();
      // TIMER-COMPARE-PASSED: a read after an arming is the re-check that sees a compare already passed.
      lastRead_ = {true, value, machine_.now()};
      arming_[0].open = arming_[1].open = false;
      return true;
    case kCtrctl:
      value = ctrctl_;
      return true;
    case kLoadReg:
      value = load_;
      return true;
    case kCc0:
    case kCc0 + 4:
      value = cc_[(offset - kCc0) / 4];
      return true;
    case kCcctl0:
    case kCcctl0 + 4:
      value = ccctl_[(offset - kCcctl0) / 4];
      return true;
    default:
      return false;
  }
}

bool Timg::writeRegister(uint32_t offset, uint32_t value) {
  rebase();
  if (clock_.write(offset, value)) {
    // CLKSEL: MFCLK_SEL bit 2 is not modelled; 0 (no clock) is a valid reset value. A new source keeps the
    // counter value (rebase above) and counts on from the source's current edge.
    if ((clock_.sel & 0x4U) != 0 && !clock_.busclk()) stop("CLKSEL selects MFCLK, not modelled");
    baseEdge_ = edgesAt(machine_.now());
    schedule();
    return true;
  }
  switch (offset) {
    case kCclkctl:
      cclkctl_ = value;
      break;
    case kCps:
      cps_ = value;
      break;
    case kCtr:
      baseValue_ = value & kCounterMask;
      stoppedAtZero_ = false;
      break;
    case kCtrctl: {
      const bool enabling = (value & kEn) && !(ctrctl_ & kEn);
      ctrctl_ = value;
      if (enabling) {
        checkTick();
        const uint32_t cvae = value & kCvaeMask;
        if (cvae == kCvaeLoad) baseValue_ = load_ & kCounterMask;
        if (cvae == kCvaeZero) baseValue_ = 0;
        baseEdge_ = edgesAt(machine_.now());
        stoppedAtZero_ = false;
      }
      checkControl();
      break;
    }
    case kLoadReg:
      load_ = value;
      break;
    case kCc0:
    case kCc0 + 4:
      cc_[(offset - kCc0) / 4] = value;
      ccWritten_[(offset - kCc0) / 4] = true;
      if (running() && !stoppedAtZero_) arming_[(offset - kCc0) / 4] = {true, lastRead_, machine_.now()};
      break;
    case kCcctl0:
    case kCcctl0 + 4:
      ccctl_[(offset - kCcctl0) / 4] = value;
      checkControl();
      break;
    default:
      return false;
  }
  schedule();
  return true;
}

}  // namespace twin
