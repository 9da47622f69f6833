// Deterministic instruction counts of the scheduler's hot paths on ARMv6-M, built with an image's definitions
// (tests/qemu/CMakeLists.txt): the scheduler the images ship.
//
// Instructions are counted with SysTick under -icount (insn_counter.hpp). Each path is repeated kIterations
// times and the loop's own overhead (measured with an empty body) is subtracted, giving the instructions per
// operation to within 0.01 (exception entry/exit is hardware, not instructions, and is not counted; on a real
// M0+ it adds 15 + 11 cycles).
//   post_isr_dispatch:  NVIC set-pending, the handler posting an event, and dispatchOne() running the task
//   timer_dispatch:     startTimer() of an already-due one-shot, and dispatchOne() firing it and running
//                       the task
//   post_dispatch:      a thread-mode post() and dispatchOne()
// Output lines start with REPORT so ./ci/test can collect them.
#include <cstdint>

#include "insn_counter.hpp"
#include "qtest.hpp"
#include "sched/scheduler.hpp"
#include "scs.hpp"

namespace {

constexpr unsigned kIrq = 25;
constexpr uint32_t kIterations = 10000;
fw::sched::Scheduler* gSched = nullptr;

struct Empty final : fw::sched::Task {
  uint32_t runs = 0;
  void run(fw::sched::EventMask) override { ++runs; }
};

// A clock that counts its reads (outside the measured loops).
struct CountingClock final : fw::hal::Clock {
  mutable uint32_t reads = 0;
  fw::Instant doNow() const override {
    ++reads;
    return fw::Instant{0};
  }
  void doWakeAt(fw::Instant) override {}
};

// A clock that costs nothing: keeps the measurement about the scheduler, not the clock driver.
struct ZeroClock final : fw::hal::Clock {
  uint32_t t = 0;
  fw::Instant doNow() const override { return fw::Instant{t}; }
  void doWakeAt(fw::Instant) override {}
};

qbench::InsnCounter gCounter;

uint32_t centiInsnPerIteration(uint64_t counts) {
  return qbench::InsnCounter::centiInsnPer(counts, kIterations);
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

  // Built as the images build it (no run-time figures), a dispatch with no timer armed reads no clock.
  static CountingClock counting;
  static fw::sched::Scheduler counted(counting);
  static Empty other;
  counted.addTask(1, other);
  counted.post(1, 0x1);
  QCHECK(counted.dispatchOne());
  QCHECK(counting.reads == 0);
  QCHECK(isrDispatch > empty && postDispatch > empty && timerDispatch > empty);
  qbench::reportCenti("sched.post_isr_dispatch_insns", centiInsnPerIteration(isrDispatch - empty));
  qbench::reportCenti("sched.post_dispatch_insns", centiInsnPerIteration(postDispatch - empty));
  qbench::reportCenti("sched.timer_dispatch_insns", centiInsnPerIteration(timerDispatch - empty));
  return qtest::finish("qemu_sched_bench");
}
