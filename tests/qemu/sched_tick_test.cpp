// The scheduler on ARMv6-M with real SysTick interrupts and WFI idle: a tick posted from the SysTick handler
// wakes a task; between ticks the core sleeps; periodic software timers keep their phase on the SysTick
// clock.
#include <cstdint>

#include "qtest.hpp"
#include "sched/scheduler.hpp"
#include "systick_clock.hpp"

namespace {

constexpr fw::sched::TaskId kTickTask = 3;
constexpr fw::sched::TaskId kTimerTask = 1;

fw::sched::Scheduler* gSched = nullptr;

struct TickTask final : fw::sched::Task {
  uint32_t runs = 0;
  uint32_t lastTick = 0;
  bool monotonic = true;
  void run(fw::sched::EventMask events) override {
    if (events != 0x1) monotonic = false;
    const uint32_t tick = bsp::qemu::sysTickClock().ticks();
    if (tick <= lastTick && runs != 0) monotonic = false;
    lastTick = tick;
    ++runs;
  }
};

struct TimerTask final : fw::sched::Task {
  uint32_t runs = 0;
  fw::Instant first{};
  fw::Instant last{};
  void run(fw::sched::EventMask) override {
    last = bsp::qemu::sysTickClock().now();
    if (runs++ == 0) first = last;
  }
};

}  // namespace

int main() {
  auto& clock = bsp::qemu::sysTickClock();
  static fw::sched::Scheduler sched(clock);
  gSched = &sched;
  static TickTask tick;
  static TimerTask timed;
  sched.addTask(kTickTask, tick);
  sched.addTask(kTimerTask, timed);
  clock.setTickHook([] { gSched->post(kTickTask, 0x1); });  // the ISR only posts

  static fw::sched::Timer timer;
  clock.start(1000);  // 1 ms tick
  sched.startTimer(timer, kTimerTask, 0x1, fw::ms(5), fw::ms(5));

  uint32_t idles = 0;
  while (tick.runs < 100) {
    if (!sched.dispatchOne()) {
      sched.idle();
      ++idles;
    }
  }
  clock.stop();

  QCHECK(tick.runs == 100);
  QCHECK(tick.monotonic);
  QCHECK(idles >= 100);  // the core slept between ticks instead of spinning
  QCHECK(timed.runs >= 19 && timed.runs <= 20);
  // Drift-free on the real clock: the k-th run happens within one tick after 5 ms * k.
  const uint32_t span = timed.last.us - timed.first.us;
  QCHECK(span == (timed.runs - 1) * 5000 ||
         (span > (timed.runs - 1) * 5000 && span < (timed.runs - 1) * 5000 + 1000));
  bsp::qemu::print("ticks handled: ");
  bsp::qemu::printUnsigned(tick.runs);
  bsp::qemu::print(", idle sleeps: ");
  bsp::qemu::printUnsigned(idles);
  bsp::qemu::print("\n");
  return qtest::finish("qemu_sched_tick_test");
}
