// Commands on CAN as the G3507 images take them (the BQ76952 board of bq769x2/board.hpp: the application with
// the command task, the MCAN's filter modelled by the simulated controller): every command end to end, the
// checks and their answers, and the safety rules (firmware/app/command/handler.hpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bq769x2/board.hpp"
#include "can/bms.hpp"
#include "command_rig.hpp"
#include "commands/command_frames.hpp"

namespace {

namespace bms = fw::can::bms;
using command_rig::Rig;
using fw::app::FaultId;

constexpr uint8_t kAccepted = 0, kBadCrc = 1, kRepeated = 2, kWrongLength = 3, kOutOfRange = 4,
                  kInconsistent = 5, kUnsupported = 6, kWrongKey = 7, kBusy = 9, kConditionPresent = 10;

// A single discharge over-current does not latch (the third within the window does, below): it stays
// until its recovery, a charge for 3 s. ClearFaults is answered and never ends it earlier (a command never
// overrides protection); the recovery then goes out in ProtectionEvent.NewlyCleared.
TEST(Commands, ClearFaultsNeverEndsAnOverCurrentBeforeItsRecovery) {
  Rig r;
  // Tighten the discharge limit from -30 A to -20 A (its clear value, +200 mA, stays), then discharge at 25
  // A.
  EXPECT_EQ(r.ack("SettingWrite", {"Setting=ocd_trip", "Value=-20000"}).result, kAccepted);
  r.b.h.runFor(fw::ms(200));
  EXPECT_EQ(r.b.app.settings().limits().rules[3].trip, -20000);
  r.b.emu.setCurrentMa(-25000);
  ASSERT_TRUE(r.b.h.runUntil([&] { return r.active(FaultId::DischargeOvercurrent); }, fw::ms(500)));
  r.b.h.runFor(fw::ms(200));
  EXPECT_FALSE(r.b.app.status().dischargeOn);
  EXPECT_FALSE(r.b.emu.dsgFet());
  // While the current still flows, and once it has stopped, the clear changes nothing.
  EXPECT_EQ(r.ack("ClearFaults").result, kAccepted);
  r.b.h.runFor(fw::ms(300));
  EXPECT_TRUE(r.active(FaultId::DischargeOvercurrent));
  r.b.emu.setCurrentMa(0);
  r.b.h.runFor(fw::ms(500));
  EXPECT_EQ(r.ack("ClearFaults").result, kAccepted);
  r.b.h.runFor(fw::ms(500));
  EXPECT_TRUE(r.active(FaultId::DischargeOvercurrent));
  EXPECT_FALSE(r.b.emu.dsgFet());
  // The recovery: a charge.
  const size_t before = r.b.output.sent().size();
  r.b.emu.setCurrentMa(1000);
  ASSERT_TRUE(r.b.h.runUntil([&] { return r.b.emu.dsgFet(); }, fw::ms(4000)));
  r.b.h.runFor(fw::ms(200));  // the next publish slot
  EXPECT_FALSE(r.active(FaultId::DischargeOvercurrent));
  EXPECT_TRUE(r.b.app.status().dischargeOn);
  bool published = false;
  for (size_t k = before; k < r.b.output.sent().size(); ++k) {
    const auto& f = r.b.output.sent()[k].frame;
    if (f.id == bms::ProtectionEvent::kId)
      published |=
          (bms::ProtectionEvent::unpack(f).newlyCleared & fw::app::bit(FaultId::DischargeOvercurrent)) != 0;
  }
  EXPECT_TRUE(published);
}

// The third discharge over-current within the window latches (app/protection/default_limits.hpp): the
// discharge path stays off through 4 s of charge, the charge path on. ClearFaults while the current still
// flows is answered condition_present and changes nothing, nor does a PathRequest releasing the discharge
// path; once the current has gone ClearFaults is accepted, the fault clears and the DSG FET comes back on.
TEST(Commands, ClearFaultsEndsALatchedOverCurrentOnlyOnceTheCurrentIsGone) {
  Rig r;
  EXPECT_EQ(r.ack("SettingWrite", {"Setting=ocd_trip", "Value=-20000"}).result, kAccepted);
  r.b.h.runFor(fw::ms(200));
  for (int trip = 1; trip <= 3; ++trip) {
    r.b.emu.setCurrentMa(-25000);
    ASSERT_TRUE(r.b.h.runUntil([&] { return r.active(FaultId::DischargeOvercurrent); }, fw::ms(500))) << trip;
    r.b.emu.setCurrentMa(1000);  // the recovery: a charge for 3 s (trips 1 and 2)
    const bool recovered =
        r.b.h.runUntil([&] { return !r.active(FaultId::DischargeOvercurrent); }, fw::ms(4000));
    EXPECT_EQ(recovered, trip < 3) << trip;
  }
  ASSERT_TRUE(r.active(FaultId::DischargeOvercurrent));
  EXPECT_FALSE(r.b.emu.dsgFet());
  EXPECT_TRUE(r.b.emu.chgFet()) << "the charge path stays available";
  EXPECT_TRUE(r.b.app.status().chargeOn);
  r.b.emu.setCurrentMa(-25000);
  r.b.h.runFor(fw::ms(300));
  const auto refused = r.ack("ClearFaults");
  EXPECT_EQ(refused.result, kConditionPresent);
  EXPECT_EQ(refused.rejected, 1);
  EXPECT_EQ(r.ack("PathRequest", {"DischargeOff=release"}).result, kAccepted);
  r.b.h.runFor(fw::ms(500));
  EXPECT_TRUE(r.active(FaultId::DischargeOvercurrent));
  EXPECT_FALSE(r.b.emu.dsgFet()) << "no command turns on a path protection holds off";
  r.b.emu.setCurrentMa(0);
  r.b.h.runFor(fw::ms(300));
  EXPECT_EQ(r.ack("ClearFaults").result, kAccepted);
  ASSERT_TRUE(r.b.h.runUntil([&] { return r.b.emu.dsgFet(); }, fw::ms(300)));
  EXPECT_FALSE(r.active(FaultId::DischargeOvercurrent));
  r.b.h.runFor(fw::ms(200));
  EXPECT_TRUE(r.b.app.status().dischargeOn);
  EXPECT_EQ(r.ack("ClearFaults").result, kAccepted) << "nothing latched: nothing to refuse";
}

// BalancingMode reaches the balancing policy (app/balancing): off, then auto again; a forced mask the device
// allows is taken too (the policy applies it under its safety rules at the next scan).
TEST(Commands, BalancingModeSetsThePolicysMode) {
  Rig r;
  ASSERT_EQ(r.b.app.balancing().mode(), fw::app::BalancingMode::Auto);
  EXPECT_EQ(r.ack("BalancingMode", {"Mode=off"}).result, kAccepted);
  EXPECT_EQ(r.b.app.balancing().mode(), fw::app::BalancingMode::Off);
  EXPECT_EQ(r.ack("BalancingMode", {"Mode=forced", "Board=0", "CellMask=1"}).result, kAccepted);
  EXPECT_EQ(r.b.app.balancing().mode(), fw::app::BalancingMode::Forced);
  EXPECT_EQ(r.ack("BalancingMode", {"Mode=auto"}).result, kAccepted);
  EXPECT_EQ(r.b.app.balancing().mode(), fw::app::BalancingMode::Auto);
}

TEST(Commands, EachRefusalIsAnsweredCountedAndChangesNothing) {
  Rig r;
  const auto limits = r.b.app.settings().limits();
  // A wrong CRC.
  auto a = r.ack("SettingWrite", {"Setting=cell_ov_trip", "Value=4100", "Crc=0"});
  EXPECT_EQ(a.result, kBadCrc);
  EXPECT_EQ(a.rejected, 1);
  EXPECT_EQ(a.command, bms::SettingWrite::kId);
  // A repeated counter: the first frame is taken, the same counter again is not.
  EXPECT_EQ(r.ack("SettingRead", {"Setting=cell_ov_trip", "Counter=7"}).result, kAccepted);
  a = r.ack("SettingRead", {"Setting=cell_ov_trip", "Counter=7"});
  EXPECT_EQ(a.result, kRepeated);
  EXPECT_EQ(a.counter, 7);
  // A wrong length: a SettingWrite of 7 bytes (its CRC made right for those 7).
  std::string error;
  auto f = r.commands.build("SettingWrite", {"Setting=cell_ov_trip", "Value=4100"}, error);
  ASSERT_TRUE(f);
  f->dlc = 7;
  f->data[0] = fw::app::command::frameCrc(f->id, f->data.data(), f->dlc);
  r.answers();
  r.sendRaw(*f);
  r.b.h.runFor(fw::ms(20));
  auto got = r.answers();
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(bms::CommandAck::unpack(got[0]).result, kWrongLength);
  // Values out of range: past the hard bound, a setting that does not exist, a mode that does not.
  EXPECT_EQ(r.ack("SettingWrite", {"Setting=cell_ov_trip", "Value=4300"}).result, kOutOfRange);
  EXPECT_EQ(r.ack("SettingWrite", {"Setting=12", "Value=0"}).result, kOutOfRange);
  EXPECT_EQ(r.ack("SettingRead", {"Setting=200"}).result, kOutOfRange);
  EXPECT_EQ(r.ack("BalancingMode", {"Mode=3"}).result, kOutOfRange);
  EXPECT_EQ(r.ack("BalancingMode", {"Mode=forced", "Board=5", "CellMask=1"}).result, kOutOfRange);  // 1 board
  EXPECT_EQ(r.ack("SettingWrite", {"Setting=cell_ov_trip", "Value=4100"}).result, kInconsistent);
  a = r.ack("EnterBootloader", {"TraceId=0x5A5A1306", "Key=0x00"});
  EXPECT_EQ(a.result, kWrongKey);
  EXPECT_EQ(a.rejected, 10);
  r.b.h.runFor(fw::ms(300));
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(r.b.app.settings().limits().rules[k].trip, limits.rules[k].trip);
    EXPECT_EQ(r.b.app.settings().limits().rules[k].clear, limits.rules[k].clear);
  }
  EXPECT_TRUE(r.b.app.status().chargeOn && r.b.app.status().dischargeOn);
  EXPECT_TRUE(r.b.system.bootloaderEntries().empty());
  const auto& st = r.b.app.commands().handler().stats();
  EXPECT_EQ(st.rejected, 10);
  EXPECT_EQ(st.rejectedFor[kBadCrc], 1);
  EXPECT_EQ(st.rejectedFor[kOutOfRange], 5);  // with the forced mask on a board the pack does not have
  EXPECT_EQ(st.rejectedFor[kUnsupported], 0);
}

