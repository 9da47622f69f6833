// Protection: the firmware's limits, layered above the battery monitor's own hardware protection.
//
// Each device protection (BQ769x2 COV/CUV/OCD/SCD..., BQ7690x COV/CUV/SCD, BQ79616 OV/UV comparators, BQ4050
// SafetyStatus) is configured outside the firmware limit it backs up (monitors/bq769x_settings.hpp), so the
// firmware acts first on every normal limit and the device is the backstop. Every fault has the same
// discipline:
//   - a trip threshold and a clear threshold (hysteresis): a fault clears only once the value is back past
//     the clear threshold, never by hovering at the trip point;
//   - a debounce count: the condition must be seen in that many consecutive evaluations of fresh data;
//   - a delay: and it must have been present for at least that long (first sighting to now);
//   - a recovery count: the value must be seen past the clear threshold in that many consecutive evaluations
//     (and for the delay) before the fault clears. A current fault's clear threshold lies on the other side
//     of zero, so it clears only while current flows the way that relieves it (TI's OCC/OCD recovery,
//     SLUUBY2B 5.2: a discharge current ends an over-current in charge, a charge current one in discharge);
//   - latching: a rule with latchTrips latches on the trip that brings its trip count to latchTrips (1: its
//     first trip). Each trip counts one; while the count is nonzero one trip is forgiven every tripDecayS
//     seconds, counted from the latest trip (TI's OCDL counter and its Counter Dec Delay, SLUUBY2B
//     Protections:OCDL). A latched fault stays tripped, whatever its recovery, until clearLatched() (a user
//     action: ClearFaults) finds its condition gone: the last fresh value past the clear threshold, for a
//     current limit no more than the clear threshold's magnitude flowing the tripped way (the current is
//     gone; the relieving current of the other way is not needed). The trip count survives the clear, so a
//     fault that comes back before it has been forgiven latches again on its next trip;
//   - an action: which path it opens, the one the fault endangers: over-voltage, charge over-current and
//     charge temperature limits the charge path; under-voltage, discharge over-current and discharge
//     temperature limits the discharge path; what leaves the measurement in doubt (stale data, lost
//     communication, an open sense wire) both. On images without FETs the fault output stands for both.
// The device's own protection is a fault too (DeviceSafety): it opens the paths the device's flags concern
// (PackView::deviceBlocks, bit by bit per device in the monitors), and both while only the fault line
// (ALERT/nFAULT) has spoken and no scan has said which flag it was.
// Stale data and lost communication are faults like any other: the evaluation knows when the last valid
// measurement was taken and how many scans in a row failed. Missing data never clears a fault: value rules
// are only evaluated on fresh, validated samples. An open sense wire (PackTotals::openWire: seen in the
// readings, or reported by the monitor) is a fault of its own: the cells beside it are left out of the cell
// limits, so the fault stands in for them.
//
// Delays are built unless FW_PROTECTION_DELAYS is 0 (the L1306 images, whose limits use none: see
// default_limits.hpp); a build without them has no Rule::delay and trips and clears on the counts alone.
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

// The value limits come first (their values line up with PackTotals::extreme, protection.cpp), the
// charge-side temperature limits last: the numbers are the bits of CAN ActiveFaults (bms.yaml), so they never
// move.
enum class FaultId : uint8_t {
  CellOvervoltage,       // cell_ov: highest cell
  CellUndervoltage,      // cell_uv: lowest cell
  ChargeOvercurrent,     // occ: pack current, charging
  DischargeOvercurrent,  // ocd: pack current, discharging
  OvertempDischarge,     // otd: highest temperature, the discharge limit
  UndertempDischarge,    // utd: lowest temperature, the discharge limit
  DeviceSafety,          // the battery monitor reports a protection of its own (alert or trip)
  StaleData,             // no valid measurement for longer than staleAfter
  CommLoss,              // commLossScans scan attempts in a row failed
  OpenWire,              // a sense wire is open: the readings of the cells beside it are not cell voltages
  OvertempCharge,        // otc: highest temperature, the charge limit (below otd)
  UndertempCharge,       // utc: lowest temperature, the charge limit (above utd)
  CommErrorRate,         // comm_rate: of the last rateWindow scan attempts, the rule's trip count failed
};
inline constexpr uint8_t kFaultCount = 13;
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

