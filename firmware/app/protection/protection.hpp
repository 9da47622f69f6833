// Protection: the firmware's limits, layered above the battery monitor's own hardware protection.
//
// The device's protections (BQ769x2 COV/CUV/OCD/SCD..., BQ79616 OV/UV comparators, BQ4050 SafetyStatus) are
// primary and act on their own. This layer adds the pack designer's limits on top, with the same discipline
// for every fault:
//   - a trip threshold and a clear threshold (hysteresis): a fault clears only once the value is back past
//     the clear threshold, never by hovering at the trip point;
//   - a debounce count: the condition must be seen in that many consecutive evaluations of fresh data;
//   - a delay: and it must have been present for at least that long (first sighting to now);
//   - the same count and delay on the way back (recovery is debounced too);
//   - latching: a latched fault stays tripped until clearLatched() (a user action), even when the value
//     recovers;
//   - an action: which FETs open (charge, discharge or both) or, on images without FETs, the fault output.
// Stale data and lost communication are faults like any other: the evaluation knows when the last valid
// measurement was taken and how many scans in a row failed. Missing data never clears a fault: value rules
// are only evaluated on fresh, validated samples. An open sense wire (PackTotals::openWire: seen in the
// readings, or reported by the monitor) is a fault of its own: the cells beside it are left out of the cell
// limits, so the fault stands in for them.
//
// Delays are built unless FW_PROTECTION_DELAYS is 0 (the L1306 images, whose limits use none: see
// default_limits.hpp); a build without them has no Rule::delay and trips on the debounce count alone.
//
// Units are integers: cell voltages in mV, current in mA (positive = charging), temperatures in 0.1 K.
// Contract: thread mode only (the protection task); no allocation; evaluate() is O(cells + temps).
#pragma once

#include <cstdint>
#include <span>

#include "app/config.hpp"
#include "app/pack/pack_view.hpp"
#include "core/time.hpp"
#include "core/zeroed.hpp"

namespace fw::app {

inline constexpr bool kProtectionDelays = FW_PROTECTION_DELAYS != 0;

enum class FaultId : uint8_t {
  CellOvervoltage,
  CellUndervoltage,
  ChargeOvercurrent,
  DischargeOvercurrent,
  Overtemperature,
  Undertemperature,
  DeviceSafety,   // the battery monitor reports a tripped protection of its own
  StaleData,      // no valid measurement for longer than staleAfter
  CommLoss,       // commLossScans scan attempts in a row failed
  OpenWire,       // a sense wire is open: the readings of the cells beside it are not cell voltages
  CommErrorRate,  // of the last rateWindow scan attempts, at least the rule's trip count failed
};
inline constexpr uint8_t kFaultCount = 11;
using FaultMask = uint16_t;
constexpr FaultMask bit(FaultId id) {
  return static_cast<FaultMask>(1U << static_cast<uint8_t>(id));
}

// Names for tools and logs ("cell_ov", "comm_loss", ...). Host/QEMU text only; not needed by the images.
const char* faultName(FaultId id);

enum class Action : uint8_t {
  None = 0,
  ChargeOff = 1,
  DischargeOff = 2,
  AllOff = 3,
};

// 16 bytes (12 without delays), largest members first (the limit table is nine of these in flash).
struct Rule {
  int32_t trip = 0;   // condition present when value >= trip (upper limits) or <= trip (lower limits)
  int32_t clear = 0;  // condition gone when value < clear (upper) or > clear (lower)
#if FW_PROTECTION_DELAYS
  Duration delay{};
#endif
  uint8_t debounce = 1;
  Action action = Action::AllOff;
  bool latch = false;
  bool enabled = false;
};

struct ProtectionConfig {
  Rule rules[kFaultCount];  // indexed by FaultId; upper limits: Ov, ChargeOc, Ot; lower: Uv, DischargeOc, Ut
  Duration staleAfter = ms(1000);
  uint8_t commLossScans = 3;
  // The scan attempts CommErrorRate counts failures over (1..16): an intermittent link that fails scans
  // without failing commLossScans of them in a row still trips it.
  uint8_t rateWindow = 10;
};

// One evaluation's inputs. Value limits are evaluated only when `fresh` (a scan just validated) and only over
// the boards whose status is Valid; the freshness rules look at every board of `pack` on every evaluation.
struct ProtectionInputs {
  const PackView* pack = nullptr;  // the measured pack (required; all zero before the first scan)
  bool fresh = false;              // a scan just completed and the device answered (what validated: `pack`)
  bool scanFailed = false;         // a scan attempt just failed (with `fresh`: some board of it did)
  bool faultLine = false;          // ALERT / nFAULT is asserted: the monitor signals a fault of its own
};

struct ProtectionState {
  FaultMask active = 0;        // tripped now
  FaultMask newlyTripped = 0;  // tripped in this evaluation
  FaultMask newlyCleared = 0;  // cleared in this evaluation
  bool chargeOff = false;      // union of the actions of every active fault
  bool dischargeOff = false;
  bool faultOutput() const { return active != 0; }
};

class Protection {
 public:
  explicit Protection(const ProtectionConfig& config) : config_(config) {}

  ProtectionState evaluate(const ProtectionInputs& in, Instant now);
  // Clears latched faults whose condition is gone (a user action: button or CAN command). Returns the faults
  // that cleared; a latched fault whose condition is still present stays.
  FaultMask clearLatched();

  FaultMask active() const { return state_->active; }
  const ProtectionConfig& config() const { return config_; }
  Instant trippedAt(FaultId id) const { return state_->tripped[static_cast<uint8_t>(id)]; }

 private:
  // Moves rule `i`'s debounce with its value `v` (out of line: the loop around it stays in registers).
  void track(uint8_t i, int32_t v, Instant now, ProtectionState& out);

  // Everything that changes, zero at construction (one block: no per-member start-up code).
  struct State {
    FaultMask active;
    FaultMask conditionNow;  // last evaluation's raw conditions (for clearLatched)
    uint8_t failedScans;
    uint16_t attempts;  // the latest scan attempts, newest in bit 0: 1 = it failed (CommErrorRate)
    // Per fault: consecutive evaluations the condition (or, when tripped, its absence) was seen, and when
    // that run started (for the delay).
    uint8_t count[kFaultCount];
#if FW_PROTECTION_DELAYS
    Instant since[kFaultCount];
#endif
    Instant tripped[kFaultCount];
  };
  const ProtectionConfig& config_;
  Zeroed<State> state_;
};

}  // namespace fw::app
