// Time on the firmware's one clock: microseconds in a wrapping 32-bit counter.
//
// Contract
// - Instant is a point on the clock; Duration a span. Both count microseconds. Instants wrap every 2^32 us
//   (71.6 minutes); compare them only with isBefore()/isDue()/elapsed(), which are correct across the wrap as
//   long as the two instants are less than 2^31 us (35.8 minutes) apart. No timer in this firmware is longer.
// - Units are part of the type: a Duration is made with us(), ms() or s(), so "2000 ms written as 1000"
//   cannot happen silently (the foxBMS DIAG_DELAY_2000ms bug).
// - Header-only, constexpr, ISR-safe.
#pragma once

#include <cstdint>

namespace fw {

struct Duration {
  uint32_t us = 0;
  constexpr bool operator==(const Duration&) const = default;
  // Written out rather than a defaulted <=>: GCC -Os keeps the synthesized three-way compare as a 20 B
  // function called from every comparison (measured: -120 B on the full L1306-BQ76952 build without it).
  constexpr bool operator<(Duration o) const { return us < o.us; }
  constexpr bool operator>(Duration o) const { return us > o.us; }
  constexpr bool operator<=(Duration o) const { return us <= o.us; }
  constexpr bool operator>=(Duration o) const { return us >= o.us; }
  constexpr Duration operator+(Duration o) const { return {us + o.us}; }
  constexpr Duration operator-(Duration o) const { return {us - o.us}; }
  constexpr Duration operator*(uint32_t k) const { return {us * k}; }
  constexpr uint32_t toMs() const { return us / 1000U; }
};

constexpr Duration us(uint32_t n) {
  return {n};
}
constexpr Duration ms(uint32_t n) {
  return {n * 1000U};
}
constexpr Duration s(uint32_t n) {
  return {n * 1000000U};
}

struct Instant {
  uint32_t us = 0;
  constexpr bool operator==(const Instant&) const = default;
  constexpr Instant operator+(Duration d) const { return {us + d.us}; }
};

// True if a is strictly earlier than b (wrap-safe).
constexpr bool isBefore(Instant a, Instant b) {
  return static_cast<int32_t>(a.us - b.us) < 0;
}
// True if `deadline` has been reached at `now`.
constexpr bool isDue(Instant deadline, Instant now) {
  return !isBefore(now, deadline);
}
// Time from `from` to `to`; `to` must not be earlier than `from`.
constexpr Duration elapsed(Instant from, Instant to) {
  return {to.us - from.us};
}
// Time from `now` to the next multiple of `period` since the clock started (a whole period when `now` is
// one; the clock's 2^32 us wrap is not a multiple, so the grid shifts once every 71.6 minutes).
constexpr Duration untilGrid(Instant now, Duration period) {
  return {period.us - now.us % period.us};
}

}  // namespace fw
