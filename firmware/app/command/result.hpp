// Result: what a command came to, as CommandAck.Result carries it (firmware/app/can/bms.yaml). The handler
// answers it, and LimitSettings::write() returns it, so a write's outcome is the answer as it stands.
#pragma once

#include <cstdint>

namespace fw::app::command {

enum class Result : uint8_t {
  Accepted = 0,
  BadCrc,
  RepeatedCounter,
  WrongLength,
  OutOfRange,
  Inconsistent,
  Unsupported,
  WrongKey,
  PathsNotOff,
  Busy,
  ConditionPresent,
  FaultActive,  // StorageMode enter: a protection fault is active or the device holds a path off
  NotAtRest,    // StorageMode enter: the current is above the pack's rest threshold
};
inline constexpr uint8_t kResultCount = 13;

}  // namespace fw::app::command
