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
// - Kept across a reset (app/store/persistence.hpp): restore(), at start-up before protection runs, takes
//   the values the record store kept, each pair (trip and clear of one limit) checked by the same rules as a
//   write (range, then its own clear value on the safe side of its trip value); a pair that fails is refused
//   whole (a clear value means nothing without its trip value), counted and never applied: that limit keeps
//   the image's default. changes() counts the applications that changed something, so the store knows
//   when to write the values again.
// - source(id) says where a value in effect came from (SettingValue.Source): the image's default, the flash,
//   a command since start-up, or the default because the kept value was refused.
// Thread mode only (the command task writes, the protection task applies; they never run at once).
#pragma once

#include <cstdint>
#include <span>

#include "app/command/result.hpp"
#include "app/config.hpp"
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

enum class SettingSource : uint8_t {
  Default = 0,
  Flash = 1,
  Command = 2,
  FlashRefused = 3
};  // SettingValue.Source
// Where the record store is built (FW_RECORD_STORE): the settings are kept, and where they came from is
// tracked; elsewhere every value is the default or a command's, and source() says Default at no cost.
inline constexpr bool kKeptSettings = FW_RECORD_STORE != 0;

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

  // Start-up only, before protection evaluates (nothing may be waiting): the kept values of every setting,
  // pair by pair, checked as a write is. Returns how many settings were refused (0..kSettingCount).
  uint8_t restore(std::span<const int32_t, kSettingCount> values);
  SettingSource source(uint8_t id) const { return kKeptSettings ? keptSource(id) : SettingSource::Default; }
  uint8_t changes() const { return pending_->changes; }

 private:
  static int32_t& valueOf(ProtectionConfig& c, uint8_t id);
  static int32_t valueOf(const ProtectionConfig& c, uint8_t id) {
    return valueOf(const_cast<ProtectionConfig&>(c), id);
  }
  int32_t upcoming(uint8_t id) const;  // the value once the waiting writes are applied
  // Range, then the pair's consistency with `partner` (the other value of the same limit): Accepted,
  // OutOfRange or Inconsistent.
  Result check(uint8_t id, int32_t value, int32_t partner) const;
  SettingSource keptSource(uint8_t id) const;

  // The waiting writes first: where they were before the kept settings' fields (no new offsets to reach).
  struct Pending {
    uint8_t count;
    uint8_t id[kPending];
    int32_t value[kPending];
    uint8_t changes;     // applications that changed a value (wraps)
    uint16_t fromFlash;  // bit n: setting n was restored from flash
    uint16_t refused;    // bit n: setting n's kept value was refused at restore
    uint16_t written;    // bit n: setting n was written by a command since start-up
  };
  const ProtectionConfig& defaults_;
  ProtectionConfig limits_;
  Zeroed<Pending> pending_;
};

}  // namespace fw::app::command
