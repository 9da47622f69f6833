// Pack storage on the G3507-BQ76952 board (bq769x2/board.hpp, the bq76952-evm pack's `storage`: a scan every
// 1000 ms, device SLEEP allowed, by command only): the StorageMode command and its refusals, the device's
// SLEEP following it, leaving on its own on a load and on a fault, the automatic entry, and the age that
// StorageStatus publishes (firmware/app/monitors/storage_mode.hpp).
#include <gtest/gtest.h>

#include <optional>

#include "command_rig.hpp"

namespace {

namespace bms = fw::can::bms;
using command_rig::Rig;
using fw::app::FaultId;

constexpr uint8_t kAccepted = 0, kFaultActive = 11, kNotAtRest = 12;

// The last StorageStatus the board sent.
std::optional<bms::StorageStatus> lastStatus(const Rig& r) {
  const auto& sent = r.b.output.sent();
  for (auto it = sent.rbegin(); it != sent.rend(); ++it)
    if (it->frame.id == bms::StorageStatus::kId) return bms::StorageStatus::unpack(it->frame);
  return std::nullopt;
}

// Scans the monitor completes in `ms` of simulated time.
uint32_t scansIn(Rig& r, uint32_t ms) {
  const uint32_t before = r.b.app.monitor().stats().scans;
  r.b.h.runFor(fw::ms(ms));
  return r.b.app.monitor().stats().scans - before;
}

TEST(Storage, EnterScansEverySecondWithTheDeviceAsleepAndLeaveRestoresBoth) {
  Rig r;
  EXPECT_EQ(scansIn(r, 1000), 10U) << "100 ms scans before";
  ASSERT_FALSE(r.b.emu.sleepAllowed()) << "the set-up disallows SLEEP (SLEEP_DISABLE), as TI's examples";
  EXPECT_EQ(r.ack("StorageMode", {"Mode=enter"}).result, kAccepted);
  r.b.h.runFor(fw::ms(200));
  EXPECT_TRUE(r.b.app.pack().storage.on);
  EXPECT_TRUE(r.b.emu.sleepAllowed()) << "SLEEP_ENABLE sent and read back";
  const uint32_t scans = scansIn(r, 10000);
  EXPECT_GE(scans, 9U);
  EXPECT_LE(scans, 11U) << "one scan per 1000 ms storage period";
  EXPECT_TRUE(r.b.emu.sleeping()) << "the device entered SLEEP on its own, no current flowing";
  EXPECT_EQ(r.b.app.status().active, 0U) << "no stale_data: stale after three storage periods";
  EXPECT_TRUE(r.b.app.status().dischargeOn);
  auto st = lastStatus(r);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->mode, 1U);
  EXPECT_EQ(st->deviceSleep, 1U);
  EXPECT_EQ(st->scanPeriod, 1000U);
  // The worst case: the device's own 5 s SLEEP interval (Power:Sleep:Voltage Time, SLUUBY2B 7.3) on top of
  // the time since the scan (below one storage period).
  EXPECT_GE(st->measurementAge, 5000U);
  EXPECT_LT(st->measurementAge, 6100U);

  EXPECT_EQ(r.ack("StorageMode", {"Mode=leave"}).result, kAccepted);
  r.b.h.runFor(fw::ms(300));
  EXPECT_FALSE(r.b.app.pack().storage.on);
  EXPECT_FALSE(r.b.emu.sleepAllowed()) << "SLEEP_DISABLE sent and read back";
  EXPECT_EQ(scansIn(r, 1000), 10U) << "100 ms scans again";
  r.b.h.runFor(fw::ms(1000));
  st = lastStatus(r);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->mode, 0U);
  EXPECT_EQ(st->deviceSleep, 0U);
  EXPECT_EQ(st->scanPeriod, 100U);
  EXPECT_LT(st->measurementAge, 200U);
}

TEST(Storage, EnteringIsRefusedWhileCurrentFlowsOrAFaultIsActive) {
  Rig r;
  r.b.emu.setCurrentMa(-2000);  // a 2 A load, above the pack's 50 mA rest threshold
  r.b.h.runFor(fw::ms(300));
  EXPECT_EQ(r.ack("StorageMode", {"Mode=enter"}).result, kNotAtRest);
  r.b.emu.setCurrentMa(0);
  r.b.emu.setCellMv(3, 4260);  // over the firmware's 4250 mV, under the device's own COV
  r.b.h.runFor(fw::ms(500));
  ASSERT_TRUE(r.active(FaultId::CellOvervoltage));
  EXPECT_EQ(r.ack("StorageMode", {"Mode=enter"}).result, kFaultActive);
  r.b.h.runFor(fw::ms(500));
  EXPECT_FALSE(r.b.app.pack().storage.on);
  EXPECT_FALSE(r.b.emu.sleepAllowed());
  EXPECT_EQ(r.ack("StorageMode", {"Mode=leave"}).result, kAccepted) << "leaving is always accepted";
}

