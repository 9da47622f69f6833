// What the protection task tells the publishers about the pack's state (PackSummary / ProtectionEvent).
#pragma once

#include <cstdint>
#include <type_traits>

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
// Where the fault in faultModule / faultLine comes from (bms.yaml Startup.FaultSource).
enum class FaultSource : uint8_t {
  None = 0,          // no fault record, in SRAM or in flash
  LastReset = 1,     // the fault that caused this reset (SRAM record or watchdog expiry), now in flash
  Stored = 2,        // no fault caused this reset: the newest fault record an earlier run left in flash
  NotAvailable = 3,  // the image keeps no records in flash: faultValid says whether SRAM kept one
};

// What the record store restored (app/store/persistence.hpp): a member of StartupInfo only where the store
// is built (FW_RECORD_STORE); elsewhere an empty one whose values are fixed at not available.
struct KeptRecordsInfo {
  static constexpr uint8_t kNotAvailable = 15;  // logEntries when the store restored nothing
  uint8_t logEntries = kNotAvailable;           // protection-log entries restored from flash
  FaultSource faultSource = FaultSource::NotAvailable;
};
struct NoKeptRecordsInfo {
  static constexpr uint8_t logEntries = KeptRecordsInfo::kNotAvailable;
  static constexpr FaultSource faultSource = FaultSource::NotAvailable;
};

struct StartupInfo {
  uint8_t resetCause = 0;   // SYSCTL RSTCAUSE.ID (0: none since it was last read)
  bool faultValid = false;  // a fault record of the previous run survived the reset (or kept.faultSource)
  uint8_t faultModule = 0;  // fw::Module of that record
  uint16_t faultLine = 0;   // its line or code
  [[no_unique_address]] std::conditional_t<FW_RECORD_STORE != 0, KeptRecordsInfo, NoKeptRecordsInfo> kept{};
};

}  // namespace fw::app
