// Firmware protection limits: debounce count, delay, hysteresis, recovery, latching, the action per fault,
// the device's own flags bit by bit, stale data, comm loss and an open sense wire.
#include <gtest/gtest.h>

#include <vector>

#include "app/protection/default_limits.hpp"
#include "app/protection/protection.hpp"

namespace {

using fw::ms;
using fw::app::Action;
using fw::app::bit;
using fw::app::FaultId;
using fw::app::Protection;
using fw::app::ProtectionConfig;
using fw::app::ProtectionInputs;

constexpr uint8_t idx(FaultId id) {
  return static_cast<uint8_t>(id);
}

fw::app::Rule rule(int32_t trip, int32_t clear, uint8_t debounce, fw::Duration delay, Action action,
                   bool latch = false, uint8_t recover = 1) {
  fw::app::Rule r;
  r.trip = trip, r.clear = clear, r.debounce = debounce, r.delay = delay, r.action = action;
  r.latchTrips = latch ? 1 : 0;
  r.recover = recover;
  r.enabled = true;
  return r;
}

ProtectionConfig baseConfig() {
  ProtectionConfig c;
  c.rules[idx(FaultId::CellOvervoltage)] = rule(4250, 4150, 3, ms(200), Action::ChargeOff);
  c.rules[idx(FaultId::CellUndervoltage)] = rule(2700, 2900, 3, ms(200), Action::DischargeOff);
  c.rules[idx(FaultId::ChargeOvercurrent)] = rule(20000, 18000, 2, ms(0), Action::ChargeOff);
  c.rules[idx(FaultId::DischargeOvercurrent)] = rule(-40000, -35000, 2, ms(0), Action::DischargeOff, true);
  c.rules[idx(FaultId::OvertempDischarge)] = rule(3332, 3282, 2, ms(0), Action::DischargeOff);  // 60.0/55.0 C
  c.rules[idx(FaultId::UndertempDischarge)] = rule(2532, 2582, 2, ms(0), Action::DischargeOff);  // -20/-15 C
  c.rules[idx(FaultId::OvertempCharge)] = rule(3182, 3132, 2, ms(0), Action::ChargeOff);   // 45.0/40.0 C
  c.rules[idx(FaultId::UndertempCharge)] = rule(2732, 2782, 2, ms(0), Action::ChargeOff);  // 0/5 C
  c.rules[idx(FaultId::DeviceSafety)] = rule(1, 1, 1, ms(0), Action::AllOff);
  c.rules[idx(FaultId::StaleData)] = rule(1, 1, 1, ms(0), Action::AllOff);
  c.rules[idx(FaultId::CommLoss)] = rule(1, 1, 1, ms(0), Action::AllOff);
  c.rules[idx(FaultId::OpenWire)] = rule(1, 1, 1, ms(0), Action::AllOff);
  c.rules[idx(FaultId::CommErrorRate)] = rule(4, 1, 1, ms(0), Action::AllOff);
  c.staleAfter = ms(500);
  c.commLossScans = 3;
  c.rateWindow = 10;
  return c;
}

// One board of four cells and two temperature sensors, as a monitor task would keep it.
struct Sampler {
  std::vector<int16_t> cells = std::vector<int16_t>(4, 3700);
  std::vector<int16_t> temps = std::vector<int16_t>(2, 2982);
  int32_t current = 0;
  uint8_t deviceBlocks = 0;  // the paths the device's flags concern (1 charge, 2 discharge)
  fw::app::BoardSample board{};
  fw::app::PackView view;

