// The limits a command may read and write (firmware/app/command/settings.hpp): the ranges stop at the
// pack's hard bound, a limit's clear value stays on the safe side of its trip value, and writes wait for the
// next scan boundary, where they take effect together.
#include <gtest/gtest.h>

#include "app/command/settings.hpp"
#include "app/protection/default_limits.hpp"

namespace {

using namespace fw::app;
using namespace fw::app::command;

constexpr uint8_t id(FaultId f, bool clear) {
  return static_cast<uint8_t>(static_cast<uint8_t>(f) * 2 + (clear ? 1 : 0));
}

TEST(LimitSettings, NoLimitCanBeLoosenedPastTheDefault) {
  LimitSettings s(kDefaultLimits);
  // Upper limits: the default trip value is the highest allowed; lower limits: the lowest.
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4251), WriteResult::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::ChargeOvercurrent, false), 20001), WriteResult::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::Overtemperature, false), 3333), WriteResult::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::CellUndervoltage, false), 2699), WriteResult::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::DischargeOvercurrent, false), -40001), WriteResult::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::Undertemperature, false), 2531), WriteResult::OutOfRange);
  for (uint8_t k = 0; k < kSettingCount; ++k) {
    const SettingSpec spec = s.spec(k);
    const Rule& r = kDefaultLimits.rules[spec.rule];
    const bool upper = (spec.rule & 1U) == 0;
    EXPECT_EQ(upper ? spec.max : spec.min, r.trip)
        << "setting " << int(k) << ": the bound is the default trip";
    EXPECT_EQ(s.read(k), spec.clear ? r.clear : r.trip);
  }
  EXPECT_EQ(s.write(kSettingCount, 0), WriteResult::UnknownSetting);
  s.apply();
  EXPECT_EQ(s.limits().rules[0].trip, 4250);  // nothing refused reached the limits
}

TEST(LimitSettings, AWriteWaitsForTheScanBoundaryAndThenTakesEffectWhole) {
  LimitSettings s(kDefaultLimits);
  const uint8_t ocdTrip = id(FaultId::DischargeOvercurrent, false),
                ocdClear = id(FaultId::DischargeOvercurrent, true);
  // Lower limit: the clear value must stay at or above the trip value. Tightening the trip to -20 A needs
  // the clear value moved first (-35 A would lie below it).
  EXPECT_EQ(s.write(ocdTrip, -20000), WriteResult::Inconsistent);
  EXPECT_EQ(s.write(ocdClear, -15000), WriteResult::Ok);
  EXPECT_EQ(s.write(ocdTrip, -20000), WriteResult::Ok);  // judged against the waiting clear value
  EXPECT_EQ(s.read(ocdTrip), -40000);                    // nothing changed before the boundary
  EXPECT_EQ(s.limits().rules[3].clear, -35000);
  s.apply();
  EXPECT_EQ(s.limits().rules[3].trip, -20000);
  EXPECT_EQ(s.limits().rules[3].clear, -15000);
  // Upper limit: the clear value may not rise above the trip value.
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, true), 4251), WriteResult::OutOfRange);
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), WriteResult::Inconsistent);  // clear 4150
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, true), 4000), WriteResult::Ok);
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), WriteResult::Ok);
  for (int k = 0; k < 2; ++k)
    EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), WriteResult::Ok);
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), WriteResult::Busy);  // four waiting at most
  s.apply();
  EXPECT_EQ(s.write(id(FaultId::CellOvervoltage, false), 4100), WriteResult::Ok);  // room again
}

}  // namespace
