// Deterministic instruction counts of the scheduler's hot paths on ARMv6-M.
//
// QEMU runs with -icount shift=0: virtual time advances exactly 1 ns per executed instruction, and SysTick
// counts that virtual time at 16 MHz, so one SysTick count is 62.5 instructions. Each path is repeated
// kIterations times and the loop's own overhead (measured with an empty body) is subtracted, giving the
// instructions per operation to within 0.01 (exception entry/exit is hardware, not instructions, and is not
// counted; on a real M0+ it adds 15 + 11 cycles).
//   post_isr_dispatch:  NVIC set-pending, the handler posting an event, and dispatchOne() running the task
//   timer_dispatch:     startTimer() of an already-due one-shot, and dispatchOne() firing it and running
//                       the task
//   post_dispatch:      a thread-mode post() and dispatchOne()
// Output lines start with REPORT so ./ci/test can collect them.
#include <cstdint>

#include "qtest.hpp"
#include "sched/scheduler.hpp"
#include "scs.hpp"
#include "systick_clock.hpp"

namespace {

constexpr unsigned kIrq = 25;
constexpr uint32_t kIterations = 10000;
constexpr uint32_t kReload = 0xFFFFFF;
fw::sched::Scheduler* gSched = nullptr;

struct Empty final : fw::sched::Task {
  uint32_t runs = 0;
  void run(fw::sched::EventMask) override { ++runs; }
};

// A free-running SysTick without interrupts: counts are read directly. The measured loops are far shorter
// than one 24-bit wrap (16.7 M instructions), and wraps are detected with COUNTFLAG anyway.
struct Counter {
  uint64_t total = 0;
  uint32_t last = kReload;
  void start() {
    using bsp::scs::reg;
    reg(bsp::scs::kSystCsr) = 0;
    reg(bsp::scs::kSystRvr) = kReload;
    reg(bsp::scs::kSystCvr) = 0;
    reg(bsp::scs::kSystCsr) = 0x5;  // CPU clock, enabled, no interrupt
    last = reg(bsp::scs::kSystCvr);
    total = 0;
  }
  uint64_t read() {
    using bsp::scs::reg;
    const uint32_t now = reg(bsp::scs::kSystCvr);
    total += (now <= last) ? (last - now) : (last + (kReload + 1) - now);
    last = now;
    return total;
  }
};

// A clock that costs nothing: keeps the measurement about the scheduler, not the clock driver.
struct ZeroClock final : fw::hal::Clock {
  uint32_t t = 0;
  fw::Instant doNow() const override { return fw::Instant{t}; }
  void doWakeAt(fw::Instant) override {}
};

Counter gCounter;

// instructions x 100 per iteration, from SysTick counts (62.5 instructions each).
uint32_t centiInsnPerIteration(uint64_t counts) {
  return static_cast<uint32_t>((counts * 6250) / kIterations);
}

void report(const char* name, uint32_t centi) {
  bsp::qemu::print("REPORT sched.");
  bsp::qemu::print(name);
  bsp::qemu::print("_insns=");
  bsp::qemu::printUnsigned(centi / 100);
  bsp::qemu::print(".");
  bsp::qemu::printUnsigned((centi % 100) / 10);
  bsp::qemu::print("\n");
}

}  // namespace

extern "C" void Irq25_Handler() {
  gSched->post(1, 0x1);
}

__attribute__((noinline)) uint64_t measureEmpty() {
  const uint64_t start = gCounter.read();
  for (uint32_t i = 0; i < kIterations; ++i)
    __asm volatile("" ::: "memory");
  return gCounter.read() - start;
}

int main() {
  static ZeroClock clock;
  static fw::sched::Scheduler sched(clock);
  gSched = &sched;
  static Empty task;
  sched.addTask(1, task);
  bsp::scs::nvicEnable(kIrq);
  gCounter.start();

  const uint64_t empty = measureEmpty();

  uint64_t start = gCounter.read();
  for (uint32_t i = 0; i < kIterations; ++i) {
    bsp::scs::nvicSetPending(kIrq);
    sched.dispatchOne();
  }
  const uint64_t isrDispatch = gCounter.read() - start;

  start = gCounter.read();
  for (uint32_t i = 0; i < kIterations; ++i) {
    sched.post(1, 0x1);
    sched.dispatchOne();
  }
  const uint64_t postDispatch = gCounter.read() - start;

  static fw::sched::Timer timer;
  start = gCounter.read();
  for (uint32_t i = 0; i < kIterations; ++i) {
    sched.startTimer(timer, 1, 0x1, fw::us(0));
    sched.dispatchOne();
  }
  const uint64_t timerDispatch = gCounter.read() - start;

  QCHECK(task.runs == 3 * kIterations);
  QCHECK(isrDispatch > empty && postDispatch > empty && timerDispatch > empty);
  report("post_isr_dispatch", centiInsnPerIteration(isrDispatch - empty));
  report("post_dispatch", centiInsnPerIteration(postDispatch - empty));
  report("timer_dispatch", centiInsnPerIteration(timerDispatch - empty));
  return qtest::finish("qemu_sched_bench");
}
