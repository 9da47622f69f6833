// What the protection task tells the publishers about the pack's state (PackSummary / ProtectionEvent).
#pragma once

#include <cstdint>

#include "app/config.hpp"
#include "app/protection/protection.hpp"

namespace fw::app {

// The native messages a build sends (FW_PUBLISH_LEVEL, app/config.hpp); a message left out never comes up
// in a cycle.
inline constexpr bool kAllMessages = FW_PUBLISH_LEVEL >= 2;
inline constexpr bool kCoreMessages = FW_PUBLISH_LEVEL >= 1;  // ProtectionEvent and CellVoltages

struct PublishStatus {
  FaultMask active = 0;
  FaultMask pendingTripped = 0;  // tripped since the last ProtectionEvent frame
  FaultMask pendingCleared = 0;  // cleared since the last ProtectionEvent frame
  // The paths as confirmed (protection_task.hpp): on FET images the device's FET read-back of the last fresh
  // scan, on fault-output images the pin. Meaningful only while pathsKnown; CAN sends them not available
  // otherwise.
  bool chargeOn = false;  // the charge path is enabled (FET on / fault output released)
  bool dischargeOn = false;
  bool pathsKnown = false;
  bool faultOutput = false;
};

}  // namespace fw::app
