// BQ79616 frame codec against TI's published frames (SLUUC56B / SLUAA17A) and against a CRC
// computed here bit by bit (not with fw::crc), so a wrong table or byte order in the firmware cannot agree
// with itself.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "drivers/bq79616/frame.hpp"
#include "regmap/bq79616.hpp"
#include "ti_vectors.hpp"

namespace {

namespace bq = fw::drivers::bq79616;
using bq::RequestType;
using fw::Status;

// CRC-16/MODBUS, one bit at a time: reflected polynomial 0xA001, init 0xFFFF (CRC-16/MODBUS, as TI's
// example's table).
uint16_t crcBitwise(const std::vector<uint8_t>& bytes) {
  uint16_t crc = 0xFFFF;
  for (uint8_t b : bytes) {
    crc ^= b;
    for (int i = 0; i < 8; ++i)
      crc = (crc & 1) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : static_cast<uint16_t>(crc >> 1);
  }
  return crc;
}

std::vector<uint8_t> withCrc(std::vector<uint8_t> body) {
  const uint16_t crc = crcBitwise(body);
  body.push_back(static_cast<uint8_t>(crc));
  body.push_back(static_cast<uint8_t>(crc >> 8));
  return body;
}

std::vector<uint8_t> encode(const test::TiVector& v) {
  std::array<uint8_t, bq::kMaxCommandBytes> out{};
  const size_t n = bq::isRead(v.type) ? bq::encodeRead(v.type, v.device, v.reg, v.data[0], out)
                                      : bq::encodeWrite(v.type, v.device, v.reg, v.data, out);
  return {out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n)};
}

TEST(Bq79616Frame, EverySection3FrameIsByteExact) {
  for (const auto& v : test::tiVectors()) {
    EXPECT_EQ(test::hexLine("TX", encode(v)), test::hexLine("TX", v.bytes)) << v.what;
  }
}

TEST(Bq79616Frame, Section3CrcsAgreeWithAnIndependentCrc) {
  // Guards the vectors themselves: each is its body plus the bitwise CRC, low byte first.
  for (const auto& v : test::tiVectors()) {
    std::vector<uint8_t> body(v.bytes.begin(), v.bytes.end() - 2);
    EXPECT_EQ(withCrc(body), v.bytes) << v.what;
  }
}

TEST(Bq79616Frame, Section3AddressesMatchTheGeneratedRegisterMap) {
  namespace r = fw::regmap::bq79616::reg;
  static_assert(r::Control1.address == 0x309 && r::Dir0Addr.address == 0x306 && r::CommCtrl.address == 0x308);
  static_assert(r::OtpEccDatain1.address == 0x343 && r::FaultRst1.address == 0x331 &&
                r::FaultRst2.address == 0x332);
  static_assert(r::FaultMsk2.address == 0x017 && r::CustCrcRsltHi.address == 0x50C &&
                r::ActiveCell.address == 0x003);
  static_assert(r::AdcConf1.address == 0x007 && r::AdcCtrl1.address == 0x30D &&
                r::Vcell16Hi.address == 0x568);
  SUCCEED();
}

TEST(Bq79616Frame, InitByteForAllSevenRequestTypes) {
  EXPECT_EQ(bq::initByte(RequestType::SingleRead, 0), 0x80);
  EXPECT_EQ(bq::initByte(RequestType::StackRead, 0), 0xA0);
  EXPECT_EQ(bq::initByte(RequestType::BroadcastRead, 0), 0xC0);
  for (size_t len = 1; len <= 8; ++len) {
    const auto low = static_cast<uint8_t>(len - 1);
    EXPECT_EQ(bq::initByte(RequestType::SingleWrite, len), 0x90 | low);
    EXPECT_EQ(bq::initByte(RequestType::StackWrite, len), 0xB0 | low);
    EXPECT_EQ(bq::initByte(RequestType::BroadcastWrite, len), 0xD0 | low);
    // TI's example adds the length only when bit 4 of the type is set, which the reverse type (0x60) lacks.
    EXPECT_EQ(bq::initByte(RequestType::BroadcastWriteReverse, len), 0xE0 | low) << len;
  }
}

TEST(Bq79616Frame, ReverseBroadcastWriteCarriesItsLength) {
  std::array<uint8_t, bq::kMaxCommandBytes> out{};
  const std::vector<uint8_t> data = {0x80, 0x00, 0x12};
  const size_t n = bq::encodeWrite(RequestType::BroadcastWriteReverse, 0, 0x309, data, out);
  ASSERT_EQ(n, 8u);
  EXPECT_EQ(std::vector<uint8_t>(out.begin(), out.begin() + 8),
            withCrc({0xE2, 0x03, 0x09, 0x80, 0x00, 0x12}));
}

