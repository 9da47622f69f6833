// What the protection task tells the publishers about the pack's state (PackSummary / ProtectionEvent).
#pragma once

#include <cstdint>

#include "app/protection.hpp"

namespace fw::app {

struct PublishStatus {
  FaultMask active = 0;
  FaultMask pendingTripped = 0;  // tripped since the last ProtectionEvent frame
  FaultMask pendingCleared = 0;  // cleared since the last ProtectionEvent frame
  bool chargeOn = false;         // the charge path is enabled (FET on / fault output released)
  bool dischargeOn = false;
  bool faultOutput = false;
  uint16_t commErrors = 0;  // failed monitor transactions, saturating
};

}  // namespace fw::app
