// The generated CAN packers: seed 001's TI frames byte for byte, the native layout's bit positions, and
// round trips at the limits of every field.
#include <gtest/gtest.h>

#include <array>

#include "app/publish/can_bits.hpp"
#include "can/bms.hpp"

namespace {

using namespace fw::can::bms;
using Bytes = std::array<uint8_t, 8>;

TEST(CanCatalogue, TiLayoutReproducesSeed001Frames) {
  // Seed 001, figure 4-5: the first two boards' frames as the CAN analyser shows them (ID 0x4, 8 bytes).
  const uint16_t frames[4][4] = {{0x16C0, 0x16BC, 0x16B4, 0x16B9},
                                 {0x16B4, 0x16B9, 0x16B4, 0x16B8},
                                 {0x16B1, 0x16B8, 0x16B2, 0x16B2},
                                 {0x16B5, 0x16AE, 0x16B4, 0x16A9}};
  const Bytes expected[4] = {{0x16, 0xC0, 0x16, 0xBC, 0x16, 0xB4, 0x16, 0xB9},
                             {0x16, 0xB4, 0x16, 0xB9, 0x16, 0xB4, 0x16, 0xB8},
                             {0x16, 0xB1, 0x16, 0xB8, 0x16, 0xB2, 0x16, 0xB2},
                             {0x16, 0xB5, 0x16, 0xAE, 0x16, 0xB4, 0x16, 0xA9}};
  for (int k = 0; k < 4; ++k) {
    TiCellVoltages m;
    for (int i = 0; i < 4; ++i)
      m.vCell[i] = static_cast<int16_t>(frames[k][i]);
    const auto f = m.pack();
    EXPECT_EQ(f.id, 0x004u);
    EXPECT_FALSE(f.extended);
    EXPECT_EQ(f.dlc, 8);
    EXPECT_EQ(f.data, expected[k]) << "frame " << k;
  }
}

TEST(CanCatalogue, NativeCellFrameCarriesBoardFrameIndexAndStatus) {
  CellVoltages m;
  m.board = 0x2A;
  m.frameIndex = 5;
  m.status = 2;
  m.cell[0] = 3700;  // 0x0E74
  m.cell[1] = 0xFFFF;
  m.cell[2] = 0x0102;
  const auto f = m.pack();
  EXPECT_EQ(f.id, 0x200u);
  EXPECT_EQ(f.data, (Bytes{0x2A, 0x25, 0x74, 0x0E, 0xFF, 0xFF, 0x02, 0x01}));
  static_assert(CellVoltages::kFrames == 6 && CellVoltages::kCellPerFrame == 3 &&
                CellVoltages::kCellTotal == 16);
}

TEST(CanCatalogue, PackSummaryBitFieldsAndSignedCurrent) {
  PackSummary m;
  m.packVoltage = 4812;   // 48.12 V
  m.packCurrent = -1234;  // -12.34 A
  m.stateOfCharge = 255;
  m.chargeFet = 1;
  m.dischargeFet = 0;
  m.faultOutput = 1;
  m.dataValid = 1;
  m.counter = 0xF;
  m.activeFaults = 0x0101;
  const auto f = m.pack();
  // Byte 5: ChargeFet 1 (bits 40-41), DischargeFet 0 (42-43), Counter 15 (44-47); bytes 6-7: ActiveFaults
  // 0x0101 (48-61), FaultOutput (62), DataValid (63).
  EXPECT_EQ(f.data, (Bytes{0xCC, 0x12, 0x2E, 0xFB, 0xFF, 0xF1, 0x01, 0xC1}));
  const auto back = PackSummary::unpack(f);
  EXPECT_EQ(back.packCurrent, -1234);
  EXPECT_EQ(back.counter, 0xF);
  EXPECT_EQ(back.activeFaults, 0x0101);
  EXPECT_EQ(PackSummary::kChargeFetNotAvailable, 3) << "a path nothing confirmed goes out as 3";
}

TEST(CanCatalogue, StateOfChargeBitFields) {
  StateOfCharge m;
  m.soc = 437;                     // 43.7 %, bits 0-15
  m.remainingCapacity = 0x12345;   // 74 565 mAh, bits 16-35
  m.fullChargeCapacity = 0xFFFFE;  // 1 048 574 mAh, the largest a pack file takes, bits 36-55
  m.basis = 1;                     // ocv, bits 56-59
  const auto f = m.pack();
  EXPECT_EQ(f.id, 0x104u);
  EXPECT_EQ(f.data, (Bytes{0xB5, 0x01, 0x45, 0x23, 0xE1, 0xFF, 0xFF, 0x01}));
  const auto back = StateOfCharge::unpack(f);
  EXPECT_EQ(back.soc, 437);
  EXPECT_EQ(back.remainingCapacity, 0x12345u);
  EXPECT_EQ(back.fullChargeCapacity, 0xFFFFEu);
  EXPECT_EQ(back.basis, 1);
  static_assert(StateOfCharge::kCycleMs == 1000 && StateOfCharge::kSocNotAvailable == 0xFFFF &&
                StateOfCharge::kRemainingCapacityNotAvailable == 0xFFFFF);
}

TEST(CanCatalogue, RoundTripsAtFieldLimits) {
  TiCellVoltages ti;
  ti.vCell[0] = INT16_MIN;
  ti.vCell[1] = INT16_MAX;
  ti.vCell[2] = -1;
  ti.vCell[3] = 0;
  const auto tb = TiCellVoltages::unpack(ti.pack());
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(tb.vCell[i], ti.vCell[i]);

  Temperatures t;
  t.board = 255;
  t.frameIndex = 15;
  t.status = 15;
  t.temp[0] = 0;
  t.temp[1] = 65535;
  t.temp[2] = 2982;
  const auto back = Temperatures::unpack(t.pack());
  EXPECT_EQ(back.board, 255);
  EXPECT_EQ(back.frameIndex, 15);
  EXPECT_EQ(back.status, 15);
  EXPECT_EQ(back.temp[1], 65535);
  EXPECT_EQ(back.temp[2], 2982);
}

TEST(CanCatalogue, PackingIsConstexpr) {
  constexpr auto f = [] {
    CellExtremes m;
    m.maxCellVoltage = 4200;
    m.minCellIndex = 1023;
    return m.pack();
  }();
  static_assert(f.data[0] == 0x68 && f.data[1] == 0x10 && f.data[6] == 0xFF && f.data[7] == 0x03);
  SUCCEED();
}

// The firmware packs its own frames (FramePlan's messages, the command answers) from stream codes, one byte
// a field: for every such message, with every field at its all-ones value and with a mixed pattern (bits
// above a field's length included, which must be dropped), the bytes equal the Field-table packer's, which
// the DBC check holds against an independent reader.
template <class M>
void expectStreamPackedLikeFields() {
  static constexpr auto kCodes = fw::can::streamCodes<M>();
  for (const uint32_t seed : {0xFFFFFFFFu, 0xA5C3F00Fu, 0x12345678u, 0u}) {
    uint32_t values[M::kFieldCount];
    for (size_t i = 0; i < M::kFieldCount; ++i)
      values[i] = seed ^ (0x9E3779B9u * static_cast<uint32_t>(i));
    Bytes fromFields{}, fromCodes{};
    fromCodes.fill(0xEE);  // every byte is written
    fw::can::pack(fromFields, M::kFields, values, M::kFieldCount);
    fw::can::packStream(fromCodes, kCodes.data(), values, M::kFieldCount);
    EXPECT_EQ(fromCodes, fromFields) << "message 0x" << std::hex << M::kId << " seed 0x" << seed;
  }
}

TEST(CanCatalogue, StreamCodesPackTheSameBytesAsTheFieldTables) {
  expectStreamPackedLikeFields<PackSummary>();
  expectStreamPackedLikeFields<CellExtremes>();
  expectStreamPackedLikeFields<ProtectionEvent>();
  expectStreamPackedLikeFields<Startup>();
  expectStreamPackedLikeFields<CellVoltages>();
  expectStreamPackedLikeFields<Temperatures>();
  expectStreamPackedLikeFields<TemperatureExtremes>();
  expectStreamPackedLikeFields<StateOfCharge>();
  expectStreamPackedLikeFields<BalancingStatus>();
  expectStreamPackedLikeFields<TiCellVoltages>();
  expectStreamPackedLikeFields<CommandAck>();
  expectStreamPackedLikeFields<IdentifyVersion>();
  expectStreamPackedLikeFields<IdentifyChip>();
  expectStreamPackedLikeFields<SettingValue>();
  expectStreamPackedLikeFields<SettingRange>();
}

}  // namespace
