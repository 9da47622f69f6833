// The limits a command may read and write (firmware/app/command/settings.hpp): the ranges stop at the
// pack's hard bound, a limit's clear value stays on the safe side of its trip value, and writes wait for the
// next scan boundary, where they take effect together.
#include <gtest/gtest.h>

#include <array>

#include "app/command/settings.hpp"
#include "app/protection/default_limits.hpp"

namespace {

using namespace fw::app;
using namespace fw::app::command;

// Settings 0..11 are FaultId 0..5 (trip, clear); 12..15 the charge temperature limits (FaultId 10, 11).
constexpr uint8_t id(FaultId f, bool clear) {
  const auto rule = static_cast<uint8_t>(f);
  return static_cast<uint8_t>((rule < 6 ? rule * 2 : 12 + (rule - 10) * 2) + (clear ? 1 : 0));
}

TEST(LimitSettings, NoLimitCanBeLoosenedPastTheDefault) {
  LimitSettings s(kDefaultLimits);
  // Upper limits: the default trip value is the highest allowed; lower limits: the lowest.
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4251), Result::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::ChargeOvercurrent, false), 20001), Result::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::OvertempDischarge, false), 3333), Result::OutOfRange);  // 60 degC
  EXPECT_EQ(s.write(id(FaultId::OvertempCharge, false), 3183), Result::OutOfRange);     // 45 degC
  EXPECT_EQ(s.write(id(FaultId::UndertempCharge, false), 2731), Result::OutOfRange);    // 0 degC
  EXPECT_EQ(s.write(id(FaultId::CellUndervoltage, false), 2699), Result::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::DischargeOvercurrent, false), -30001), Result::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::UndertempDischarge, false), 2531), Result::OutOfRange);  // -20 degC
  for (uint8_t k = 0; k < kSettingCount; ++k) {
    const SettingSpec spec = s.spec(k);
    const Rule& r = kDefaultLimits.rules[spec.rule];
    const bool upper = (spec.rule & 1U) == 0;
    EXPECT_EQ(upper ? spec.max : spec.min, r.trip)
        << "setting " << int(k) << ": the bound is the default trip";
    EXPECT_EQ(s.read(k), spec.clear ? r.clear : r.trip);
    EXPECT_TRUE(s.read(k) >= spec.min && s.read(k) <= spec.max)
        << "setting " << int(k) << ": the default is in range";
    EXPECT_EQ(spec.unit, spec.rule < 2 ? Unit::Millivolt : spec.rule < 4 ? Unit::Milliamp : Unit::DeciKelvin);
  }
  // Every value limit of the protection has its two settings, once each.
  for (uint8_t rule : {0, 1, 2, 3, 4, 5, 10, 11}) {
    int seen = 0;
    for (uint8_t k = 0; k < kSettingCount; ++k)
      seen += s.spec(k).rule == rule ? 1 : 0;
    EXPECT_EQ(seen, 2) << "rule " << int(rule);
  }
  EXPECT_EQ(s.write(kSettingCount, 0), Result::OutOfRange);
  s.apply();
  EXPECT_EQ(s.limits().rules[0].trip, 4250);  // nothing refused reached the limits
}

TEST(LimitSettings, AWriteWaitsForTheScanBoundaryAndThenTakesEffectWhole) {
  LimitSettings s(kDefaultLimits);
  const uint8_t ocdTrip = id(FaultId::DischargeOvercurrent, false),
                ocdClear = id(FaultId::DischargeOvercurrent, true);
  // Lower limit: the clear value must stay at or above the trip value. A clear value of -25 A (clearing while
  // 25 A still flow) with the trip left at -20 A would lie below it.
  EXPECT_EQ(s.write(ocdClear, -25000), Result::Accepted);
  EXPECT_EQ(s.write(ocdTrip, -20000), Result::Inconsistent);  // judged against the waiting clear value
  EXPECT_EQ(s.write(ocdClear, -15000), Result::Accepted);
  EXPECT_EQ(s.write(ocdTrip, -20000), Result::Accepted);
  EXPECT_EQ(s.read(ocdTrip), -30000);  // nothing changed before the boundary
  EXPECT_EQ(s.limits().rules[3].clear, 200);
  s.apply();
  EXPECT_EQ(s.limits().rules[3].trip, -20000);
  EXPECT_EQ(s.limits().rules[3].clear, -15000);
  // Upper limit: the clear value may not rise above the trip value.
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, true), 4251), Result::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), Result::Inconsistent);  // clear 4150
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, true), 4000), Result::Accepted);
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), Result::Accepted);
  for (int k = 0; k < 2; ++k)
    EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), Result::Accepted);
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), Result::Busy);  // four waiting at most
  s.apply();
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), Result::Accepted);  // room again
}

