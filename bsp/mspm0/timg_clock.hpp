// TimgClock: the firmware clock (fw::hal::Clock) on a 16-bit TIMG timer counting microseconds.
//
// The timer counts up 0..0xFFFF at 1 MHz (bus clock / prescaler). Software widens it to 32 bits by counting
// half-periods: the load event (counter = 0xFFFF) and the CC1 compare event (counter = 0x8000) each add one,
// so bit 15 of the counter and bit 0 of the half count always describe the same half (embassy-mspm0's
// time driver uses the same two-events-per-wrap scheme). now() is correct as long as the interrupt is not
// held off for more than a quarter period (16 ms).
//
// Contract
// - now(): any context, including ISRs and with interrupts masked. Monotonic; microseconds; wraps at 2^32.
// - wakeAt(deadline): called by the scheduler with interrupts masked. Arms CC0 for `deadline`, or for an
//   intermediate wake-up 61.4 ms ahead when the deadline is further (the scheduler then calls wakeAt() again
//   and the remainder is armed): the CPU wakes within 1 us of the deadline whatever its distance. Right after
//   arming it re-reads now(); if the armed time has already passed it pends the interrupt with ISET, so the
//   wake-up is never lost.
// - wakeArmed() (hal::Clock): cleared by onInterrupt() when CCU0 fires; an intermediate alarm of a far
//   deadline fires before the deadline, never after.
// - halt() / resume(at): for a deep sleep (power_policy.hpp), interrupts masked, in that order. halt() stops
//   the 1 MHz count (CTRCTL.EN 0: no BUSCLK deadline stays armed in STOP or STANDBY, where BUSCLK stops) and
//   returns the time it stopped at; now() returns that time until resume(). resume(at) drops the half-period
//   events of before, restarts the count at `at` (the time the sleep lasted added by the caller) and re-arms
//   the wake-up for `deadline` if `timed` (wakeAt(): an intermediate target the sleep went past, or a
//   deadline now due, is armed afresh or pended).
// - onInterrupt(): body of the timer's IRQ handler. Reads MIS, clears exactly those bits, counts
//   half-periods, disarms a fired alarm and resumes the Thread for it (fw::port::resumeOnExit: the scheduler
//   re-checks its timers); the half-period counts alone let the core sleep on.
#pragma once

#include <cstdint>

#include "hal/clock.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"

namespace bsp::mspm0 {

class TimgClock final : public fw::hal::Clock {
 public:
  struct Config {
    uintptr_t base = 0;
    uint8_t irq = 0;
    uint8_t prescaler = 31;  // CPS.PCNT for a 1 MHz count from BUSCLK: reg::timg::prescalerFor1MHz(32 MHz)
  };

  constexpr explicit TimgClock(const Config& config) : config_(config) {}

  // Powers and starts the timer and enables its interrupt in the NVIC. Thread mode, once. The static form
  // is inline: a board that passes its constant configuration gets constant register writes.
  void start() const { start(config_); }
  static void start(const Config& config) {
    namespace timg = reg::timg;
    const uintptr_t base = config.base;
    timg::powerUpClock(base, config.prescaler);  // 1 MHz counter clock
    timg::Counter& counter = timg::counter(base);
    counter.load.write(0xFFFF);
    counter.ccctl[0].write(0);  // compare mode, immediate update
    counter.ccctl[1].write(0);
    counter.cc[1].write(kHalf);
    reg::EventBlock& events = reg::cpuInt(base);
    events.iclr.write(0xFFFFFFFF);
    events.imask.write(timg::kIntLoad | timg::kIntCcu1);
    // CLC/CAC/CZC are written as 0: their reset value (7) is reserved and stops some instances counting.
    counter.ctrctl.write(timg::kCtrEnable | timg::kCtrRepeat | timg::kCtrCountUp | timg::kCtrStartAtZero);
    nvic::enable(config.irq);
  }
  void onInterrupt();
  fw::Instant halt();
  void resume(fw::Instant at, bool timed, fw::Instant deadline);

  // Combines a half-period count and a raw counter value into microseconds (exposed for tests).
  static uint32_t widen(uint32_t halves, uint32_t counter) {
    // Bit 15 of the counter says which half the counter is in; the parity of `halves` says which half the
    // software has seen. When they disagree the event is either pending (counter just entered the next half,
    // low bits small) or was taken a tick early (counter still at the end of the half, low bits large).
    counter &= 0xFFFF;
    if ((counter >> 15) != (halves & 1U)) halves += (counter & 0x7FFF) < 0x4000 ? 1U : ~0U;
    return (halves << 15) | (counter & 0x7FFF);
  }

 private:
  static constexpr uint32_t kHalf = 0x8000;  // CC1: the counter's mid-point, the second half-period event

  fw::Instant doNow() const override;
  void doWakeAt(fw::Instant deadline) override;

  Config config_;
  volatile uint32_t halves_ = 0;  // written by onInterrupt only
};

}  // namespace bsp::mspm0
