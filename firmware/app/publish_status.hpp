// What the protection task tells the publishers about the pack's state (PackSummary / ProtectionEvent).
#pragma once

#include <cstdint>

#include "app/protection.hpp"

#ifndef FW_PUBLISH_LEVEL
#define FW_PUBLISH_LEVEL 2
#endif

namespace fw::app {

// The native messages a build sends (FW_PUBLISH_LEVEL): 2, the default (the host, bms-sim and the G3507
// images), every one; 1, PackSummary, ProtectionEvent and CellVoltages (no CellExtremes, Temperatures or
// TemperatureExtremes); 0, PackSummary alone. Images whose flash budget has no room for the others (the
// L1306) build with less; a message left out never comes up in a cycle.
static_assert(FW_PUBLISH_LEVEL >= 0 && FW_PUBLISH_LEVEL <= 2);
inline constexpr bool kAllMessages = FW_PUBLISH_LEVEL >= 2;
inline constexpr bool kCoreMessages = FW_PUBLISH_LEVEL >= 1;  // ProtectionEvent and CellVoltages

struct PublishStatus {
  FaultMask active = 0;
  FaultMask pendingTripped = 0;  // tripped since the last ProtectionEvent frame
  FaultMask pendingCleared = 0;  // cleared since the last ProtectionEvent frame
  bool chargeOn = false;         // the charge path is enabled (FET on / fault output released)
  bool dischargeOn = false;
  bool faultOutput = false;
};

}  // namespace fw::app