TEST(Bq79616Frame, EightByteWriteAndMaximumRead) {
  std::array<uint8_t, bq::kMaxCommandBytes> out{};
  const std::vector<uint8_t> data = {1, 2, 3, 4, 5, 6, 7, 8};
  ASSERT_EQ(bq::encodeWrite(RequestType::SingleWrite, 63, 0x318, data, out), 14u);
  EXPECT_EQ(std::vector<uint8_t>(out.begin(), out.end()),
            withCrc({0x97, 0x3F, 0x03, 0x18, 1, 2, 3, 4, 5, 6, 7, 8}));
  ASSERT_EQ(bq::encodeRead(RequestType::StackRead, 0, 0x568, 128, out), 6u);
  EXPECT_EQ(std::vector<uint8_t>(out.begin(), out.begin() + 6), withCrc({0xA0, 0x05, 0x68, 0x7F}));
}

TEST(Bq79616Frame, MalformedRequestsEncodeNothing) {
  std::array<uint8_t, bq::kMaxCommandBytes> out{};
  out.fill(0xAA);
  const std::vector<uint8_t> nine(9, 0);
  const std::vector<uint8_t> one = {0};
  EXPECT_EQ(bq::encodeWrite(RequestType::BroadcastWrite, 0, 0x309, {}, out), 0u);
  EXPECT_EQ(bq::encodeWrite(RequestType::BroadcastWrite, 0, 0x309, nine, out), 0u);
  EXPECT_EQ(bq::encodeWrite(RequestType::SingleWrite, 64, 0x309, one, out), 0u);
  EXPECT_EQ(bq::encodeWrite(RequestType::SingleRead, 0, 0x309, one, out), 0u);
  EXPECT_EQ(bq::encodeRead(RequestType::BroadcastWrite, 0, 0x309, 1, out), 0u);
  EXPECT_EQ(bq::encodeRead(RequestType::BroadcastRead, 0, 0x568, 0, out), 0u);
  EXPECT_EQ(bq::encodeRead(RequestType::BroadcastRead, 0, 0x568, 129, out), 0u);  // TI refused > 128 too
  EXPECT_EQ(bq::encodeRead(RequestType::SingleRead, 64, 0x568, 1, out), 0u);
  std::array<uint8_t, 6> small{};
  EXPECT_EQ(bq::encodeRead(RequestType::SingleRead, 1, 0x306, 1, small), 0u);  // needs 7 bytes
  for (uint8_t b : out)
    EXPECT_EQ(b, 0xAA) << "a refused frame writes nothing";
}

// --- responses ---------------------------------------------------------------------------------------------

std::vector<uint8_t> response(uint8_t device, uint16_t reg, std::vector<uint8_t> data) {
  std::vector<uint8_t> f = {static_cast<uint8_t>(data.size() - 1), device, static_cast<uint8_t>(reg >> 8),
                            static_cast<uint8_t>(reg)};
  f.insert(f.end(), data.begin(), data.end());
  return withCrc(f);
}

TEST(Bq79616Frame, ParsesAValidResponse) {
  const auto f = response(1, 0x306, {0x01});
  bq::ResponseFrame out;
  ASSERT_EQ(bq::parseResponse(f, 0x306, 1, out), Status::Ok);
  EXPECT_EQ(out.device, 1);
  EXPECT_EQ(out.reg, 0x306);
  ASSERT_EQ(out.data.size(), 1u);
  EXPECT_EQ(out.data[0], 0x01);
}

TEST(Bq79616Frame, NamesEachWayAResponseCanBeWrong) {
  bq::ResponseFrame out;
  auto f = response(1, 0x306, {0x01});
  EXPECT_EQ(bq::parseResponse(std::span(f).first(f.size() - 1), 0x306, 1, out), Status::Truncated);
  auto flipped = f;
  flipped[4] ^= 0x10;
  EXPECT_EQ(bq::parseResponse(flipped, 0x306, 1, out), Status::Crc);
  auto badCrc = f;
  badCrc[5] ^= 0x01;
  EXPECT_EQ(bq::parseResponse(badCrc, 0x306, 1, out), Status::Crc);
  // Intact frame, but of another length than the read asked for.
  const auto two = response(1, 0x306, {0x01, 0x02});
  EXPECT_EQ(bq::parseResponse(two, 0x306, 1, out), Status::Length);
  EXPECT_EQ(bq::parseResponse(response(1, 0x306, {0x01}), 0x306, 2, out), Status::Truncated);
  // Intact, but from another register, or with the reserved device-address bits set.
  EXPECT_EQ(bq::parseResponse(response(1, 0x307, {0x01}), 0x306, 1, out), Status::DeviceId);
  EXPECT_EQ(bq::parseResponse(response(0x41, 0x306, {0x01}), 0x306, 1, out), Status::DeviceId);
}

