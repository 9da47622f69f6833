// The bit-serial division behind the target's __aeabi_uidiv / __aeabi_uidivmod (bsp/mspm0/runtime.hpp)
// against the host's hardware division.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "runtime.hpp"

namespace bsp::mspm0::runtime {
namespace {

TEST(Runtime, UdivmodMatchesHardwareDivision) {
  const uint32_t edges[] = {0, 1, 2, 3, 7, 0x7FFFFFFF, 0x80000000, 0x80000001, 0xFFFFFFFE, 0xFFFFFFFF};
  for (uint32_t n : edges) {
    for (uint32_t d : edges) {
      if (d == 0) continue;
      const QuotientRemainder qr = udivmod(n, d);
      EXPECT_EQ(qr.quotient, n / d) << n << " / " << d;
      EXPECT_EQ(qr.remainder, n % d) << n << " % " << d;
    }
  }
  std::mt19937 rng(7);
  for (int i = 0; i < 100000; ++i) {
    const uint32_t n = rng();
    const uint32_t d = (rng() >> (rng() % 32)) | 1U;
    const QuotientRemainder qr = udivmod(n, d);
    ASSERT_EQ(qr.quotient, n / d) << n << " / " << d;
    ASSERT_EQ(qr.remainder, n % d) << n << " % " << d;
  }
}

TEST(Runtime, DivisionByZeroIsZero) {
  EXPECT_EQ(udivmod(5, 0).quotient, 0U);
  EXPECT_EQ(udivmod(5, 0).remainder, 0U);
}

}  // namespace
}  // namespace bsp::mspm0::runtime
