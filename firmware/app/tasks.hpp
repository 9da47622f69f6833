// The tasks of every image, by priority (TaskId: a higher id runs first), and the command task's events.
//
//   3 protection   firmware limits, the fault line, host requests (app/protection)
//   2 monitor      the battery monitor's set-up and scans (app/monitors)
//   1 publisher    CAN frames or SLCAN lines, and the command task's answers (app/publish)
//   0 command      received commands (app/command): the lowest, so a flood of commands waits for every other
//                  task and never delays protection, a scan or the published messages
#pragma once

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
}  // namespace command_event

}  // namespace fw::app