TEST(Commands, AFrameForAnotherNodeIsCountedAndNotAnswered) {
  Rig r;
  r.answers();
  r.send("ClearFaults", {"Target=7"});
  r.send("PathRequest", {"Target=2", "ChargeOff=1"});
  r.b.h.runFor(fw::ms(50));
  EXPECT_TRUE(r.answers().empty());
  EXPECT_EQ(r.b.app.commands().handler().stats().otherTarget, 2U);
  EXPECT_TRUE(r.b.app.status().chargeOn);
  EXPECT_EQ(r.ack("ClearFaults", {"Target=all"}).result, kAccepted);  // 255: every node
}

TEST(Commands, AnIdentifierThatIsNotACommandIsRejectedByTheFilterWithoutAnInterrupt) {
  Rig r;
  const uint64_t interrupts = r.b.output.receiveInterrupts();
  fw::hal::CanFrame f{0x608, false, 3, {}};  // after the last command (StorageMode 0x607)
  f.data[0] = fw::app::command::frameCrc(f.id, f.data.data(), f.dlc);
  f.data[2] = 1;
  r.sendRaw(f);
  r.sendRaw(fw::hal::CanFrame{0x100, false, 8, {}});       // telemetry of another node
  r.sendRaw(fw::hal::CanFrame{0x600 << 18, true, 3, {}});  // extended, with 0x600 in its base part
  r.b.h.runFor(fw::ms(50));
  EXPECT_EQ(r.b.output.receiveInterrupts(), interrupts);
  EXPECT_EQ(r.b.output.filteredOut(), 3U);
  EXPECT_EQ(r.b.app.commands().handler().stats().frames, 0U);
  EXPECT_TRUE(r.answers().empty());
}

