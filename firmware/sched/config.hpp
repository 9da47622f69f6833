// Build options of the scheduler (firmware/sched): every option's default, meaning and dependencies. An image
// sets its values in bsp/mspm0/images/<preset>/options.cmake; the host build uses these defaults.
#pragma once

// Task slots (1..8: the ready set is one byte). The images run four tasks (protection, monitor, publisher,
// commands) and build 4, which saves RAM and the table search; the host tests use up to 8.
#ifndef FW_SCHED_MAX_TASKS
#define FW_SCHED_MAX_TASKS 8
#endif
static_assert(FW_SCHED_MAX_TASKS >= 1 && FW_SCHED_MAX_TASKS <= 8, "FW_SCHED_MAX_TASKS: 1..8");

// Run-time measurement (1): each task's worst run time, run count and overruns of its budget, at two extra
// clock reads per dispatch. 0 saves those reads and bytes: no image registers a task with a budget and
// nothing on the target reads the figures (stats().worstRun, runs and overruns stay 0; addTask() ignores
// `budget`).
#ifndef FW_SCHED_BUDGETS
#define FW_SCHED_BUDGETS 1
#endif

// Trace hook (sched/trace.hpp): 1 records every scheduling decision for the host tests (the host build sets
// it); 0 compiles the hook out (no code, no RAM).
#ifndef FW_SCHED_TRACE
#define FW_SCHED_TRACE 0
#endif

// The board's power policy at each idle (hal/power.hpp, Scheduler::setPowerPolicy): 1 builds the hook (the
// host tests; the images whose board has a policy); 0 saves its 40 B where the board has none: the idle
// always sleeps the plain way (WFI with sleep-on-exit) and setPowerPolicy() does not exist.
#ifndef FW_SCHED_POWER_POLICY
#define FW_SCHED_POWER_POLICY 1
#endif
