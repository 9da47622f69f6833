// The state of charge (app/soc): the accumulated-charge decoding of both families (wrap, device restart),
// the open-circuit table, the first value, counting, the full and empty resets, the rest correction and its
// flat-table limit, restore(). Integer arithmetic throughout; every expectation is computed from the config.
#include <gtest/gtest.h>

#include "app/soc/accumulated_charge.hpp"
#include "app/soc/soc.hpp"

namespace {

using namespace fw::app;

constexpr SocConfig kLiIon{.capacityMah = 2500,
                           .fullCellMv = 4200,
                           .emptyCellMv = 2800,
                           .restCurrentMa = 50,
                           .restTime = fw::s(600),
                           .ocvMinStepMv = 20,
                           .ocvMv = {3000, 3450, 3550, 3620, 3680, 3740, 3810, 3890, 3970, 4060, 4170}};
constexpr SocConfig kLfp{.capacityMah = 20000,
                         .fullCellMv = 3600,
                         .emptyCellMv = 2600,
                         .restCurrentMa = 200,
                         .restTime = fw::s(1800),
                         .ocvMinStepMv = 20,
                         .ocvMv = {2500, 3200, 3250, 3280, 3300, 3310, 3320, 3330, 3340, 3360, 3450}};

// A BQ769x2 counter at `mah` userAh (1 mA unit) plus its reset value, and the time.
ChargeCount count769x2(int64_t mah, uint32_t seconds) {
  return {static_cast<int64_t>(static_cast<uint64_t>(mah) << 32) + 0x7FFFFFFF, seconds * 1000};
}

SocInputs scan(uint32_t ms, int32_t currentMa, int16_t cellMv, ChargeCount c, bool counted = true) {
  SocInputs in;
  in.now = fw::Instant{ms * 1000};
  in.currentMa = currentMa;
  in.maxCellMv = in.minCellMv = in.avgCellMv = cellMv;
  in.cells = true;
  in.counted = counted;
  in.count = c;
  return in;
}

TEST(AccumulatedCharge, DecodesEachFamilysBytes) {
  // BQ769x2 DASTATUS6: -2 userAh + 0x80000000/2^32, 77 s.
  const uint8_t d2[12] = {0xFE, 0xFF, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x80, 77, 0, 0, 0};
  const ChargeCount c2 = bq769x2Count(d2);
  EXPECT_EQ(c2.count, -(int64_t{2} << 32) + 0x80000000LL);
  EXPECT_EQ(c2.timeMs, 77000u);
  // BQ7690x PASSQ: -5 userA-s in 48 bits (low word, high 16 bits sign-extended), 8 x 250 ms.
  const uint8_t d7[12] = {0xFB, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 8, 0, 0, 0};
  const ChargeCount c7 = bq7690xCount(d7);
  EXPECT_EQ(c7.count, -5);
  EXPECT_EQ(c7.timeMs, 2000u);
}

TEST(AccumulatedCharge, StepsAcrossTheCountersWrap) {
  // BQ769x2: 2^31 - 1 userAh to -2^31 + 9 is +10 userAh.
  const ChargeCount a{static_cast<int64_t>(0x7FFFFFFFULL << 32), 100000};
  const ChargeCount b{static_cast<int64_t>(0x80000009ULL << 32), 101000};
  const ChargeStep s =
      chargeStep(CounterFamily::Bq769x2, uahQ32PerCount(CounterFamily::Bq769x2, 10), a, b, fw::ms(1000));
  EXPECT_FALSE(s.restarted);
  EXPECT_EQ(s.uahQ32, (int64_t{10} << 32) * 1000) << "10 mAh in uAh x 2^32";
  // BQ7690x: 2^47 - 1 userA-s to -2^47 + 35 is +36 userA-s = 10 uAh at 1 mA.
  const ChargeCount c{(int64_t{1} << 47) - 1, 4000};
  const ChargeCount d{-(int64_t{1} << 47) + 35, 8000};
  const ChargeStep t =
      chargeStep(CounterFamily::Bq7690x, uahQ32PerCount(CounterFamily::Bq7690x, 10), c, d, fw::ms(4000));
  EXPECT_FALSE(t.restarted);
  EXPECT_EQ(t.uahQ32 >> 32, 9) << "36 mA-s is 10 uAh, rounded down by the fixed point";
  EXPECT_NEAR(static_cast<double>(t.uahQ32) / 4294967296.0, 10.0, 1e-6);
}

TEST(AccumulatedCharge, ACounterWhoseTimeDidNotFollowTheMcusRestartedAndCountsFromZero) {
  // Device time 1000 s, then 3 s: a reset in between; the charge since is the reading less half a userAh.
  const ChargeCount before = count769x2(500, 1000);
  const ChargeCount after = count769x2(-4, 3);
  const ChargeStep s = chargeStep(CounterFamily::Bq769x2, uahQ32PerCount(CounterFamily::Bq769x2, 10), before,
                                  after, fw::ms(5000));
  EXPECT_TRUE(s.restarted);
  EXPECT_EQ(s.uahQ32, -(int64_t{4} << 32) * 1000);
  // An outage longer than the device had been up: its time moved less than the MCU's clock.
  const ChargeStep t = chargeStep(CounterFamily::Bq769x2, uahQ32PerCount(CounterFamily::Bq769x2, 10),
                                  count769x2(0, 5), count769x2(1, 30), fw::ms(60000));
  EXPECT_TRUE(t.restarted);
  // A counter that kept counting through an outage is no restart.
  const ChargeStep u = chargeStep(CounterFamily::Bq769x2, uahQ32PerCount(CounterFamily::Bq769x2, 10),
                                  count769x2(0, 5), count769x2(-7, 65), fw::ms(60000));
  EXPECT_FALSE(u.restarted);
  EXPECT_EQ(u.uahQ32, -(int64_t{7} << 32) * 1000);
}

TEST(Soc, OcvTableInterpolatesAndKnowsWhereItIsTooFlat) {
  EXPECT_EQ(ocvEstimate(kLiIon, 2900).permille, 0u);
  EXPECT_EQ(ocvEstimate(kLiIon, 3000).permille, 0u);
  EXPECT_EQ(ocvEstimate(kLiIon, 3225).permille, 50u);
  EXPECT_EQ(ocvEstimate(kLiIon, 3740).permille, 500u);
  EXPECT_EQ(ocvEstimate(kLiIon, 4170).permille, 1000u);
  EXPECT_EQ(ocvEstimate(kLiIon, 4300).permille, 1000u);
  EXPECT_TRUE(ocvEstimate(kLiIon, 3700).resolves);
  EXPECT_FALSE(ocvEstimate(kLfp, 3305).resolves) << "10 mV per 10 % on the LFP plateau";
  EXPECT_TRUE(ocvEstimate(kLfp, 3000).resolves);
}

TEST(Soc, NotKnownUntilTheFirstScanAtRestThenCounted) {
  StateOfCharge soc(kLiIon, CounterFamily::Bq769x2, 10);
  soc.update(scan(100, -2000, 3740, count769x2(0, 1)));  // under load: no voltage estimate
  EXPECT_FALSE(soc.known());
  EXPECT_EQ(soc.permille(), 0u);
  soc.update(scan(200, 0, 3740, count769x2(0, 1)));
  ASSERT_TRUE(soc.known());
  EXPECT_EQ(soc.basis(), SocBasis::Ocv);
  EXPECT_EQ(soc.permille(), 500u);
  EXPECT_EQ(soc.remainingMah(), 1250u);
  // 250 mAh out: 10 %.
  soc.update(scan(900200, -1000, 3700, count769x2(-250, 901)));
  EXPECT_EQ(soc.remainingMah(), 1000u);
  EXPECT_EQ(soc.permille(), 400u);
  EXPECT_EQ(soc.basis(), SocBasis::Ocv) << "the anchor stays; the count moved it";
}

TEST(Soc, FullAndEmptyResetAtThePacksVoltageLimits) {
  StateOfCharge soc(kLiIon, CounterFamily::Bq769x2, 10);
  soc.update(scan(100, 0, 3740, count769x2(0, 0)));
  SocInputs full = scan(200, 500, 4200, count769x2(0, 0));
  full.minCellMv = 4150;
  soc.update(full);
  EXPECT_EQ(soc.basis(), SocBasis::Full);
  EXPECT_EQ(soc.permille(), 1000u);
  EXPECT_EQ(soc.remainingMah(), 2500u);
  // The highest cell at the limit while discharging is no full pack.
  StateOfCharge s2(kLiIon, CounterFamily::Bq769x2, 10);
  s2.update(scan(100, 0, 3740, count769x2(0, 0)));
  s2.update(scan(200, -500, 4200, count769x2(0, 0)));
  EXPECT_EQ(s2.basis(), SocBasis::Ocv);
  // Empty: the lowest cell at emptyCellMv while not charging.
  SocInputs empty = scan(300, -2500, 3300, count769x2(0, 0));
  empty.minCellMv = 2800;
  soc.update(empty);
  EXPECT_EQ(soc.basis(), SocBasis::Empty);
  EXPECT_EQ(soc.permille(), 0u);
  // Counting never goes below empty or above full.
  soc.update(scan(400, -2500, 3300, count769x2(-100, 0)));
  EXPECT_EQ(soc.remainingMah(), 0u);
}

TEST(Soc, ARestCorrectsTheCountFromTheOpenCircuitVoltage) {
  StateOfCharge soc(kLiIon, CounterFamily::Bq769x2, 10);
  soc.restore(800);  // 20 % above the truth (60 %)
  EXPECT_EQ(soc.basis(), SocBasis::Restored);
  uint32_t ms = 0;
  // 9 minutes 59 s at rest at the 60 % voltage: no correction yet.
  for (; ms <= 599000; ms += 1000)
    soc.update(scan(ms, 0, 3810, count769x2(0, ms / 1000)));
  EXPECT_EQ(soc.permille(), 800u);
  soc.update(scan(ms, 0, 3810, count769x2(0, ms / 1000)));
  EXPECT_EQ(soc.basis(), SocBasis::Ocv);
  EXPECT_EQ(soc.permille(), 600u);
}

TEST(Soc, NoCorrectionWhereTheTableIsFlat) {
  StateOfCharge soc(kLfp, CounterFamily::Bq7690x, 10);
  soc.restore(300);
  uint32_t ms = 0;
  for (; ms <= 1900000; ms += 1000)
    soc.update(scan(ms, 0, 3305, {0, ms}));
  EXPECT_EQ(soc.permille(), 300u) << "3305 mV lies on the plateau: the count stands";
  EXPECT_EQ(soc.basis(), SocBasis::Restored);
}

TEST(Soc, RestoreNeverReplacesAValueAlreadyKnown) {
  StateOfCharge soc(kLiIon, CounterFamily::Bq769x2, 10);
  soc.update(scan(100, 0, 3740, count769x2(0, 0)));
  soc.restore(100);
  EXPECT_EQ(soc.permille(), 500u);
  soc.restore(1001);  // out of range: ignored either way
}

TEST(Soc, ADeviceRestartKeepsCountingFromTheRestartedCounter) {
  StateOfCharge soc(kLiIon, CounterFamily::Bq769x2, 10);
  soc.update(scan(100, 0, 3740, count769x2(0, 1000)));       // 50 %
  soc.update(scan(5000, -1000, 3700, count769x2(-100, 3)));  // reset in between; 100 mAh out since
  EXPECT_EQ(soc.counterRestarts(), 1u);
  EXPECT_EQ(soc.remainingMah(), 1150u);
}

}  // namespace
