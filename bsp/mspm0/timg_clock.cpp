#include "timg_clock.hpp"

#include <atomic>

#include "hal/irq.hpp"
#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"

namespace bsp::mspm0 {

namespace timg = reg::timg;

namespace {
// How far ahead CC0 is armed. In up-counting with LOAD = 0xFFFF the counter takes every value once per wrap
// and CCU0 is set when it becomes CC0 (SLAU846B / SLAU847D TIMx "counter compare": compare event on CCR
// match while counting up; hw_gptimer.h CPU_INT CCU0), so a target less than one wrap (65 536 us) ahead
// fires exactly when due. A deadline further away is reached in steps: CC0 is armed this far ahead, the
// wake-up runs the scheduler's idle loop, which calls wakeAt() again with the same absolute deadline, and
// the remainder is computed afresh from now(). The 4 096 us left below a wrap cover the time from reading
// the counter to writing CC0 (interrupts are masked: a few cycles), so an intermediate target can never be
// behind the counter when armed and alias to the next wrap.
//
// (Before: deadlines more than 0x4000 us away were not armed at all and waited for the next half-period
// event, up to 32.8 ms later: up to 16.4 ms late, the twin's 98.3 .. 116.1 ms publish periods.)
constexpr int32_t kMaxAlarmUs = 0xF000;
}  // namespace

fw::Instant TimgClock::doNow() const {
  const uint32_t halves = halves_;
  std::atomic_signal_fence(std::memory_order_acquire);  // read the count before the counter
  return fw::Instant{widen(halves, timg::counter(config_.base).ctr.read())};
}

void TimgClock::doWakeAt(fw::Instant deadline) {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  timg::Counter& counter = timg::counter(config_.base);
  const uint32_t now = doNow().us;
  if (static_cast<int32_t>(deadline.us - now) > kMaxAlarmUs) deadline = fw::Instant{now + kMaxAlarmUs};
  counter.cc[0].write(deadline.us & 0xFFFF);
  events.iclr.write(timg::kIntCcu0);
  mmio::setBits(events.imask, timg::kIntCcu0);
  // The compare fires only when the counter equals CC0; if it passed CC0 while we were arming, the event is
  // gone. Re-check and pend the interrupt ourselves (embassy-mspm0 set_alarm does the same).
  if (fw::isDue(deadline, doNow())) events.iset.write(timg::kIntCcu0);
}

fw::Instant TimgClock::halt() {
  mmio::clearBits(timg::counter(config_.base).ctrctl, timg::kCtrEnable);
  // Read after the stop: the counter holds its value, and widen() accounts for a half-period event that is
  // pending but not counted yet.
  return doNow();
}

void TimgClock::resume(fw::Instant at, bool timed, fw::Instant deadline) {
  timg::Counter& counter = timg::counter(config_.base);
  // A half-period event of before the stop would be counted again on top of the new count: drop it (a
  // handler that still runs for its NVIC request finds MIS 0 and counts nothing).
  reg::cpuInt(config_.base).iclr.write(timg::kIntLoad | timg::kIntCcu1);
  halves_ = at.us >> 15;  // bit 0 of the half count and bit 15 of the counter name the same half (widen())
  counter.ctr.write(at.us & 0xFFFF);
  // CVAE NOCHANGE: the count goes on from the CTR just written (hw_gptimer.h CTRCTL.CVAE_NOCHANGE; the
  // start-up's ZEROVAL would clear it).
  counter.ctrctl.write(timg::kCtrEnable | timg::kCtrRepeat | timg::kCtrCountUp | timg::kCtrKeepValue);
  if (timed) wakeAt(deadline);
}

void TimgClock::onInterrupt() {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  const uint32_t pending = events.mis.read();
  events.iclr.write(pending);
  uint32_t halves = halves_;
  if (pending & timg::kIntLoad) ++halves;
  if (pending & timg::kIntCcu1) ++halves;
  halves_ = halves;
  if (pending & timg::kIntCcu0) {
    mmio::clearBits(events.imask, timg::kIntCcu0);  // one-shot alarm
    wakeFired();
    fw::port::resumeOnExit();  // a timer may be due: the Thread looks (the counts alone let it sleep)
  }
}

}  // namespace bsp::mspm0