  const fw::app::PackView* pack() {
    view.boards = std::span<const fw::app::BoardSample>(&board, 1);
    view.cellsPerBoard = static_cast<uint8_t>(cells.size());
    view.tempsPerBoard = static_cast<uint8_t>(temps.size());
    view.hasCurrent = true;
    view.currentMa = current;
    view.deviceBlocks = deviceBlocks;
    return &view;
  }
  // A scan that validated at tMs.
  ProtectionInputs fresh(uint32_t tMs) {
    board.takenAt = fw::Instant{tMs * 1000};
    board.last = fw::Status::Ok;
    board.valid = true;
    for (size_t i = 0; i < cells.size(); ++i)
      board.cellMv[i] = cells[i];
    for (size_t i = 0; i < temps.size(); ++i)
      board.tempDeciK[i] = temps[i];
    ProtectionInputs in;
    in.fresh = true;
    in.pack = pack();
    fw::app::summarize(view, board.takenAt);  // what a monitor does after each scan
    return in;
  }
  // A scan attempt that failed.
  ProtectionInputs failed() {
    board.last = fw::Status::Timeout;
    ProtectionInputs in;
    in.scanFailed = true;
    in.pack = pack();
    fw::app::summarize(view, board.takenAt);
    return in;
  }
  // A periodic check with no new scan.
  ProtectionInputs tick() {
    ProtectionInputs in;
    in.pack = pack();
    return in;
  }
};

fw::Instant at(uint32_t tMs) {
  return fw::Instant{tMs * 1000};
}

TEST(Protection, OvervoltageNeedsDebounceCountAndDelay) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.cells[2] = 4260;
  // 100 ms scans: the third sighting is at 200 ms, which also satisfies the 200 ms delay.
  EXPECT_EQ(p.evaluate(s.fresh(0), at(0)).active, 0);
  EXPECT_EQ(p.evaluate(s.fresh(100), at(100)).active, 0);
  const auto st = p.evaluate(s.fresh(200), at(200));
  EXPECT_EQ(st.active, bit(FaultId::CellOvervoltage));
  EXPECT_EQ(st.newlyTripped, bit(FaultId::CellOvervoltage));
  EXPECT_TRUE(st.chargeOff());
  EXPECT_FALSE(st.dischargeOff());
  EXPECT_EQ(p.trippedAt(FaultId::CellOvervoltage), at(200));
}

TEST(Protection, DelayHoldsTripEvenAfterEnoughSightings) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.cells[0] = 4300;
  // 10 ms scans: three sightings by 20 ms, but the 200 ms delay is not over until 200 ms.
  for (uint32_t t = 0; t < 200; t += 10)
    EXPECT_EQ(p.evaluate(s.fresh(t), at(t)).active, 0) << t;
  EXPECT_EQ(p.evaluate(s.fresh(200), at(200)).active, bit(FaultId::CellOvervoltage));
}

TEST(Protection, OneNoisySampleDoesNotTrip) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  for (uint32_t t = 0; t < 2000; t += 100) {
    s.cells[1] = (t / 100) % 2 == 0 ? 4300 : 4000;  // every other sample over the limit
    EXPECT_EQ(p.evaluate(s.fresh(t), at(t)).active, 0) << t;
  }
}

TEST(Protection, HysteresisKeepsTheFaultUntilBelowTheClearThreshold) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.cells[3] = 4300;
  for (uint32_t t = 0; t <= 200; t += 100)
    p.evaluate(s.fresh(t), at(t));
  ASSERT_EQ(p.active(), bit(FaultId::CellOvervoltage));
  s.cells[3] = 4200;  // under the trip, above the clear threshold
  for (uint32_t t = 300; t <= 1500; t += 100)
    EXPECT_EQ(p.evaluate(s.fresh(t), at(t)).active, p.active());
  EXPECT_EQ(p.active(), bit(FaultId::CellOvervoltage));
  s.cells[3] = 4100;  // past the clear threshold: recovery is debounced and delayed like the trip
  EXPECT_NE(p.evaluate(s.fresh(1600), at(1600)).active, 0);
  EXPECT_NE(p.evaluate(s.fresh(1700), at(1700)).active, 0);
  const auto st = p.evaluate(s.fresh(1800), at(1800));
  EXPECT_EQ(st.active, 0);
  EXPECT_EQ(st.newlyCleared, bit(FaultId::CellOvervoltage));
  EXPECT_FALSE(st.chargeOff());
}

