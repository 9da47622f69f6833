// The stored records' payload encodings: fixed sizes, little-endian, round trips, refusal of other lengths.
#include "app/store/records.hpp"

#include <gtest/gtest.h>

#include <array>

using namespace fw::app::store;

TEST(StoreRecords, SettingsRoundTripLittleEndian) {
  SettingsRecord r;
  for (uint32_t k = 0; k < r.value.size(); ++k)
    r.value[k] = static_cast<int32_t>(k * 1000) - 7000;
  std::array<uint8_t, SettingsRecord::kBytes> b{};
  encode(r, b);
  EXPECT_EQ(b[0], 0xA8);  // -7000 = 0xFFFFE4A8, low byte first
  EXPECT_EQ(b[3], 0xFF);
  SettingsRecord back;
  ASSERT_TRUE(decode(b, back));
  EXPECT_EQ(back.value, r.value);
  EXPECT_FALSE(decode(std::span<const uint8_t>(b.data(), b.size() - 1), back));
}

TEST(StoreRecords, ProtectionLogRoundTrip) {
  ProtectionLogRecord r;
  r.count = 3;
  r.entry[0] = {1, 3600, 4250};
  r.entry[1] = {3, 7200, -30000};
  r.entry[2] = {11, 86400, 2731};
  std::array<uint8_t, ProtectionLogRecord::kBytes> b{};
  encode(r, b);
  ProtectionLogRecord back;
  ASSERT_TRUE(decode(b, back));
  EXPECT_EQ(back.count, 3);
  for (uint32_t k = 0; k < 3; ++k) {
    EXPECT_EQ(back.entry[k].rule, r.entry[k].rule);
    EXPECT_EQ(back.entry[k].uptimeS, r.entry[k].uptimeS);
    EXPECT_EQ(back.entry[k].value, r.entry[k].value);
  }
  b[0] = ProtectionLogRecord::kEntries + 1;  // more entries than the record holds: refused
  EXPECT_FALSE(decode(b, back));
}

TEST(StoreRecords, FaultAndSocRoundTrip) {
  FaultRecord f{0x0C, 0xBEEF, 0x0000'12A4, 99, 30};
  std::array<uint8_t, FaultRecord::kBytes> fb{};
  encode(f, fb);
  EXPECT_EQ(fb[1], 30);  // the module, in what was the padding byte
  EXPECT_EQ(fb[2], 0xEF);
  EXPECT_EQ(fb[3], 0xBE);
  FaultRecord fback;
  ASSERT_TRUE(decode(fb, fback));
  EXPECT_EQ(fback.resetCause, 0x0C);
  EXPECT_EQ(fback.code, 0xBEEF);
  EXPECT_EQ(fback.pc, 0x12A4U);
  EXPECT_EQ(fback.uptimeS, 99U);
  EXPECT_EQ(fback.module, 30);

  SocRecord s{734, 41250};
  std::array<uint8_t, SocRecord::kBytes> sb{};
  encode(s, sb);
  SocRecord sback;
  ASSERT_TRUE(decode(sb, sback));
  EXPECT_EQ(sback.permille, 734);
  EXPECT_EQ(sback.remainingMah, 41250U);
  EXPECT_FALSE(decode(fb, sback));
}