TEST(Bq79616Frame, SplitsABroadcastResponseTopOfStackFirst) {
  // Three devices answering VCELL16_HI.. (2 bytes): the top (address 2) first, the base last.
  std::vector<uint8_t> rx;
  for (uint8_t dev : {2, 1, 0}) {
    const auto f = response(dev, 0x568, {static_cast<uint8_t>(0x16), static_cast<uint8_t>(0xC0 + dev)});
    rx.insert(rx.end(), f.begin(), f.end());
  }
  ASSERT_EQ(rx.size(), 3 * bq::responseSize(2));
  for (size_t i = 0; i < 3; ++i) {
    bq::ResponseFrame out;
    ASSERT_EQ(bq::parseResponse(std::span(rx).subspan(i * bq::responseSize(2)), 0x568, 2, out), Status::Ok);
    EXPECT_EQ(out.device, 2 - i);
    EXPECT_EQ(out.data[1], 0xC0 + (2 - i));
  }
  // The CRC over each whole frame checks to zero (the receiver's test, SLUSE81E).
  EXPECT_EQ(crcBitwise(std::vector<uint8_t>(rx.begin(), rx.begin() + 8)), 0);
}

TEST(Bq79616Frame, Section7CellFrameLayout) {
  // SLUSE81E response frame, TI's example's reading: per-board response [0]=0x1F, [1]=dev, [2..3]=05 68,
  // [4..35] cells 16..1, [36..37] CRC.
  std::vector<uint8_t> cells(32);
  cells[0] = 0x16;
  cells[1] = 0xC0;  // VCELL16 = 0x16C0 = 5824 LSB = 1110.8 mV (app note figure 4-5)
  const auto f = response(1, 0x568, cells);
  ASSERT_EQ(f.size(), 38u);
  EXPECT_EQ(f[0], 0x1F);
  bq::ResponseFrame out;
  ASSERT_EQ(bq::parseResponse(f, 0x568, 32, out), Status::Ok);
  EXPECT_EQ((out.data[0] << 8) | out.data[1], 0x16C0);
}

}  // namespace

namespace {

namespace bits = fw::regmap::bq79616::bits;
namespace enums = fw::regmap::bq79616::enums;

// Issue 12 item 9: the register map's fields against the datasheet's bit positions and TI's example literals.
// Fails on the map before the fix (LPF_VCELL_EN at bit 4: the fields built 0x16, not TI's 0x0E).
TEST(Bq79616RegisterFields, AdcCtrl1BuildsTisLiteral) {
  // SLUSF21 ADC_CTRL1: LPF_BB_EN 4, LPF_VCELL_EN 3, MAIN_GO 2, MAIN_MODE 1:0 (10 = continuous). TI's example
  // writes 0x0E "continuous run, LPF enabled, MAIN_GO".
  const auto v = bits::AdcCtrl1{}.with_lpf_vcell_en(true).with_main_go(true).with_main_mode(
      enums::MainAdcMode::Continuous);
  EXPECT_EQ(v.raw(), 0x0E);
  const auto ti = bits::AdcCtrl1::fromRaw(0x0E);
  EXPECT_TRUE(ti.lpf_vcell_en());
  EXPECT_FALSE(ti.lpf_bb_en());
  EXPECT_TRUE(ti.main_go());
  EXPECT_EQ(ti.main_mode(), enums::MainAdcMode::Continuous);
}

TEST(Bq79616RegisterFields, FaultAndStatusBitsAreTheDatasheets) {
  EXPECT_EQ(bits::FaultSys::drst_mask, 0x10);                       // SLUSF21 FAULT_SYS bit 4
  EXPECT_EQ(bits::FaultOtp::cust_crc_mask, 0x10);                   // SLUSF21 FAULT_OTP bit 4
  EXPECT_EQ(bits::DevStat::cust_crc_done_mask, 0x20);               // SLUSF21 DEV_STAT bit 5
  EXPECT_EQ(bits::DevStat::main_run_mask, 0x01);                    // SLUSF21 DEV_STAT bit 0
  EXPECT_EQ(bits::FaultMsk2{}.with_msk_otp_crc(true).raw(), 0x40);  // TI's example: FAULT_MSK2 = 0x40
  EXPECT_EQ(bits::FaultRst2::rst_otp_crc_mask, 0x40);               // the same position in FAULT_RST2
}

}  // namespace
