// The tasks of every image, by priority (TaskId: a higher id runs first), and the command task's events.
//
//   3 protection   firmware limits, the fault line, host requests (app/protection)
//   2 monitor      the battery monitor's set-up and scans (app/monitors)
//   1 publisher    CAN frames or SLCAN lines, and the command task's answers (app/publish)
//   0 command      received commands (app/command): the lowest, so a flood of commands waits for every other
//                  task and never delays protection, a scan or the published messages
#pragma once

#include "app/config.hpp"
#include "sched/task.hpp"

namespace fw::app {

inline constexpr sched::TaskId kCommandTask = 0;
inline constexpr sched::TaskId kPublisherTask = 1;
inline constexpr sched::TaskId kMonitorTask = 2;
inline constexpr sched::TaskId kProtectionTask = 3;

namespace command_event {
inline constexpr sched::EventMask kInput = 0x1;       // the bus or line has received something
inline constexpr sched::EventMask kOutboxFree = 0x2;  // the publisher has sent the last answers
inline constexpr sched::EventMask kTimer = 0x4;       // bootloader entry: check the paths / the answer left
inline constexpr sched::EventMask kStore = 0x8;       // the record store has a flash job (BackgroundWork)
}  // namespace command_event

// Work the lowest-priority task does for another part on command_event::kStore (app/store/persistence.hpp:
// flash writes and erases, which must wait for everything else). One bounded job per call.
class BackgroundWork {
 public:
  virtual void step() = 0;
  // Just before a commanded reset (bootloader entry, the paths off): what must not be lost, written now.
  virtual void beforeReset() = 0;

 protected:
  ~BackgroundWork() = default;
};

// Where a task keeps the record store's hook (a BackgroundWork, a TripObserver): a pointer where the store
// is built (FW_RECORD_STORE), no member at all otherwise (the L1306 images pay nothing for it). No default
// member initializer: it lives in zero-initialised blocks too (value-initialise it elsewhere: `{}`).
template <class T, bool kBuilt = FW_RECORD_STORE != 0>
struct StoreHook {
  T* to;
  void set(T& t) { to = &t; }
};
template <class T>
struct StoreHook<T, false> {
  static constexpr T* to = nullptr;
  void set(T&) {}
};

}  // namespace fw::app
