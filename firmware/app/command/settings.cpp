#include "app/command/settings.hpp"

namespace fw::app::command {

namespace {

// Plausibility ends of the ranges, on the side that tightens protection (the other side is the default), by
// rule (FaultId 0..5; the charge temperature limits 10 and 11 share the temperature rows): cells 3.0 V / 3.8
// V, 0.1 A, 0 degC / 25 degC (0.1 K). A current limit clears only while current flows the other way (its
// default clear value, app/protection/default_limits.hpp), up to 5 A of it.
struct Bounds {
  int16_t tripEnd, clearEnd;  // every end fits 16 bits (mV, mA, 0.1 K)
};
constexpr Bounds kTightEnd[6] = {{3000, 2900}, {3800, 4000}, {100, -5000},
                                 {-100, 5000}, {2732, 2732}, {2982, 3032}};

constexpr bool isUpperLimit(uint8_t rule) {
  return (rule & 1U) == 0;  // CellOvervoltage, ChargeOvercurrent, OvertempDischarge, OvertempCharge
}

// Settings 0..11: rules 0..5 (FaultId order); 12..15: OvertempCharge (10) and UndertempCharge (11).
constexpr uint8_t ruleOf(uint8_t id) {
  return id < 12 ? static_cast<uint8_t>(id >> 1) : static_cast<uint8_t>(10 + ((id - 12) >> 1));
}

}  // namespace

SettingSpec settingSpec(uint8_t id, const ProtectionConfig& defaults) {
  const uint8_t rule = ruleOf(id);
  const bool clear = (id & 1U) != 0;
  const int32_t hard = defaults.rules[rule].trip;  // the pack's bound: the default trip value
  const Bounds& b = kTightEnd[rule < 6 ? rule : rule - 6];
  const int32_t tight = clear ? b.clearEnd : b.tripEnd;
  const Unit unit = rule < 2 ? Unit::Millivolt : rule < 4 ? Unit::Milliamp : Unit::DeciKelvin;
  return isUpperLimit(rule) ? SettingSpec{rule, clear, unit, tight, hard}
                            : SettingSpec{rule, clear, unit, hard, tight};
}

int32_t& LimitSettings::valueOf(ProtectionConfig& c, uint8_t id) {
  Rule& r = c.rules[ruleOf(id)];
  return (id & 1U) != 0 ? r.clear : r.trip;
}

int32_t LimitSettings::upcoming(uint8_t id) const {
  int32_t v = read(id);
  for (uint8_t k = 0; k < pending_->count; ++k) {
    if (pending_->id[k] == id) v = pending_->value[k];
  }
  return v;
}

Result LimitSettings::check(uint8_t id, int32_t value, int32_t partner) const {
  const SettingSpec s = spec(id);
  if (value < s.min || value > s.max) return Result::OutOfRange;
  // The pair as it will be: an upper limit clears below its trip value, a lower limit above it.
  const int32_t trip = s.clear ? partner : value;
  const int32_t clear = s.clear ? value : partner;
  return (isUpperLimit(s.rule) ? clear > trip : clear < trip) ? Result::Inconsistent : Result::Accepted;
}

Result LimitSettings::write(uint8_t id, int32_t value) {
  if (id >= kSettingCount) return Result::OutOfRange;
  const Result r = check(id, value, upcoming(static_cast<uint8_t>(id ^ 1U)));
  if (r != Result::Accepted) return r;
  if (pending_->count == kPending) return Result::Busy;
  pending_->id[pending_->count] = id;
  pending_->value[pending_->count++] = value;
  return Result::Accepted;
}

void LimitSettings::apply() {
  Pending& p = *pending_;
  if (kKeptSettings && p.count != 0) ++p.changes;
  for (uint8_t k = 0; k < p.count; ++k) {
    valueOf(limits_, p.id[k]) = p.value[k];
    if (kKeptSettings) p.written = static_cast<uint16_t>(p.written | 1U << p.id[k]);
  }
  p.count = 0;
}

uint8_t LimitSettings::restore(std::span<const int32_t, kSettingCount> values) {
  Pending& p = *pending_;
  uint8_t refused = 0;
  for (uint8_t trip = 0; trip < kSettingCount; trip += 2) {
    const auto clear = static_cast<uint8_t>(trip + 1);
    const uint16_t pair = static_cast<uint16_t>(3U << trip);
    if (check(trip, values[trip], values[clear]) == Result::Accepted &&
        check(clear, values[clear], values[trip]) == Result::Accepted) {
      valueOf(limits_, trip) = values[trip];
      valueOf(limits_, clear) = values[clear];
      p.fromFlash = static_cast<uint16_t>(p.fromFlash | pair);
    } else {
      p.refused = static_cast<uint16_t>(p.refused | pair);
      refused = static_cast<uint8_t>(refused + 2);
    }
  }
  return refused;
}

SettingSource LimitSettings::keptSource(uint8_t id) const {
  const Pending& p = *pending_;
  const uint16_t bit = static_cast<uint16_t>(1U << id);
  if ((p.written & bit) != 0) return SettingSource::Command;
  if ((p.fromFlash & bit) != 0) return SettingSource::Flash;
  return (p.refused & bit) != 0 ? SettingSource::FlashRefused : SettingSource::Default;
}

}  // namespace fw::app::command
