#include "timg_clock.hpp"

#include <atomic>

#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/timg.hpp"

namespace bsp::mspm0 {

namespace timg = reg::timg;

namespace {
// An alarm further away than a quarter period could alias with the 16-bit compare; leave it to the
// half-period wake-up instead.
constexpr int32_t kMaxAlarmUs = 0x4000;
}  // namespace

fw::Instant TimgClock::doNow() const {
  const uint32_t halves = halves_;
  std::atomic_signal_fence(std::memory_order_acquire);  // read the count before the counter
  return fw::Instant{widen(halves, timg::counter(config_.base).ctr.read())};
}

void TimgClock::doWakeAt(fw::Instant deadline) {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  if (static_cast<int32_t>(deadline.us - doNow().us) > kMaxAlarmUs) {
    mmio::clearBits(events.imask, timg::kIntCcu0);
    return;
  }
  timg::counter(config_.base).cc[0].write(deadline.us & 0xFFFF);
  events.iclr.write(timg::kIntCcu0);
  mmio::setBits(events.imask, timg::kIntCcu0);
  // The compare fires only when the counter equals CC0; if it passed CC0 while we were arming, the event is
  // gone. Re-check and pend the interrupt ourselves (embassy-mspm0 set_alarm does the same).
  if (fw::isDue(deadline, doNow())) events.iset.write(timg::kIntCcu0);
}

void TimgClock::onInterrupt() {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  const uint32_t pending = events.mis.read();
  events.iclr.write(pending);
  uint32_t halves = halves_;
  if (pending & timg::kIntLoad) ++halves;
  if (pending & timg::kIntCcu1) ++halves;
  halves_ = halves;
  if (pending & timg::kIntCcu0) mmio::clearBits(events.imask, timg::kIntCcu0);  // one-shot alarm
}

}  // namespace bsp::mspm0
