// Issue 14 item 3, for every application with a scan monitor: protection evaluates each scan's data once,
// not a second time at its periodic check (the old code: 40 evaluations for 20 scans).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>

#include "core/time.hpp"

template <class Board>
void expectOneEvaluationPerScan(Board& b) {
  b.h.runFor(fw::ms(1000));
  const uint32_t evaluations = b.app.protection().evaluations();
  const uint32_t scans = b.app.monitor().stats().scans;
  b.h.runFor(fw::ms(2000));
  const uint32_t scanned = b.app.monitor().stats().scans - scans;
  EXPECT_EQ(scanned, 20u) << "a scan every 100 ms";
  EXPECT_EQ(b.app.protection().evaluations() - evaluations, scanned);
}