TEST(Protection, MissingDataNeverClearsOrAdvancesAFault) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.cells[0] = 2600;
  for (uint32_t t = 0; t <= 200; t += 100)
    p.evaluate(s.fresh(t), at(t));
  ASSERT_EQ(p.active(), bit(FaultId::CellUndervoltage));
  p.evaluate(s.failed(), at(300));
  EXPECT_TRUE(p.active() & bit(FaultId::CellUndervoltage)) << "a failed scan is not evidence of recovery";
}

TEST(Protection, LatchedFaultStaysUntilClearedAndOnlyIfTheConditionIsGone) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.current = -45000;
  p.evaluate(s.fresh(0), at(0));
  auto st = p.evaluate(s.fresh(10), at(10));
  ASSERT_EQ(st.active, bit(FaultId::DischargeOvercurrent));
  EXPECT_TRUE(st.dischargeOff());
  EXPECT_EQ(p.clearLatched(), 0) << "condition still present";
  s.current = -1000;
  for (uint32_t t = 20; t < 200; t += 10)
    EXPECT_EQ(p.evaluate(s.fresh(t), at(t)).active, st.active);
  EXPECT_EQ(p.clearLatched(), bit(FaultId::DischargeOvercurrent));
  EXPECT_EQ(p.evaluate(s.fresh(200), at(200)).active, 0);
}

TEST(Protection, StaleDataIsAFaultAndFreshDataClearsIt) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  p.evaluate(s.fresh(0), at(0));
  EXPECT_EQ(p.evaluate(s.tick(), at(400)).active, 0);
  EXPECT_EQ(p.evaluate(s.tick(), at(500)).active, 0) << "exactly the limit is still fresh";
  const auto st = p.evaluate(s.tick(), at(501));
  EXPECT_EQ(st.active, bit(FaultId::StaleData));
  EXPECT_TRUE(st.chargeOff() && st.dischargeOff());
  EXPECT_EQ(p.evaluate(s.fresh(600), at(600)).active, 0);
}

TEST(Protection, NoSampleEverIsStaleOnceTheLimitPasses) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  EXPECT_EQ(p.evaluate(s.tick(), at(100)).active, 0);
  EXPECT_EQ(p.evaluate(s.tick(), at(600)).active, bit(FaultId::StaleData));
}

TEST(Protection, CommLossAfterConsecutiveFailedScans) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  p.evaluate(s.fresh(0), at(0));
  EXPECT_EQ(p.evaluate(s.failed(), at(100)).active, 0);
  EXPECT_EQ(p.evaluate(s.failed(), at(200)).active, 0);
  p.evaluate(s.fresh(300), at(300));              // one success resets the run
  constexpr auto kLoss = bit(FaultId::CommLoss);  // (the failure rate trips too: four of the last five)
  EXPECT_EQ(p.evaluate(s.failed(), at(400)).active & kLoss, 0);
  EXPECT_EQ(p.evaluate(s.failed(), at(450)).active & kLoss, 0);
  EXPECT_EQ(p.evaluate(s.failed(), at(480)).active & kLoss, kLoss);
  EXPECT_EQ(p.evaluate(s.fresh(490), at(490)).active & kLoss, 0);
}

// An intermittent link: two failures, one success, over and over, never three failures in a row. comm_loss
// never trips; comm_rate does at the fourth failure within the last ten attempts, and clears only once ten
// attempts in a row validated.
TEST(Protection, CommErrorRateCountsFailuresWithinTheWindowNotInARow) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  p.evaluate(s.fresh(0), at(0));
  uint32_t t = 0;
  int failures = 0;
  for (int cycle = 0; cycle < 4; ++cycle) {
    for (int k = 0; k < 2; ++k) {
      t += 100;
      ++failures;
      const auto st = p.evaluate(s.failed(), at(t));
      EXPECT_EQ(st.active & bit(FaultId::CommLoss), 0) << t;
      EXPECT_EQ((st.active & bit(FaultId::CommErrorRate)) != 0, failures >= 4) << t;
    }
    t += 100;
    EXPECT_EQ((p.evaluate(s.fresh(t), at(t)).active & bit(FaultId::CommErrorRate)) != 0, failures >= 4) << t;
  }
  // Healed (one success already): still tripped while a failure is among the last ten attempts.
  for (int k = 2; k < 10; ++k) {
    t += 100;
    EXPECT_NE(p.evaluate(s.fresh(t), at(t)).active & bit(FaultId::CommErrorRate), 0) << t;
  }
  t += 100;
  const auto st = p.evaluate(s.fresh(t), at(t));
  EXPECT_EQ(st.active, 0);
  EXPECT_EQ(st.newlyCleared, bit(FaultId::CommErrorRate));
}

