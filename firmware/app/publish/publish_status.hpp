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

// What the Startup message carries, once after a reset (bms.yaml Startup): the image fills it from its BSP's
// start-up report (bsp/mspm0/fault.hpp takeStartupReport) and hands it to FramePlan::announceStartup().
struct StartupInfo {
  uint8_t resetCause = 0;   // SYSCTL RSTCAUSE.ID (0: none since it was last read)
  bool faultValid = false;  // a fault record of the previous run survived the reset
  uint8_t faultModule = 0;  // fw::Module of that record
  uint16_t faultLine = 0;   // its line or code
};

}  // namespace fw::app
