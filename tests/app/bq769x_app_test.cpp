// The BQ769x2-family application as the lp-mspm0g3507-bq76952 image composes it (CAN out, fault output), on
// the host BSP against the BQ76952 emulator: the fault output, and the ALERT fast path against its budget
// (ARCHITECTURE.md: fault visible in the device -> FET-off command complete <= 2 ms on ALERT).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "app/bq769x_app.hpp"
#include "app/bq769x_settings.hpp"
#include "bq769x2/emulator.hpp"
#include "can/bms.hpp"
#include "sim/can.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"
#include "sim/peripherals.hpp"

namespace {

namespace b769 = fw::drivers::bq769x2;
using Emulator = bsp::host::Bq769xEmulator;
using App = fw::app::Bq769xApp<b769::Bq769x2, b769::Bq769x2Measurement, fw::app::CanPublisher>;

constexpr const char* kAllFetsOff = "S 10 3E 95 00";

struct G3507 {
  bsp::host::Harness h;
  bsp::host::SimI2cBus bus{h.clock, h.irq, {400000, fw::ms(4), fw::us(4)}};
  Emulator emu{h.clock, Emulator::Model::Bq76952};
  bsp::host::SimEdgeInput alert{h.irq, "alert", bsp::host::SimEdgeInput::Edge::Falling, true};
  bsp::host::SimCan can{h.clock, h.irq, 500000, 8};
  bsp::host::SimDigitalOut faultOut{h.clock, true};  // the board asserts it from reset
  fw::app::Bq769xAppConfig config = [this] {
    fw::app::Bq769xAppConfig c{fw::app::kBq76952Settings, 16};
    c.faultIndicator = &faultOut;
    return c;
  }();
  App app{h.sched, bus, alert, can, config};

  explicit G3507(bool present = true) {
    if (present) bus.attach(0x08, emu);
    for (uint8_t c = 1; c <= 16; ++c)
      emu.setCellMv(c, 3700);
    app.start();
  }
  // End time of the first ALL_FETS_OFF on the wire at or after `fromUs`, or 0.
  uint64_t fetOffDoneUs(uint64_t fromUs) const {
    for (const auto& r : bus.wireLog())
      if (r.startUs >= fromUs && r.text.rfind(kAllFetsOff, 0) == 0 && r.status == fw::Status::Ok)
        return r.endUs;
    return 0;
  }
};

TEST(Bq769xApp, FaultOutputIsReleasedOnceProtectionHasMeasuredAHealthyPack) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_TRUE(b.app.monitor().running());
  EXPECT_FALSE(b.faultOut.level()) << "both paths on: no fault";
  b.emu.setCellMv(5, 4300);  // above the firmware limit (4250 mV)
  b.h.runFor(fw::ms(250));
  EXPECT_TRUE(b.faultOut.level()) << "cell over-voltage holds the paths off";
  EXPECT_FALSE(b.app.status().chargeOn || b.app.status().dischargeOn);
}

TEST(Bq769xApp, FaultOutputStaysAssertedWhileTheDeviceNeverAnswers) {
  G3507 b(false);
  b.h.runFor(fw::ms(2000));
  EXPECT_FALSE(b.app.monitor().running());
  EXPECT_TRUE(b.faultOut.level());
  for (const auto& [t, level] : b.faultOut.history())
    EXPECT_TRUE(level) << "released at " << t << " us without a measurement";
}

// A device that stops answering: every failed scan is one failed board measurement (three in a row, then the
// monitor probes instead of scanning), and the ProtectionEvent frames the comm-loss fault brings out say how
// many there have been.
TEST(Bq769xApp, ProtectionEventCountsTheFailedMeasurements) {
  G3507 b;
  b.h.runFor(fw::ms(1000));
  ASSERT_TRUE(b.app.monitor().running());
  ASSERT_EQ(b.app.monitor().stats().scanFailures, 0u);
  const size_t before = b.can.sent().size();
  b.emu.setMuted(true);
  b.h.runFor(fw::ms(1500));
  const uint32_t failures = b.app.monitor().stats().scanFailures;
  ASSERT_GE(failures, 3u);
  std::vector<uint16_t> counts;
  for (size_t i = before; i < b.can.sent().size(); ++i) {
    const auto& f = b.can.sent()[i].frame;
    if (f.id == fw::can::bms::ProtectionEvent::kId)
      counts.push_back(fw::can::bms::ProtectionEvent::unpack(f).commErrors);
  }
  ASSERT_FALSE(counts.empty()) << "comm loss trips a fault, which brings out ProtectionEvent";
  EXPECT_TRUE(std::is_sorted(counts.begin(), counts.end()));
  EXPECT_EQ(counts.back(), failures);
  EXPECT_EQ(b.app.pack().commErrors, failures);
}

// ALERT may come at any point of a scan. Swept over one scan period in 50 us steps, the FET-off command
// completes within 2 ms of the edge every time: a scan in progress gives way at its next read.
TEST(Bq769xApp, AlertToFetOffWithinTwoMillisecondsWhereverTheScanIs) {
  uint64_t worst = 0, worstAt = 0;
  for (uint64_t offset = 0; offset < 2600; offset += 50) {
    G3507 b;
    b.h.runFor(fw::ms(1000));  // a scan starts on every 100 ms tick
    ASSERT_TRUE(b.app.monitor().running());
    b.h.runFor(fw::us(static_cast<uint32_t>(offset)));
    const uint64_t t0 = b.h.nowUs();
    b.alert.drive(false);
    ASSERT_TRUE(b.h.runUntil([&] { return b.fetOffDoneUs(t0) != 0; }, fw::ms(20))) << "offset " << offset;
    const uint64_t took = b.fetOffDoneUs(t0) - t0;
    if (took > worst) worst = took, worstAt = offset;
    EXPECT_LE(took, 2000u) << "ALERT " << offset << " us into the scan period";
    // The scan that gave way is taken again right after the command: the data does not go stale.
    ASSERT_TRUE(b.h.runUntil([&] { return b.app.monitor().stats().scans > 10; }, fw::ms(200)));
  }
  std::printf("REPORT app.bq76952.alert_to_fet_off_worst_us=%llu (at %llu us into the period; budget 2000)\n",
              static_cast<unsigned long long>(worst), static_cast<unsigned long long>(worstAt));
}

}  // namespace
