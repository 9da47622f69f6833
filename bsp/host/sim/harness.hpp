// Harness: one simulated MCU for a host test or tool: interrupt controller, virtual clock, scheduler and
// trace recorder, plus the loop that stands in for Scheduler::run().
//
// runUntilIdle() dispatches until nothing is ready, then lets the scheduler go idle once (recorded as
// "idle"). runFor(d) alternates runUntilIdle() with advancing virtual time to the next event (device
// completions, timer alarms) until d has passed. runUntil(pred, limit) stops early when pred() holds after a
// step. Only one Harness may exist at a time (the interrupt controller is per process).
#pragma once

#include <cstddef>
#include <functional>

#include "core/time.hpp"
#include "sched/scheduler.hpp"
#include "sim/sim_clock.hpp"
#include "sim/sim_irq.hpp"
#include "sim/trace_recorder.hpp"

namespace bsp::host {

class Harness {
 public:
  Harness();
  ~Harness();
  Harness(const Harness&) = delete;
  Harness& operator=(const Harness&) = delete;

  // Dispatches until nothing is ready and then idles once. Stops early (without idling) once virtual time
  // passes `stopAtUs`, so a saturated CPU cannot hold the harness forever.
  size_t runUntilIdle(size_t maxRuns = 1000000, uint64_t stopAtUs = UINT64_MAX);
  void runFor(fw::Duration d);
  bool runUntil(const std::function<bool()>& done, fw::Duration limit);
  // runFor(d), except that what is due exactly at the end (a timer's deadline, a device event) is left for
  // the next run: a tool that changes the world between runs (bms-sim's scenario steps) then has its change
  // at instant t come before what the firmware does at t, as on the MSPM0 twin, where the firmware's tick
  // at t is a CPU wake-up after the step.
  void runBefore(fw::Duration d);
  uint64_t nowUs() const { return clock.nowUs(); }

  SimIrq& irq;
  SimClock clock;
  TraceRecorder trace;
  fw::sched::Scheduler sched;
};

}  // namespace bsp::host