// A load wakes the device (current above Sleep Current, SLUUBY2B 7.3) and the next storage scan, seeing it
// above the rest threshold, ends storage: 100 ms scans and no SLEEP from then on.
TEST(Storage, ALoadEndsStorageAtTheNextStorageScan) {
  Rig r;
  EXPECT_EQ(r.ack("StorageMode", {"Mode=enter"}).result, kAccepted);
  r.b.h.runFor(fw::ms(3000));
  ASSERT_TRUE(r.b.app.pack().storage.on);
  ASSERT_TRUE(r.b.emu.sleeping());
  r.b.emu.setCurrentMa(-2000);
  EXPECT_FALSE(r.b.emu.sleeping()) << "the device woke on the current";
  r.b.h.runFor(fw::ms(1100));
  EXPECT_FALSE(r.b.app.pack().storage.on);
  r.b.h.runFor(fw::ms(100));
  EXPECT_FALSE(r.b.emu.sleepAllowed());
  EXPECT_EQ(scansIn(r, 1000), 10U);
  r.b.emu.setCurrentMa(0);
  r.b.h.runFor(fw::ms(3000));
  EXPECT_FALSE(r.b.app.pack().storage.on) << "by command only (auto_entry_min 0): not again on its own";
}

// Storage never overrides protection: a cell over its limit trips at a storage scan (in SLEEP the device
// measures every 5 s, so within 5 s and a storage period), protection opens the charge path, and storage
// ends.
TEST(Storage, AFaultEndsStorageAndProtectionActs) {
  Rig r;
  EXPECT_EQ(r.ack("StorageMode", {"Mode=enter"}).result, kAccepted);
  r.b.h.runFor(fw::ms(2000));
  ASSERT_TRUE(r.b.app.pack().storage.on);
  r.b.emu.setCellMv(5, 4270);
  r.b.h.runFor(fw::ms(8000));
  EXPECT_TRUE(r.active(FaultId::CellOvervoltage));
  EXPECT_FALSE(r.b.app.pack().storage.on);
  EXPECT_FALSE(r.b.emu.chgFet()) << "charge path opened";
  EXPECT_FALSE(r.b.emu.sleepAllowed());
  EXPECT_EQ(scansIn(r, 1000), 10U);
}

// The automatic entry (a pack file's auto_entry_min; here 3 s of scan periods on the board's config): at rest
// that long, storage begins on its own; current starts the count again.
TEST(Storage, AutomaticEntryAfterTheRestTime) {
  Rig r;
  r.b.config.storage.autoEntryPeriods = 30;
  r.b.emu.setCurrentMa(-1000);
  r.b.h.runFor(fw::ms(5000));
  EXPECT_FALSE(r.b.app.pack().storage.on) << "not at rest";
  r.b.emu.setCurrentMa(0);
  r.b.h.runFor(fw::ms(2500));
  EXPECT_FALSE(r.b.app.pack().storage.on) << "not yet 3 s at rest";
  r.b.h.runFor(fw::ms(1000));
  EXPECT_TRUE(r.b.app.pack().storage.on);
  EXPECT_TRUE(r.b.emu.sleepAllowed());
}

// ALERT ends storage without waiting for the next storage scan: a 45 A short trips the device's OCD1 (40 A,
// its comparator runs in SLEEP as in NORMAL, SLUUBY2B 7.3), ALERT makes protection open the FETs at once, the
// FET command is followed by a scan (bq769x_app.hpp commandPosted), and that scan's current, or the device's
// fault at the next scan period, ends storage: well before the next storage scan. (AFaultEndsStorage... is
// the one that fails without the fault rule: here the scan after the command sees the current as well.)
TEST(Storage, AlertEndsStorageBeforeTheNextStorageScan) {
  Rig r;
  EXPECT_EQ(r.ack("StorageMode", {"Mode=enter"}).result, kAccepted);
  r.b.h.runFor(fw::ms(2500));
  ASSERT_TRUE(r.b.app.pack().storage.on);
  const uint32_t scans = r.b.app.monitor().stats().scans;
  ASSERT_TRUE(r.b.h.runUntil([&] { return r.b.app.monitor().stats().scans != scans; }, fw::ms(1100)));
  r.b.h.runFor(fw::ms(20));  // just after a storage scan: the next one is most of a second away
  r.b.emu.setCurrentMa(-45000);
  r.b.h.runFor(fw::ms(250));
  EXPECT_NE(r.b.app.status().active & fw::app::bit(FaultId::DeviceSafety), 0U) << "ALERT: the device's fault";
  EXPECT_FALSE(r.b.app.pack().storage.on) << "ended within a scan period of the fault, not at the next scan";
  EXPECT_FALSE(r.b.emu.dsgFet());
}

}  // namespace