// A scan that validated some boards and failed on others (kNewData and kScanFailed together) counts as a
// failed attempt for the rate, not for comm_loss (the link answered).
TEST(Protection, APartlyFailedScanCountsTowardTheRateOnly) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  for (uint32_t t = 0; t < 400; t += 100) {
    auto in = s.fresh(t);
    in.scanFailed = true;
    const auto st = p.evaluate(in, at(t));
    EXPECT_EQ(st.active & bit(FaultId::CommLoss), 0);
    EXPECT_EQ((st.active & bit(FaultId::CommErrorRate)) != 0, t == 300) << t;
  }
}

// While the monitor's first bring-up runs within its bound (PackView::startupGrace), a pack never measured is
// neither stale nor lost; once the grace ends it is stale at once (counted from power-up).
TEST(Protection, StartupGraceHoldsStaleDataAndCommLossUntilItEnds) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.view.startupGrace = true;
  s.view.firstDataDue = at(5000);
  s.board.valid = false;
  for (uint32_t t = 100; t <= 900; t += 100) {
    auto in = s.tick();
    in.scanFailed = true;  // a failed period, should one be reported
    EXPECT_EQ(p.evaluate(in, at(t)).active, 0) << t;
  }
  s.view.startupGrace = false;
  EXPECT_EQ(p.evaluate(s.tick(), at(1000)).active, bit(FaultId::StaleData));
}

TEST(Protection, ActionsAreTheUnionOfActiveFaults) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.temps[1] = 2700;  // -3.2 C: too cold to charge, warm enough to discharge
  p.evaluate(s.fresh(0), at(0));
  auto st = p.evaluate(s.fresh(10), at(10));
  EXPECT_EQ(st.active, bit(FaultId::UndertempCharge));
  EXPECT_TRUE(st.chargeOff());
  EXPECT_FALSE(st.dischargeOff());
  s.cells[2] = 2600;  // under-voltage (3 sightings over 200 ms): discharge off too
  p.evaluate(s.fresh(100), at(100));
  p.evaluate(s.fresh(200), at(200));
  st = p.evaluate(s.fresh(300), at(300));
  EXPECT_EQ(st.active, bit(FaultId::UndertempCharge) | bit(FaultId::CellUndervoltage));
  EXPECT_TRUE(st.chargeOff() && st.dischargeOff());
  EXPECT_TRUE(st.faultOutput());
}

// Issue 24: each fault opens the path it endangers, and only that one.
TEST(Protection, EachFaultOpensThePathItEndangers) {
  struct Case {
    const char* what;
    void (*set)(Sampler&);
    FaultId fault;
    bool chargeOff, dischargeOff;
  };
  const Case cases[] = {
      {"cell over-voltage", [](Sampler& s) { s.cells[0] = 4300; }, FaultId::CellOvervoltage, true, false},
      {"cell under-voltage", [](Sampler& s) { s.cells[0] = 2600; }, FaultId::CellUndervoltage, false, true},
      {"charge over-current", [](Sampler& s) { s.current = 25000; }, FaultId::ChargeOvercurrent, true, false},
      {"discharge over-current", [](Sampler& s) { s.current = -45000; }, FaultId::DischargeOvercurrent, false,
       true},
      {"too warm to charge", [](Sampler& s) { s.temps[0] = 3232; }, FaultId::OvertempCharge, true, false},
      {"too cold to charge", [](Sampler& s) { s.temps[0] = 2700; }, FaultId::UndertempCharge, true, false},
  };
  for (const Case& c : cases) {
    const auto cfg = baseConfig();
    Protection p(cfg);
    Sampler s;
    c.set(s);
    fw::app::ProtectionState st;
    for (uint32_t t = 0; t <= 600; t += 100)
      st = p.evaluate(s.fresh(t), at(t));
    EXPECT_EQ(st.active, bit(c.fault)) << c.what;
    EXPECT_EQ(st.chargeOff(), c.chargeOff) << c.what;
    EXPECT_EQ(st.dischargeOff(), c.dischargeOff) << c.what;
  }
  // The discharge temperature limits lie outside the charge ones: both trip, both paths open.
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.temps[0] = 3400;  // 66.9 C
  fw::app::ProtectionState st;
  for (uint32_t t = 0; t <= 200; t += 100)
    st = p.evaluate(s.fresh(t), at(t));
  EXPECT_EQ(st.active, bit(FaultId::OvertempCharge) | bit(FaultId::OvertempDischarge));
  EXPECT_TRUE(st.chargeOff() && st.dischargeOff());
}