// 20 bytes (16 without delays), largest members first (the limit table is thirteen of these in flash).
struct Rule {
  int32_t trip = 0;   // condition present when value >= trip (upper limits) or <= trip (lower limits)
  int32_t clear = 0;  // condition gone when value < clear (upper) or > clear (lower)
#if FW_PROTECTION_DELAYS
  Duration delay{};  // the condition (and, tripped, its absence) must last this long
#endif
  uint8_t debounce = 1;            // evaluations in a row with the condition present before it trips
  uint8_t recover = 1;             // evaluations in a row with the condition gone before it clears
  Action action = Action::AllOff;  // DeviceSafety: the most it may open (the device's flags say which)
  uint8_t latchTrips = 0;          // the trip that brings the count to this latches it; 0: never latches
  uint8_t tripDecayS = 0;          // s: one counted trip forgiven per this long after the latest; 0: never
  bool enabled = false;
};

struct ProtectionConfig {
  Rule rules[kFaultCount];  // by FaultId; upper limits: Ov, ChargeOc, Ot*; lower: Uv, DischargeOc, Ut*
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
  uint8_t off = 0;             // the paths to open (Action bits): the union of every active fault's action
  bool chargeOff() const { return (off & static_cast<uint8_t>(Action::ChargeOff)) != 0; }
  bool dischargeOff() const { return (off & static_cast<uint8_t>(Action::DischargeOff)) != 0; }
  bool faultOutput() const { return active != 0; }
};

class Protection {
 public:
  explicit Protection(const ProtectionConfig& config) : config_(config) {}

  ProtectionState evaluate(const ProtectionInputs& in, Instant now);
  // Clears latched faults whose condition is gone (a user action: button or CAN command). Returns the faults
  // that cleared; a latched fault whose condition is still present stays (latched() still has it).
  FaultMask clearLatched();

  FaultMask active() const { return state_->active; }
  FaultMask latched() const { return state_->latched; }  // active and held until clearLatched()
  uint8_t trips(FaultId id) const {
    return state_->trips[static_cast<uint8_t>(id)];
  }  // counted, not forgiven
  const ProtectionConfig& config() const { return config_; }
  Instant trippedAt(FaultId id) const { return state_->tripped[static_cast<uint8_t>(id)]; }
  // The paths DeviceSafety opens now (Action bits): the last scan's device flags, both after the fault line.
  uint8_t deviceBlocks() const { return state_->deviceBlocks; }

 private:
  // Moves rule `i`'s debounce with its value `v` (out of line: the loop around it stays in registers).
  void track(uint8_t i, int32_t v, Instant now, ProtectionState& out);
  // Forgives rule `i`'s counted trips whose decay has passed by `now`.
  void forgive(uint8_t i, Instant now);

  // Everything that changes, zero at construction (one block: no per-member start-up code).
  struct State {
    FaultMask active;
    FaultMask latched;  // active faults that stay until clearLatched()
    FaultMask goneNow;  // the last fresh value was past the rule's release threshold (for clearLatched)
    uint8_t failedScans;
    uint8_t deviceBlocks;  // DeviceSafety's paths (Action bits): the last scan's flags, or both on the line
    uint16_t attempts;     // the latest scan attempts, newest in bit 0: 1 = it failed (CommErrorRate)
    // Per fault: consecutive evaluations the condition (or, when tripped, its absence) was seen, and when
    // that run started (for the delay).
    uint8_t count[kFaultCount];
#if FW_PROTECTION_DELAYS
    Instant since[kFaultCount];
#endif
    Instant tripped[kFaultCount];
    // Per latching rule: trips counted and not yet forgiven, and when the decay towards the next is counted
    // from.
    uint8_t trips[kFaultCount];
    Instant tripsSince[kFaultCount];
  };
  const ProtectionConfig& config_;
  Zeroed<State> state_;
};

}  // namespace fw::app
