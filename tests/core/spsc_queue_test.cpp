#include <gtest/gtest.h>

#include "core/spsc_queue.hpp"

namespace {

TEST(SpscQueue, FifoOrderAndCapacity) {
  fw::SpscQueue<int, 4> q;
  EXPECT_TRUE(q.empty());
  for (int i = 0; i < 4; ++i)
    EXPECT_TRUE(q.push(i));
  EXPECT_FALSE(q.push(99)) << "a full queue stores nothing";
  EXPECT_EQ(q.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    int v = -1;
    ASSERT_TRUE(q.pop(v));
    EXPECT_EQ(v, i);
  }
  int v;
  EXPECT_FALSE(q.pop(v));
}

TEST(SpscQueue, IndicesWrapManyTimes) {
  fw::SpscQueue<uint32_t, 8> q;
  uint32_t next = 0, expect = 0;
  for (int round = 0; round < 100000; ++round) {
    const int burst = round % 9;
    for (int i = 0; i < burst; ++i) {
      if (q.push(next)) ++next;
    }
    uint32_t v;
    while (q.pop(v))
      EXPECT_EQ(v, expect++);
  }
  EXPECT_EQ(next, expect);
  EXPECT_GT(next, 65536u) << "the 16-bit indices wrapped";
}

}  // namespace