// A current limit clears only while current flows the way that relieves it (TI's OCC/OCD recovery): with
// the charge path open and the charger still there the current reads 0, which must not switch the charger
// back on to trip again; a discharge of more than the clear threshold, for `recover` scans, does.
TEST(Protection, ACurrentFaultRecoversOnlyWithCurrentTheOtherWay) {
  auto cfg = baseConfig();
  cfg.rules[idx(FaultId::ChargeOvercurrent)] = rule(20000, -200, 2, ms(0), Action::ChargeOff, false, 30);
  Protection p(cfg);
  Sampler s;
  s.current = 25000;
  p.evaluate(s.fresh(0), at(0));
  ASSERT_EQ(p.evaluate(s.fresh(100), at(100)).active, bit(FaultId::ChargeOvercurrent));
  s.current = 0;  // the charge path is open: nothing flows
  for (uint32_t t = 200; t < 10000; t += 100)
    ASSERT_EQ(p.evaluate(s.fresh(t), at(t)).active, bit(FaultId::ChargeOvercurrent)) << t;
  s.current = -1500;  // a load draws from the pack: discharge current
  uint32_t cleared = 0;
  for (uint32_t t = 10000; t < 14000 && cleared == 0; t += 100)
    if (p.evaluate(s.fresh(t), at(t)).newlyCleared == bit(FaultId::ChargeOvercurrent)) cleared = t;
  EXPECT_EQ(cleared, 12900u) << "the 30th scan of discharge current";
}

// Behind one fault output (the BQ4050 and BQ79616 images) no current can flow the other way while a current
// fault holds the output: with kDefaultLimits the fault would never clear. kSingleOutputLimits recovers it
// after 3 s without current in the tripped direction (the output is then released and retried).
TEST(Protection, BehindOneFaultOutputACurrentFaultRecoversOnTime) {
  for (const bool single : {false, true}) {
    Protection p(single ? fw::app::kSingleOutputLimits : fw::app::kDefaultLimits);
    Sampler s;
    s.current = -31000;  // past the -30 A discharge limit
    p.evaluate(s.fresh(0), at(0));
    ASSERT_EQ(p.evaluate(s.fresh(100), at(100)).active, bit(FaultId::DischargeOvercurrent)) << single;
    s.current = 0;  // the one output opened both paths: nothing flows
    uint32_t cleared = 0;
    for (uint32_t t = 200; t < 10000 && cleared == 0; t += 100)
      if (p.evaluate(s.fresh(t), at(t)).newlyCleared == bit(FaultId::DischargeOvercurrent)) cleared = t;
    EXPECT_EQ(cleared, single ? 3100u : 0u) << (single ? "the 30th scan without current" : "never");
  }
}

// The discharge over-current latch of the default limits (TI's OCDL, default_limits.hpp): three trips, each
// within 10 s of the one before, latch the discharge path off; each trip here recovers by a charge first.
struct OcdCycler {
  Protection p{fw::app::kDefaultLimits};
  Sampler s;
  uint32_t t = 0;
  fw::app::ProtectionState st{};