TEST(Commands, APathRequestOpensPathsAndNeverTurnsOnOneProtectionHoldsOff) {
  Rig r;
  EXPECT_EQ(r.ack("PathRequest", {"ChargeOff=hold_off"}).result, kAccepted);
  ASSERT_TRUE(r.b.h.runUntil([&] { return !r.b.emu.chgFet(); }, fw::ms(300)));
  EXPECT_TRUE(r.b.emu.dsgFet());
  EXPECT_FALSE(r.b.app.status().chargeOn);
  EXPECT_EQ(r.ack("PathRequest", {"ChargeOff=release"}).result, kAccepted);
  ASSERT_TRUE(r.b.h.runUntil([&] { return r.b.emu.chgFet(); }, fw::ms(300)));
  // Over-voltage holds the charge path off: releasing every request and clearing turn it not on.
  r.b.emu.setCellMv(3, 4300);
  ASSERT_TRUE(r.b.h.runUntil([&] { return r.active(FaultId::CellOvervoltage); }, fw::ms(300)));
  r.b.h.runFor(fw::ms(50));
  EXPECT_EQ(r.ack("PathRequest", {"ChargeOff=release", "DischargeOff=release"}).result, kAccepted);
  EXPECT_EQ(r.ack("ClearFaults").result, kAccepted);
  r.b.h.runFor(fw::ms(500));
  EXPECT_FALSE(r.b.emu.chgFet());
  EXPECT_FALSE(r.b.app.status().chargeOn);
  EXPECT_TRUE(r.b.emu.dsgFet());  // over-voltage leaves discharge allowed
  // A request holds the path protection leaves on off: requests only ever open paths.
  EXPECT_EQ(r.ack("PathRequest", {"DischargeOff=hold_off"}).result, kAccepted);
  ASSERT_TRUE(r.b.h.runUntil([&] { return !r.b.emu.dsgFet(); }, fw::ms(300)));
  EXPECT_FALSE(r.b.emu.chgFet());
}

