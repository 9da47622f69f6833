// LimitSettings: the firmware protection limits a command may read and write, and the rules a write obeys.
//
// The limits live here, in RAM, started from the image's defaults (app/protection/default_limits.hpp); the
// protection evaluates them by reference. Sixteen settings: the trip and clear values of the eight value
// limits (firmware/app/can/bms.yaml, SettingRead.Setting), in mV, mA or 0.1 K.
//
// Safety rules (tests/app/command_settings_test.cpp):
// - A write outside its setting's range is refused (OutOfRange, as is a setting that does not exist). Every
//   range stops at the image's default on the side that loosens protection: no upper limit can be raised,
//   and no lower limit lowered, past the pack's hard bound (the defaults until the pack file sets them); the
//   other end is a plausibility bound.
// - A write that would put a limit's clear value on the unsafe side of its trip value (above it for an upper
//   limit, below it for a lower one) is refused (Inconsistent), judged against the writes already waiting.
// - A write takes effect only at a scan boundary: it waits (at most kPending of them, in order; a further one
//   is refused Busy) until the protection task calls apply() just before it evaluates a new scan, which
//   applies every waiting write at once. Between two scans' evaluations the limits never change.
// Thread mode only (the command task writes, the protection task applies; they never run at once).
#pragma once

#include <cstdint>

#include "app/command/result.hpp"
#include "app/protection/protection.hpp"
#include "app/protection/protection_task.hpp"
#include "core/zeroed.hpp"

namespace fw::app::command {

enum class Unit : uint8_t { Millivolt = 0, Milliamp = 1, DeciKelvin = 2 };  // SettingValue.Unit

struct SettingSpec {
  uint8_t rule;  // FaultId of the limit
  bool clear;    // the clear value (else the trip value)
  Unit unit;
  int32_t min, max;
};

inline constexpr uint8_t kSettingCount = 16;

// Setting n: its trip value (n even) or clear value (n odd) of rule n / 2 (n < 12: cell_ov .. utd) or of
// OvertempCharge / UndertempCharge (12..15); the range from `defaults`.
SettingSpec settingSpec(uint8_t id, const ProtectionConfig& defaults);

class LimitSettings final : public LimitUpdate {
 public:
  static constexpr uint8_t kPending = 4;

  // `defaults` must outlive this object: it is both the starting point and the source of the hard bounds.
  explicit LimitSettings(const ProtectionConfig& defaults) : defaults_(defaults), limits_(defaults) {}

  const ProtectionConfig& limits() const { return limits_; }
  SettingSpec spec(uint8_t id) const { return settingSpec(id, defaults_); }
  // The value in effect (a write waiting for the next scan is not).
  int32_t read(uint8_t id) const { return valueOf(limits_, id); }
  // Accepted (waiting for the next scan), OutOfRange (no such setting, or outside its range), Inconsistent
  // or Busy (kPending writes already waiting).
  Result write(uint8_t id, int32_t value);
  void apply() override;

 private:
  static int32_t& valueOf(ProtectionConfig& c, uint8_t id);
  static int32_t valueOf(const ProtectionConfig& c, uint8_t id) {
    return valueOf(const_cast<ProtectionConfig&>(c), id);
  }
  int32_t upcoming(uint8_t id) const;  // the value once the waiting writes are applied

  struct Pending {
    uint8_t count;
    uint8_t id[kPending];
    int32_t value[kPending];
  };
  const ProtectionConfig& defaults_;
  ProtectionConfig limits_;
  Zeroed<Pending> pending_;
};

}  // namespace fw::app::command