  void scan() {
    st = p.evaluate(s.fresh(t), at(t));
    t += 100;
  }
  void scans(uint32_t n) {
    for (uint32_t k = 0; k < n; ++k)
      scan();
  }
  // A discharge of 35 A until the fault trips (two scans), then a charge of 1 A for the 3 s recovery.
  void trip() {
    s.current = -35000;
    scans(2);
    ASSERT_TRUE(st.active & bit(FaultId::DischargeOvercurrent)) << t;
    s.current = 1000;
    scans(30);
  }
  bool ocd() const { return (p.active() & bit(FaultId::DischargeOvercurrent)) != 0; }
  bool latched() const { return (p.latched() & bit(FaultId::DischargeOvercurrent)) != 0; }
};

TEST(ProtectionLatch, TheThirdDischargeOvercurrentWithinTheWindowLatchesTheDischargePathOff) {
  OcdCycler c;
  c.scans(5);
  c.trip();
  c.trip();
  EXPECT_FALSE(c.ocd()) << "the first two trips recover by the charge";
  c.trip();
  EXPECT_TRUE(c.ocd()) << "the third stays through its recovery";
  EXPECT_TRUE(c.latched());
  c.scans(300);  // 30 s more of charge
  EXPECT_TRUE(c.ocd());
  EXPECT_TRUE(c.st.dischargeOff());
  EXPECT_FALSE(c.st.chargeOff()) << "the charge path stays available";
  EXPECT_EQ(c.st.newlyCleared, 0);
}

TEST(ProtectionLatch, TwoTripsDoNotLatch) {
  OcdCycler c;
  c.trip();
  c.trip();
  EXPECT_FALSE(c.ocd());
  EXPECT_EQ(c.p.latched(), 0);
  EXPECT_EQ(c.p.trips(FaultId::DischargeOvercurrent), 2);
  EXPECT_FALSE(c.st.dischargeOff());
}

// One counted trip is forgiven every 10 s after the latest (TI's Counter Dec Delay): trips 10 s apart never
// latch, 9.9 s apart latch on the third; two trips then 20 s without one start the count afresh.
TEST(ProtectionLatch, TheCountDecaysOneTripEveryTenSeconds) {
  for (const uint32_t gapScans : {100U, 99U}) {
    OcdCycler c;
    for (int k = 0; k < 6 && !c.latched(); ++k) {
      c.trip();
      c.scans(gapScans - 32);  // the trip and its recovery took 32 scans
    }
    EXPECT_EQ(c.latched(), gapScans == 99) << gapScans;
    if (gapScans == 100) {
      EXPECT_EQ(c.p.trips(FaultId::DischargeOvercurrent), 1);
    }
  }
  OcdCycler c;
  c.trip();
  c.trip();
  c.scans(175);  // 20.5 s after the second trip: both forgiven
  EXPECT_EQ(c.p.trips(FaultId::DischargeOvercurrent), 0);
  c.trip();
  c.trip();
  EXPECT_FALSE(c.latched()) << "two counted, not three";
  c.trip();
  EXPECT_TRUE(c.latched());
}

// ClearFaults (clearLatched) ends the latch only once the current is gone: not while 35 A or 500 mA of
// discharge flows; with none (or a charge) it clears, the discharge path comes back at the next evaluation,
// and the count survives: a trip before it is forgiven latches again at once.
TEST(ProtectionLatch, ClearLatchedClearsOnlyOnceTheCurrentIsGone) {
  OcdCycler c;
  c.trip();
  c.trip();
  c.s.current = -35000;
  c.scans(2);
  ASSERT_TRUE(c.latched());
  EXPECT_EQ(c.p.clearLatched(), 0) << "the over-current is still there";
  c.s.current = -500;
  c.scans(40);
  EXPECT_EQ(c.p.clearLatched(), 0) << "500 mA of discharge is not gone";
  EXPECT_TRUE(c.ocd());
  c.s.current = 0;
  c.scan();
  EXPECT_EQ(c.p.clearLatched(), bit(FaultId::DischargeOvercurrent));
  EXPECT_FALSE(c.latched());
  c.scan();
  EXPECT_FALSE(c.ocd());
  EXPECT_FALSE(c.st.dischargeOff());
  c.s.current = -35000;  // within 10 s: the count (3) is not forgiven yet
  c.scans(2);
  EXPECT_TRUE(c.latched()) << "a fault that came back latches on its first trip";
  c.s.current = 1000;  // a charge is gone too
  c.scan();
  EXPECT_EQ(c.p.clearLatched(), bit(FaultId::DischargeOvercurrent));
}

