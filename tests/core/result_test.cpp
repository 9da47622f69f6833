#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/result.hpp"
#include "core/status.hpp"
#include "core/time.hpp"

namespace {

TEST(Status, EveryValueHasADistinctName) {
  std::set<std::string> names;
  for (uint8_t i = 0; i < fw::kStatusCount; ++i) {
    const std::string name = fw::statusName(static_cast<fw::Status>(i));
    EXPECT_NE(name, "?") << int(i);
    EXPECT_TRUE(names.insert(name).second) << "duplicate name " << name;
  }
  EXPECT_EQ(names.size(), fw::kStatusCount);
}

TEST(Result, CarriesValueOrFailure) {
  fw::Result<int16_t> good(int16_t{3700});
  EXPECT_TRUE(good.ok());
  EXPECT_EQ(good.value(), 3700);
  fw::Result<int16_t> bad(fw::Status::Crc);
  EXPECT_FALSE(bad.ok());
  EXPECT_EQ(bad.status(), fw::Status::Crc);
  EXPECT_EQ(bad.valueOr(-1), -1);
}

TEST(ResultDeathTest, ReadingAFailedValueIsAFault) {
  fw::Result<int> bad(fw::Status::Timeout);
  EXPECT_DEATH((void)bad.value(), "FW_ASSERT failed: module 1");
}

TEST(ResultDeathTest, OkIsNotAFailure) {
  EXPECT_DEATH(fw::Result<int>(fw::Status::Ok), "FW_ASSERT failed");
}

TEST(Time, WrapSafeComparisons) {
  const fw::Instant nearWrap{0xFFFFFF00u};
  const fw::Instant afterWrap = nearWrap + fw::us(0x200);
  EXPECT_EQ(afterWrap.us, 0x100u);
  EXPECT_TRUE(fw::isBefore(nearWrap, afterWrap));
  EXPECT_FALSE(fw::isBefore(afterWrap, nearWrap));
  EXPECT_TRUE(fw::isDue(nearWrap, afterWrap));
  EXPECT_EQ(fw::elapsed(nearWrap, afterWrap).us, 0x200u);
  EXPECT_EQ(fw::ms(2).us, 2000u);
  EXPECT_EQ(fw::s(3).toMs(), 3000u);
}

}  // namespace