TEST(Commands, IdentifyAnswersVersionImageChipAndResetCause) {
  Rig r;
  r.answers();
  r.send("Identify");
  r.b.h.runFor(fw::ms(20));
  const auto a = r.answers();
  ASSERT_EQ(a.size(), 3U);
  EXPECT_EQ(bms::CommandAck::unpack(a[0]).result, kAccepted);
  const auto v = bms::IdentifyVersion::unpack(a[1]);
  EXPECT_EQ(v.node, 1);
  EXPECT_EQ(v.versionMajor, 0);
  EXPECT_EQ(v.versionMinor, 1);
  EXPECT_EQ(v.image, 0);  // a host build
  const auto c = bms::IdentifyChip::unpack(a[2]);
  EXPECT_EQ(c.traceId, 0x5A5A1306U);
  EXPECT_EQ(c.node, 1);
}

TEST(Commands, SettingReadAnswersValueUnitAndRange) {
  Rig r;
  r.answers();
  r.send("SettingRead", {"Setting=utd_clear"});
  r.b.h.runFor(fw::ms(20));
  const auto a = r.answers();
  ASSERT_EQ(a.size(), 3U);
  const auto v = bms::SettingValue::unpack(a[1]);
  EXPECT_EQ(v.setting, 11);
  EXPECT_EQ(v.unit, 2);  // 0.1 K
  EXPECT_EQ(v.value, 2582);
  EXPECT_EQ(v.source, 0) << "the image's default";
  const auto g = bms::SettingRange::unpack(a[2]);
  EXPECT_EQ(g.min, 2532);
  EXPECT_EQ(g.max, 3032);
}

// SettingValue.Source: the default until a command's write takes effect at a scan boundary, then command.
TEST(Commands, SettingReadAnswersWhereTheValueCameFrom) {
  Rig r;
  r.answers();
  ASSERT_EQ(r.ack("SettingWrite", {"Setting=ocd_trip", "Value=-20000"}).result, kAccepted);
  r.b.h.runFor(fw::ms(250));  // the next scan's evaluation applies it
  r.answers();
  r.send("SettingRead", {"Setting=ocd_trip"});
  r.b.h.runFor(fw::ms(20));
  auto a = r.answers();
  ASSERT_EQ(a.size(), 3U);
  auto v = bms::SettingValue::unpack(a[1]);
  EXPECT_EQ(v.value, -20000);
  EXPECT_EQ(v.source, 2) << "command";
  r.send("SettingRead", {"Setting=ocd_clear"});
  r.b.h.runFor(fw::ms(20));
  a = r.answers();
  ASSERT_EQ(a.size(), 3U);
  v = bms::SettingValue::unpack(a[1]);
  EXPECT_EQ(v.source, 0) << "its pair partner was not written: still the default";
}

