#include "sim/harness.hpp"

#include <cstdio>
#include <cstdlib>

namespace bsp::host {

namespace {
SimIrq& freshIrq() {
  simIrq().reset();
  return simIrq();
}
}  // namespace

Harness::Harness() : irq(freshIrq()), clock(irq), trace(clock), sched(clock) {
  sched.setTraceSink(&trace);
}

Harness::~Harness() {
  simIrq().reset();
}

size_t Harness::runUntilIdle(size_t maxRuns, uint64_t stopAtUs) {
  size_t runs = 0;
  for (;;) {
    if (clock.nowUs() > stopAtUs) return runs;
    if (!sched.dispatchOne()) break;
    if (++runs > maxRuns) {
      std::fprintf(stderr, "Harness: more than %zu task runs without going idle (livelock?)\n", maxRuns);
      std::abort();
    }
  }
  sched.idle();
  return runs;
}

bool Harness::runUntil(const std::function<bool()>& done, fw::Duration limit) {
  const uint64_t end = clock.nowUs() + limit.us;
  for (;;) {
    runUntilIdle(1000000, end);
    if (done && done()) return true;
    if (clock.nowUs() >= end) break;
    uint64_t next = 0;
    if (!clock.nextEvent(next) || next > end) break;
    clock.advanceTo(next);
  }
  clock.advanceTo(end);
  runUntilIdle(1000000, end);
  return done && done();
}

void Harness::runFor(fw::Duration d) {
  runUntil(nullptr, d);
}

void Harness::runBefore(fw::Duration d) {
  const uint64_t end = clock.nowUs() + d.us;
  for (;;) {
    runUntilIdle(1000000, end);
    uint64_t next = 0;
    if (!clock.nextEvent(next) || next >= end) break;
    clock.advanceTo(next);
  }
  clock.advanceBefore(end);
  runUntilIdle(1000000, end);
}

}  // namespace bsp::host
