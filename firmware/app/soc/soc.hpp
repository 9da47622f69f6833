// StateOfCharge: the pack's state of charge from the battery monitor's accumulated charge, in integers.
//
// Once per validated scan, update() gets the scan's current, highest, lowest and average cell voltage, and
// the device's charge counter when the scan read it:
//   - counting: the counter's change since the last reading (accumulated_charge.hpp: wrap and device
//     restarts handled) moves the remaining charge; it is kept in uAh x 2^32 and clamped to 0..capacity;
//   - first value: the open-circuit voltage table at the first scan whose current is below the rest current
//     (a pack that has not rested reads low under load, high after a charge), or a full or empty reset, or
//     restore() (the record store's saved value) - whichever comes first. Until then nothing is known and
//     the outputs say not available;
//   - full: the highest cell at or above fullCellMv while the pack is not discharging sets 100 %; empty: the
//     lowest cell at or below emptyCellMv while it is not charging sets 0 %;
//   - rest: after |current| < restCurrentMa for restTime (and every restTime while the rest lasts), the
//     average cell's open-circuit voltage sets the charge (foxBMS recalibrates at rest the same way;
//     LibreSolar only at start-up), unless the table is too flat there (ocvMinStepMv per 10 %).
// Outputs: soc in 0.1 %, the remaining charge and the capacity in mAh, and how the value was last anchored
// (the count since then moves it).
// Contract: monitor task only (thread mode); no allocation, no division by a variable other than 32-bit.
#pragma once

#include <cstdint>

#include "app/soc/accumulated_charge.hpp"
#include "app/soc/soc_config.hpp"
#include "app/soc/soc_view.hpp"
#include "core/time.hpp"
#include "core/zeroed.hpp"

namespace fw::app {

// One scan's view of the pack, as update() needs it.
struct SocInputs {
  Instant now;
  int32_t currentMa = 0;
  int16_t maxCellMv = 0;
  int16_t minCellMv = 0;
  int16_t avgCellMv = 0;
  bool cells = false;    // the cell voltages are a whole validated scan (no open wire)
  bool counted = false;  // `count` holds a reading of the device's counter from this scan
  ChargeCount count{};
};

// The open-circuit voltage table's state of charge (0.1 %) for a cell voltage, and whether the table's step
// there is at least minStepMv (the voltage resolves the charge).
struct OcvEstimate {
  uint16_t permille;
  bool resolves;
};
OcvEstimate ocvEstimate(const SocConfig& c, int16_t cellMv);

class StateOfCharge {
 public:
  StateOfCharge(const SocConfig& config, CounterFamily family, int32_t lsbTenthMa)
      : config_(config), perCountQ32_(uahQ32PerCount(family, lsbTenthMa)), family_(family) {}

  void update(const SocInputs& in);
  // A value kept across a reset (the record store's SOC record): taken unless a better one is already known.
  void restore(uint16_t permille);

  bool known() const { return state_->basis != SocBasis::Unknown; }
  SocBasis basis() const { return state_->basis; }
  uint16_t permille() const;      // 0..1000; 0 while unknown
  uint32_t remainingMah() const;  // 0 while unknown
  uint32_t capacityMah() const { return config_.capacityMah; }
  uint32_t counterRestarts() const { return state_->restarts; }

 private:
  void set(uint32_t permille, SocBasis basis);

  struct State {
    int64_t chargeQ32;  // remaining uAh x 2^32
    ChargeCount last;   // the last counter reading
    Instant lastAt;
    Duration rest;      // how long the current has been below the rest current (saturating)
    Duration sinceFix;  // rest time since the last open-circuit correction
    uint32_t restarts;
    SocBasis basis;
    bool haveLast;
    bool started;  // lastAt is a scan's time
  };
  const SocConfig& config_;
  int64_t perCountQ32_;  // uAh x 2^32 per device count (uahQ32PerCount)
  CounterFamily family_;
  Zeroed<State> state_;
};

}  // namespace fw::app