// Kept values (app/store/persistence.hpp) pass the checks a write passes, pair by pair, before protection
// runs; where each value in effect came from is what SettingValue.Source answers.
TEST(LimitSettings, RestoreChecksEachPairAsAWriteAndTellsWhereEachValueCameFrom) {
  LimitSettings s(kDefaultLimits);
  std::array<int32_t, kSettingCount> kept{};
  for (uint8_t k = 0; k < kSettingCount; ++k)
    kept[k] = s.read(k);
  const uint8_t ovTrip = id(FaultId::CellOvervoltage, false), ovClear = id(FaultId::CellOvervoltage, true);
  const uint8_t uvTrip = id(FaultId::CellUndervoltage, false), uvClear = id(FaultId::CellUndervoltage, true);
  const uint8_t ocdTrip = id(FaultId::DischargeOvercurrent, false);
  // A pair a single write could not reach (the trip below the default clear value) but whole is consistent.
  kept[ovTrip] = 4000;
  kept[ovClear] = 3900;
  kept[uvTrip] = 2600;  // below the default 2700 mV: loosens protection, refused with its clear value
  kept[uvClear] = 3000;
  kept[ocdTrip] = -20000;
  EXPECT_EQ(s.write(uvTrip, 2600), Result::OutOfRange) << "what a command could not write";
  EXPECT_EQ(s.restore(kept), 2);
  EXPECT_EQ(s.read(ovTrip), 4000);
  EXPECT_EQ(s.read(ovClear), 3900);
  EXPECT_EQ(s.limits().rules[0].trip, 4000) << "in effect at once: protection has not run yet";
  EXPECT_EQ(s.read(uvTrip), kDefaultLimits.rules[1].trip);
  EXPECT_EQ(s.read(uvClear), kDefaultLimits.rules[1].clear);
  EXPECT_EQ(s.read(ocdTrip), -20000);
  EXPECT_EQ(s.source(ovTrip), SettingSource::Flash);
  EXPECT_EQ(s.source(uvTrip), SettingSource::FlashRefused);
  EXPECT_EQ(s.source(uvClear), SettingSource::FlashRefused);
  const uint8_t before = s.changes();
  EXPECT_EQ(s.write(ocdTrip, -25000), Result::Accepted);
  EXPECT_EQ(s.source(ocdTrip), SettingSource::Flash) << "a waiting write is not in effect";
  s.apply();
  EXPECT_EQ(s.source(ocdTrip), SettingSource::Command);
  EXPECT_EQ(s.changes(), static_cast<uint8_t>(before + 1));
  s.apply();
  EXPECT_EQ(s.changes(), static_cast<uint8_t>(before + 1)) << "nothing waited: nothing changed";
  // A clear value crossing its trip value, each in range: refused too.
  LimitSettings t(kDefaultLimits);
  kept[ovTrip] = 4000;
  kept[ovClear] = 4100;
  kept[uvTrip] = kDefaultLimits.rules[1].trip;
  kept[uvClear] = kDefaultLimits.rules[1].clear;
  EXPECT_EQ(t.restore(kept), 2);
  EXPECT_EQ(t.read(ovTrip), kDefaultLimits.rules[0].trip);
  EXPECT_EQ(t.source(id(FaultId::UndertempCharge, true)), SettingSource::Flash);
  LimitSettings fresh(kDefaultLimits);
  EXPECT_EQ(fresh.source(ovTrip), SettingSource::Default);
}

}  // namespace
