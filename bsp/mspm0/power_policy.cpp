#include "power_policy.hpp"

#include "hal/irq.hpp"
#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/gpio.hpp"
#include "regs/i2c.hpp"
#include "regs/sysctl.hpp"
#include "regs/timg.hpp"
#include "regs/uart.hpp"

namespace bsp::mspm0 {

namespace timg = reg::timg;

namespace {
// SCR (0xE000ED10) and its SLEEPDEEP bit 2 (ARMv6-M ARM B3.2.7; CMSIS core_cm0plus.h SCB_SCR_SLEEPDEEP): the
// WFI enters the mode PMODECFG selects. Written whole, as the port writes SCR (cortex_m/port/irq_port.hpp):
// SLEEPONEXIT stays clear for this sleep, so the Thread runs after the handler that woke the core and the
// next idle chooses again. Through mmio, so that the register model of the host tests sees it.
constexpr uintptr_t kScr = 0xE000ED10;
constexpr uint32_t kScrSleepDeep = 1U << 2;

inline void writeScr(uint32_t value) {
  mmio::block<mmio::Reg>(kScr).write(value);
}

// Microseconds to LFCLK ticks, rounded down (x 67 / 2048 = 0.032715 ticks/us, 0.16 % under 32 768 / 1e6):
// the wake-up comes early, never late; the rest is slept on the exact clock. kMaxSleepUs x 67 fits 32 bits.
constexpr uint32_t ticksFor(uint32_t us) {
  return (us * 67U) >> 11;
}
static_assert(ticksFor(StandbyIdle::kMaxSleepUs) < 0xF000 && ticksFor(1000000) <= 32768);
}  // namespace

void StandbyIdle::init(const Config& config) {
  // The LFCLK timer, in the TIMCLK set-up order of the TRM (SLAU847D TIMx: source, divider, prescaler,
  // enable): LFCLK /1, free-running up-count over 16 bits, compare 0 for the wake-up (hw_gptimer.h CLKSEL
  // LFCLK_SEL, bit 1).
  const uintptr_t base = config.lfTimer;
  reg::resetAndPowerUp(reg::gprcm(base));
  timg::Clock& clk = timg::clock(base);
  clk.clksel.write(timg::kClkselLfclk);
  clk.clkdiv.write(0);
  timg::Common& com = timg::common(base);
  com.cps.write(0);
  com.cclkctl.write(timg::kClockEnable);
  timg::Counter& counter = timg::counter(base);
  counter.load.write(0xFFFF);
  counter.ccctl[0].write(0);
  counter.ctrctl.write(timg::kCtrEnable | timg::kCtrRepeat | timg::kCtrCountUp | timg::kCtrStartAtZero);
  nvic::enable(config.lfIrq);
  reg::sysctl::pmodecfg().write(reg::sysctl::kPmodeStandby);
  mmio::setBits(reg::sysctl::clocks().mclkcfg, reg::sysctl::kMclkStopClkStandby);
}

bool StandbyIdle::doSleep(bool timed, fw::Instant deadline) {
  if ((reg::i2c::controller(config_.i2c).msr.read() & reg::i2c::kMsrBusy) != 0 ||
      (reg::uart::line(config_.uart).stat.read() & reg::uart::kStatBusy) != 0)
    return false;
  // GPIO_ERR_01 case 2 (SLAZ741A 6.4, L130x rev C; SLAZ742A for the G350x): when a GPIO edge woke the device
  // and the pulse is still active as it goes back to STANDBY1, no later wake edge is detected. So STANDBY1
  // waits until every falling-edge wake pin (ALERT, active low) reads high again; SLEEP0, not a STANDBY
  // mode, keeps catching edges meanwhile.
  if ((reg::gpio::input(config_.wakePort).din.read() & config_.wakePins) != config_.wakePins) return false;
  uint32_t sleepUs = kMaxSleepUs;
  if (timed) {
    const int32_t left = static_cast<int32_t>(deadline.us - clock_.now().us);
    if (left < static_cast<int32_t>(2 * kMarginUs)) return false;
    if (static_cast<uint32_t>(left) - kMarginUs < sleepUs) sleepUs = static_cast<uint32_t>(left) - kMarginUs;
  }

  timg::Counter& lf = timg::counter(config_.lfTimer);
  reg::EventBlock& lfEvents = reg::cpuInt(config_.lfTimer);
  const uint32_t start = lf.ctr.read();
  const fw::Instant halted = clock_.halt();
  const uint32_t ticks = ticksFor(sleepUs);
  lf.cc[0].write((start + ticks) & 0xFFFF);
  lfEvents.iclr.write(timg::kIntCcu0);
  lfEvents.imask.write(timg::kIntCcu0);
  // The compare fires only when the count becomes CC0 (SLAU847D TIMx compare): if it got there while this
  // was armed, pend the wake-up ourselves.
  if (((lf.ctr.read() - start) & 0xFFFF) >= ticks) lfEvents.iset.write(timg::kIntCcu0);

  // The flash prefetcher is already off (CPU_ERR_03): the scheduler's idle turned it off before asking this
  // policy and turns it on again once the Thread runs on (fw::port::chipSleepBegin, chip_sleep.hpp).
  writeScr(kScrSleepDeep);
  fw::port::waitForInterrupt();
  writeScr(0);

  const uint32_t woke = lf.ctr.read();
  // The compare's request is consumed here, never by a handler: mask it, clear it, drop its NVIC pending.
  lfEvents.imask.write(0);
  lfEvents.iclr.write(timg::kIntCcu0);
  nvic::regs().icpr.write(1U << config_.lfIrq);
  clock_.resume(timeAfterSleep(anchor_, halted, start, woke), timed, deadline);
  return true;
}

fw::Instant StandbyIdle::timeAfterSleep(Anchor& anchor, fw::Instant halted, uint32_t lfAtHalt,
                                        uint32_t lfNow) {
  // The time is the LFCLK count since an anchor, not the halted time plus this sleep: each sleep's time then
  // errs by less than one tick (30.5 us) without adding up. Adding up it did: the scans start at the same
  // 1 MHz offset from the previous wake, so the halt falls at the same phase of the LFCLK tick every time
  // and the truncation is the same each sleep (the twin: 61 us/s slow). A count since the anchor is found
  // from its low 16 bits (the counter) and the estimate by the 1 MHz clock, good to far better than the half
  // wrap (1 s) for up to kMaxAnchorUs. The anchor is moved on in steps of 512 ticks, exactly 15 625 us, at
  // the halt (so that it stays fresh however long the core was awake) and after the wake-up; only an anchor
  // older than kMaxAnchorUs at the halt (no deep sleep for that long) is replaced by this sleep's start,
  // and that sleep errs by up to a tick.
  if (halted.us - anchor.us > kMaxAnchorUs) anchor = {halted.us, lfAtHalt};
  const uint32_t sinceAnchor = ticksFor(halted.us - anchor.us);
  const uint32_t atHalt =
      sinceAnchor + static_cast<uint32_t>(static_cast<int16_t>(lfAtHalt - anchor.lf - sinceAnchor));
  anchor.lf = (anchor.lf + (atHalt & ~0x1FFU)) & 0xFFFF;
  anchor.us += (atHalt >> 9) * 15625U;
  const uint32_t ticks = (atHalt & 0x1FFU) + ((lfNow - lfAtHalt) & 0xFFFF);
  // The count's last edge came before the read: by tWAKE (15 us, SLASEX0D 7.8) when the compare woke the
  // core (the usual case), by half a tick (15.3 us) on average for any other wake-up.
  const fw::Instant now{anchor.us + ((ticks * 15625U) >> 9) + kWakeUs};
  const uint32_t blocks = ticks >> 9;
  anchor.lf = (anchor.lf + (blocks << 9)) & 0xFFFF;
  anchor.us += blocks * 15625U;
  return fw::isBefore(now, halted) ? halted : now;  // monotonic: the tick's rounding never steps back
}

}  // namespace bsp::mspm0
