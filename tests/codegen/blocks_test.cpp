// The generated scan blocks (regmaps/*/commands.yaml `blocks:`) against the TRMs: every member's offset
// puts it at the direct-command address TI gives (SLUUBY2B chapter 12 for the BQ769x2, SLUUCJ0 "Direct
// Commands" for the BQ7690x; the addresses below are written from those tables, not read from the YAML), and
// is the member's descriptor address less the block's. Blocks lie back to back in the record.
#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>

#include "regmap/bq7690x.hpp"
#include "regmap/bq769x2.hpp"

namespace {

namespace x2 = fw::regmap::bq769x2;
namespace x0 = fw::regmap::bq7690x;

// One member: its generated offset, its descriptor's address and the TRM's address.
struct Member {
  unsigned offset;
  unsigned descriptorAddress;
  unsigned trmAddress;
};

template <class Block>
void expectMembers(std::initializer_list<Member> members) {
  for (const Member& m : members) {
    EXPECT_EQ(Block::address + m.offset, m.trmAddress) << "TRM address 0x" << std::hex << m.trmAddress;
    EXPECT_EQ(m.offset, m.descriptorAddress - Block::address) << "TRM address 0x" << std::hex << m.trmAddress;
  }
}

TEST(Bq769x2Blocks, MembersSitAtTheTrmAddresses) {
  using V = x2::blocks::PfStatusAndVoltages;
  expectMembers<V>({{V::offsetPfAlertA, x2::cmd::PfAlertA.address, 0x0A},
                    {V::offsetPfStatusA, x2::cmd::PfStatusA.address, 0x0B},
                    {V::offsetPfAlertB, x2::cmd::PfAlertB.address, 0x0C},
                    {V::offsetPfStatusB, x2::cmd::PfStatusB.address, 0x0D},
                    {V::offsetPfAlertC, x2::cmd::PfAlertC.address, 0x0E},
                    {V::offsetPfStatusC, x2::cmd::PfStatusC.address, 0x0F},
                    {V::offsetPfAlertD, x2::cmd::PfAlertD.address, 0x10},
                    {V::offsetPfStatusD, x2::cmd::PfStatusD.address, 0x11},
                    {V::offsetBatteryStatus, x2::cmd::BatteryStatus.address, 0x12},
                    {V::offsetCell1Voltage, x2::cmd::Cell1Voltage.address, 0x14},
                    {V::offsetCell2Voltage, x2::cmd::Cell2Voltage.address, 0x16},
                    {V::offsetCell8Voltage, x2::cmd::Cell8Voltage.address, 0x22},
                    {V::offsetCell16Voltage, x2::cmd::Cell16Voltage.address, 0x32},
                    {V::offsetStackVoltage, x2::cmd::StackVoltage.address, 0x34},
                    {V::offsetPackPinVoltage, x2::cmd::PackPinVoltage.address, 0x36},
                    {V::offsetLdPinVoltage, x2::cmd::LdPinVoltage.address, 0x38},
                    {V::offsetCc2Current, x2::cmd::Cc2Current.address, 0x3A}});
  EXPECT_EQ(V::address, 0x0A);
  EXPECT_EQ(V::size, 0x3C - 0x0A);  // through CC2 Current's high byte 0x3B
  using T = x2::blocks::AlarmsAndTemperatures;
  expectMembers<T>({{T::offsetAlarmStatus, x2::cmd::AlarmStatus.address, 0x62},
                    {T::offsetAlarmRawStatus, x2::cmd::AlarmRawStatus.address, 0x64},
                    {T::offsetAlarmEnable, x2::cmd::AlarmEnable.address, 0x66},
                    {T::offsetIntTemperature, x2::cmd::IntTemperature.address, 0x68},
                    {T::offsetCfetoffTemperature, x2::cmd::CfetoffTemperature.address, 0x6A},
                    {T::offsetDfetoffTemperature, x2::cmd::DfetoffTemperature.address, 0x6C},
                    {T::offsetAlertTemperature, x2::cmd::AlertTemperature.address, 0x6E},
                    {T::offsetTs1Temperature, x2::cmd::Ts1Temperature.address, 0x70},
                    {T::offsetTs2Temperature, x2::cmd::Ts2Temperature.address, 0x72},
                    {T::offsetTs3Temperature, x2::cmd::Ts3Temperature.address, 0x74}});
  EXPECT_EQ(T::size, 0x76 - 0x62);
  using S = x2::blocks::Safety;
  expectMembers<S>({{S::offsetSafetyAlertA, x2::cmd::SafetyAlertA.address, 0x02},
                    {S::offsetSafetyStatusA, x2::cmd::SafetyStatusA.address, 0x03},
                    {S::offsetSafetyAlertB, x2::cmd::SafetyAlertB.address, 0x04},
                    {S::offsetSafetyStatusB, x2::cmd::SafetyStatusB.address, 0x05},
                    {S::offsetSafetyAlertC, x2::cmd::SafetyAlertC.address, 0x06},
                    {S::offsetSafetyStatusC, x2::cmd::SafetyStatusC.address, 0x07}});
  EXPECT_EQ(S::size, 6);
  using F = x2::blocks::Fets;
  expectMembers<F>({{F::offsetFetStatus, x2::cmd::FetStatus.address, 0x7F}});
  EXPECT_EQ(F::size, 1);
}

TEST(Bq769x2Blocks, BlocksLieBackToBackInTheRecord) {
  using namespace x2::blocks;
  EXPECT_EQ(PfStatusAndVoltages::record, 0);
  EXPECT_EQ(AlarmsAndTemperatures::record, PfStatusAndVoltages::size);
  EXPECT_EQ(Safety::record, AlarmsAndTemperatures::record + AlarmsAndTemperatures::size);
  EXPECT_EQ(Fets::record, Safety::record + Safety::size);
  EXPECT_EQ(kRecordSize, Fets::record + Fets::size);
  EXPECT_EQ(kLargestSize, 50);  // 0x0A..0x3B
}

TEST(Bq7690xBlocks, MembersSitAtTheTrmAddresses) {
  using V = x0::blocks::StatusAndVoltages;
  expectMembers<V>({{V::offsetBatteryStatus, x0::cmd::BatteryStatus.address, 0x12},
                    {V::offsetCell1Voltage, x0::cmd::Cell1Voltage.address, 0x14},
                    {V::offsetCell5Voltage, x0::cmd::Cell5Voltage.address, 0x1C},
                    {V::offsetCell7Voltage, x0::cmd::Cell7Voltage.address, 0x20},
                    {V::offsetReg18Voltage, x0::cmd::Reg18Voltage.address, 0x22},
                    {V::offsetVssVoltage, x0::cmd::VssVoltage.address, 0x24},
                    {V::offsetStackVoltage, x0::cmd::StackVoltage.address, 0x26},
                    {V::offsetIntTemperature, x0::cmd::IntTemperature.address, 0x28},
                    {V::offsetTsMeasurement, x0::cmd::TsMeasurement.address, 0x2A}});
  EXPECT_EQ(V::size, 0x2C - 0x12);
  using A = x0::blocks::Alarms;
  expectMembers<A>({{A::offsetAlarmStatus, x0::cmd::AlarmStatus.address, 0x62},
                    {A::offsetAlarmRawStatus, x0::cmd::AlarmRawStatus.address, 0x64},
                    {A::offsetAlarmEnable, x0::cmd::AlarmEnable.address, 0x66}});
  EXPECT_EQ(A::size, 6);
  using C = x0::blocks::Current;
  expectMembers<C>({{C::offsetCc2Current, x0::cmd::Cc2Current.address, 0x3A}});
  EXPECT_EQ(C::size, 2);
  using S = x0::blocks::Safety;
  expectMembers<S>({{S::offsetSafetyAlertA, x0::cmd::SafetyAlertA.address, 0x02},
                    {S::offsetSafetyStatusA, x0::cmd::SafetyStatusA.address, 0x03},
                    {S::offsetSafetyAlertB, x0::cmd::SafetyAlertB.address, 0x04},
                    {S::offsetSafetyStatusB, x0::cmd::SafetyStatusB.address, 0x05}});
  EXPECT_EQ(S::size, 4);
}

TEST(Bq7690xBlocks, BlocksLieBackToBackInTheRecord) {
  using namespace x0::blocks;
  EXPECT_EQ(StatusAndVoltages::record, 0);
  EXPECT_EQ(Alarms::record, StatusAndVoltages::size);
  EXPECT_EQ(Current::record, Alarms::record + Alarms::size);
  EXPECT_EQ(Safety::record, Current::record + Current::size);
  EXPECT_EQ(kRecordSize, Safety::record + Safety::size);
  EXPECT_EQ(kLargestSize, 26);  // 0x12..0x2B
}

}  // namespace