// A latched fault behind one fault output (kSingleOutputLimits: the over-current recovers at zero current)
// latches the same way and holds the output until the clear.
TEST(ProtectionLatch, BehindOneFaultOutputTheLatchHoldsUntilCleared) {
  Protection p(fw::app::kSingleOutputLimits);
  Sampler s;
  uint32_t t = 0;
  for (int k = 0; k < 3; ++k) {
    s.current = -35000;
    for (int n = 0; n < 2; ++n, t += 100)
      p.evaluate(s.fresh(t), at(t));
    s.current = 0;
    for (int n = 0; n < 31; ++n, t += 100)
      p.evaluate(s.fresh(t), at(t));
  }
  EXPECT_EQ(p.latched(), bit(FaultId::DischargeOvercurrent));
  EXPECT_TRUE(p.evaluate(s.fresh(t), at(t)).dischargeOff());
  EXPECT_EQ(p.clearLatched(), bit(FaultId::DischargeOvercurrent));
  EXPECT_EQ(p.evaluate(s.fresh(t + 100), at(t + 100)).active, 0);
}

// The device's own flags open the paths they concern (PackView::deviceBlocks), not both: a device COV keeps
// discharge available. The fault line (no flag known yet) opens both until the scan that names the flag.
TEST(Protection, DeviceFlagsOpenOnlyThePathsTheyConcern) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  p.evaluate(s.fresh(0), at(0));
  ProtectionInputs line = s.tick();
  line.faultLine = true;
  auto st = p.evaluate(line, at(5));
  EXPECT_EQ(st.active, bit(FaultId::DeviceSafety));
  EXPECT_TRUE(st.chargeOff() && st.dischargeOff()) << "the line says nothing about which flag";
  s.deviceBlocks = 1;  // the scan after it: a charge-side flag (COV)
  st = p.evaluate(s.fresh(8), at(8));
  EXPECT_EQ(st.active, bit(FaultId::DeviceSafety));
  EXPECT_TRUE(st.chargeOff());
  EXPECT_FALSE(st.dischargeOff());
  s.deviceBlocks = 2;  // CUV
  st = p.evaluate(s.fresh(100), at(100));
  EXPECT_FALSE(st.chargeOff());
  EXPECT_TRUE(st.dischargeOff());
  EXPECT_EQ(st.newlyTripped | st.newlyCleared, 0) << "one fault all along: no flapping";
}

TEST(Protection, ChargeOvercurrentUsesPositiveCurrent) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.current = 25000;
  p.evaluate(s.fresh(0), at(0));
  EXPECT_EQ(p.evaluate(s.fresh(10), at(10)).active, bit(FaultId::ChargeOvercurrent));
  s.current = -25000;  // a large discharge is not a charge overcurrent
  Protection q(cfg);
  q.evaluate(s.fresh(0), at(0));
  EXPECT_EQ(q.evaluate(s.fresh(10), at(10)).active, 0);
}

TEST(Protection, DeviceSafetyTripsAtOnce) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  s.deviceBlocks = 3;
  const auto st = p.evaluate(s.fresh(0), at(0));
  EXPECT_EQ(st.active, bit(FaultId::DeviceSafety));
  EXPECT_TRUE(st.chargeOff() && st.dischargeOff());
}