// The record store (where built) writes what must survive just before the commanded reset: after the paths
// are off and the answer has left, before the restart (app/store/persistence.hpp beforeReset).
TEST(Commands, BootloaderEntryLetsTheRecordStoreWriteBeforeTheReset) {
  struct Store final : fw::app::BackgroundWork, fw::app::TripObserver {
    explicit Store(const Rig& r) : rig(r) {}
    void step() override {}
    void evaluated(fw::app::FaultMask, bool, fw::Instant) override {}
    void beforeReset() override {
      ++calls;
      resetsBefore = rig.b.system.bootloaderEntries().size();
      fetsOn = rig.b.emu.chgFet() || rig.b.emu.dsgFet();
    }
    const Rig& rig;
    int calls = 0;
    size_t resetsBefore = 99;
    bool fetsOn = true;
  };
  Rig r;
  Store store(r);
  r.b.app.attachStore(store, store);
  r.answers();
  r.send("EnterBootloader", {"TraceId=0x5A5A1306", "Key=key"});
  ASSERT_TRUE(r.b.h.runUntil([&] { return !r.b.system.bootloaderEntries().empty(); }, fw::ms(500)));
  EXPECT_EQ(store.calls, 1);
  EXPECT_EQ(store.resetsBefore, 0U) << "before the reset";
  EXPECT_FALSE(store.fetsOn) << "with the paths off";
}

TEST(Commands, BootloaderEntryOpensThePathsThenAnswersThenResets) {
  Rig r;
  r.answers();
  const uint64_t requestAt = r.b.h.nowUs();
  r.send("EnterBootloader", {"TraceId=0x5A5A1306", "Key=key"});
  // While the paths are being opened every other command is answered busy.
  r.b.h.runFor(fw::us(500));
  r.send("Identify");
  ASSERT_TRUE(r.b.h.runUntil([&] { return !r.b.system.bootloaderEntries().empty(); }, fw::ms(500)));
  const uint64_t resetAt = r.b.system.bootloaderEntries()[0];
  uint64_t ackAt = 0, fetsOffAt = 0;
  bool busy = false;
  for (const auto& s : r.b.output.sent()) {
    if (s.frame.id != bms::CommandAck::kId) continue;
    const auto a = bms::CommandAck::unpack(s.frame);
    if (a.command == bms::EnterBootloader::kId && a.result == kAccepted) ackAt = s.timeUs;
    if (a.command == bms::Identify::kId) busy = a.result == kBusy;
  }
  ASSERT_NE(ackAt, 0U);
  EXPECT_TRUE(busy);
  EXPECT_FALSE(r.b.emu.chgFet());
  EXPECT_FALSE(r.b.emu.dsgFet());
  for (const auto& [t, level] : r.b.faultOut.history()) {
    if (level && t >= requestAt) fetsOffAt = t;  // the fault indicator follows protection's request
  }
  ASSERT_NE(fetsOffAt, 0U);
  EXPECT_LT(fetsOffAt, ackAt);
  EXPECT_LT(ackAt, resetAt);
  std::printf(
      "REPORT commands.bootloader_entry: request to paths off %.2f ms, to the answer %.2f ms, to the "
      "reset %.2f ms (host, simulated time)\n",
      (fetsOffAt - requestAt) / 1000.0, (ackAt - requestAt) / 1000.0, (resetAt - requestAt) / 1000.0);
}

TEST(Commands, BootloaderEntryIsRefusedWhenThePathsCannotBeConfirmedOff) {
  Rig r;
  r.b.emu.setMuted(true);  // the device stops answering: no FET command can complete
  const auto a = [&] {
    r.answers();
    r.send("EnterBootloader", {"TraceId=0x5A5A1306", "Key=key"});
    r.b.h.runFor(fw::ms(1200));
    return r.answers();
  }();
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(bms::CommandAck::unpack(a.back()).result, 8);  // paths_not_off
  EXPECT_TRUE(r.b.system.bootloaderEntries().empty());
}

}  // namespace