TEST(Protection, FaultLineTripsDeviceSafetyWithoutWaitingForAScan) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  p.evaluate(s.fresh(0), at(0));
  ProtectionInputs line = s.tick();
  line.faultLine = true;  // ALERT/nFAULT edge: no new measurement yet
  const auto st = p.evaluate(line, at(5));
  EXPECT_EQ(st.active, bit(FaultId::DeviceSafety));
  EXPECT_TRUE(st.chargeOff() && st.dischargeOff());
  EXPECT_EQ(p.evaluate(s.fresh(100), at(100)).active, 0) << "the next scan shows no device fault";
}

TEST(Protection, OnlyValidBoardsFeedTheLimitsAndALostBoardGoesStale) {
  const auto cfg = baseConfig();
  Protection p(cfg);
  fw::app::BoardSample boards[2]{};
  for (auto& b : boards) {
    b.valid = true;
    b.last = fw::Status::Ok;
    b.takenAt = at(0);
    for (int c = 0; c < 4; ++c)
      b.cellMv[c] = 3700;
  }
  boards[1].last = fw::Status::NoResponse;  // board 1 stopped answering; its old values must not count
  boards[1].cellMv[0] = 1000;
  fw::app::PackView view;
  view.boards = boards;
  view.cellsPerBoard = 4;
  ProtectionInputs in;
  in.fresh = true;
  in.pack = &view;
  for (uint32_t t = 0; t <= 400; t += 100) {
    boards[0].takenAt = at(t);
    fw::app::summarize(view, at(t));
    EXPECT_EQ(p.evaluate(in, at(t)).active, 0) << t;  // no undervoltage from the lost board's old cell
  }
  boards[0].takenAt = at(600);
  fw::app::summarize(view, at(600));
  EXPECT_EQ(p.evaluate(in, at(600)).active, bit(FaultId::StaleData)) << "board 1's data is 600 ms old";
}

TEST(Protection, AnOpenSenseWireIsAFaultOfItsOwnNotAnOvervoltage) {
  // The tap between cells 2 and 3 opens: cell 2 reads both cells, cell 3 nothing. Those two readings are
  // not cell voltages: open_wire trips at once and opens both paths; cell_ov and cell_uv do not.
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  EXPECT_EQ(p.evaluate(s.fresh(0), at(0)).active, 0);
  s.cells[1] = 7400;
  s.cells[2] = 0;
  for (uint32_t t = 100; t <= 500; t += 100) {
    const auto st = p.evaluate(s.fresh(t), at(t));
    EXPECT_EQ(st.active, bit(FaultId::OpenWire)) << t;
    EXPECT_TRUE(st.chargeOff() && st.dischargeOff());
  }
  s.cells[1] = s.cells[2] = 3700;  // the wire is back
  EXPECT_EQ(p.evaluate(s.fresh(600), at(600)).newlyCleared, bit(FaultId::OpenWire));
}

TEST(Protection, AMonitorReportedSenseFaultIsAnOpenWireNotACommLoss) {
  // BQ4050: the gauge answers with a cell above its 5 V input range, so the scan brings no cells (the board
  // is not Valid) yet the link works: the monitor reports kNewData and sets totals.openWire itself.
  const auto cfg = baseConfig();
  Protection p(cfg);
  Sampler s;
  EXPECT_EQ(p.evaluate(s.fresh(0), at(0)).active, 0);
  for (uint32_t t = 100; t <= 300; t += 100) {
    auto in = s.fresh(t);
    s.board.last = fw::Status::Implausible;
    fw::app::summarize(s.view, at(t));
    s.view.totals.openWire = true;
    EXPECT_EQ(p.evaluate(in, at(t)).active & (bit(FaultId::OpenWire) | bit(FaultId::CommLoss)),
              bit(FaultId::OpenWire))
        << t;
  }
}

TEST(Protection, DisabledRulesNeverTrip) {
  ProtectionConfig cfg;  // every rule disabled
  Protection p(cfg);
  Sampler s;
  s.cells[0] = 5000;
  s.deviceBlocks = 3;
  for (uint32_t t = 0; t < 5000; t += 100)
    EXPECT_EQ(p.evaluate(s.fresh(t), at(t)).active, 0);
  EXPECT_EQ(p.evaluate(s.tick(), at(100000)).active, 0);
}

}  // namespace
