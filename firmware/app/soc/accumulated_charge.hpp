// The battery monitor's accumulated charge, as the state of charge counts it: each family's counter turned
// into charge passed since the previous reading, in microampere-hours with 32 fractional bits, with the
// counter's wrap and the device's restarts (reset, power loss) handled. Integer arithmetic only, no division.
//
//   BQ769x2 (SLUUBY2B DASTATUS6 0x0076, TI answer E2E 970294, TI's bq769x2_control_i2c BQ769x2_ReadPassQ):
//     bytes 0-3 the integer part (signed, userAh), bytes 4-7 the fraction (unsigned, 1/2^32 userAh), bytes
//     8-11 the accumulated time (s). Together one signed 32.32 fixed-point count, which wraps at 2^31 userAh.
//     After RESET_PASSQ (and, the firmware assumes, after a device reset) the fraction reads 0x7FFFFFFF (half
//     a userAh, E2E 970294).
//   BQ7690x (SLUUCJ0 PASSQ 0x0004): bytes 0-3 the low 32 bits, bytes 4-7 the high 16 bits sign-extended, of a
//     signed 48-bit count in userA-seconds; bytes 8-11 the accumulated time in 250 ms. (SLUUCJ0's unit column
//     reads "0.25-userA-sec" where its description says userA-seconds: the firmware takes the description,
//     which is also the side that reports less charge left after a discharge; regmaps/README.md lists it.)
// userA is the device's user-amps unit (BQ769x2 DA Configuration[USER_AMPS]; the BQ7690x at its 1 mA
// default), given as its LSB in 0.1 mA.
//
// A reading's time that did not advance by what the MCU's clock measured (within kRestartSlackMs) means the
// counter restarted from zero in between: the charge since the restart is the reading itself (less the
// BQ769x2's half userAh). The charge between the last reading before it and the restart is lost (at most one
// scan period and the outage).
#pragma once

#include <cstdint>

#include "core/bytes.hpp"
#include "core/time.hpp"

namespace fw::app {

// One reading of the counter: the count in the family's unit and the device's accumulated time in ms.
struct ChargeCount {
  int64_t count = 0;
  uint32_t timeMs = 0;
};

// The BQ769x2 DASTATUS6 bytes 0..11 (little-endian, as read).
constexpr ChargeCount bq769x2Count(const uint8_t* d) {
  const uint64_t integer = bytes::loadLe32(d);
  const uint64_t fraction = bytes::loadLe32(d + 4);
  return {static_cast<int64_t>((integer << 32) | fraction), bytes::loadLe32(d + 8) * 1000U};
}
// The BQ7690x PASSQ bytes 0..11.
constexpr ChargeCount bq7690xCount(const uint8_t* d) {
  const uint64_t low = bytes::loadLe32(d);
  const uint64_t high = bytes::loadLe32(d + 4) & 0xFFFFU;
  return {static_cast<int64_t>(((high << 32) | low) << 16) >> 16, bytes::loadLe32(d + 8) * 250U};
}

enum class CounterFamily : uint8_t { Bq769x2, Bq7690x };

// The count a restarted counter starts from (BQ769x2: half a userAh, E2E 970294).
constexpr int64_t restartCount(CounterFamily f) {
  return f == CounterFamily::Bq769x2 ? 0x7FFFFFFF : 0;
}

// The count's change from `from` to `to`, across the counter's wrap (2^64 fixed point, 2^48 for the BQ7690x).
constexpr int64_t countDelta(CounterFamily f, int64_t from, int64_t to) {
  const uint64_t d = static_cast<uint64_t>(to) - static_cast<uint64_t>(from);
  return f == CounterFamily::Bq769x2 ? static_cast<int64_t>(d) : static_cast<int64_t>(d << 16) >> 16;
}

// uAh x 2^32 per count: BQ769x2 counts userAh x 2^32, so one count is (uA per userA) uAh x 2^32 / 2^32;
// BQ7690x counts userA-seconds: (uA per userA) / 3600 uAh, x 2^32 (rounded: 1e-10 relative).
constexpr int64_t uahQ32PerCount(CounterFamily f, int32_t lsbTenthMa) {
  const int64_t uaPerUserA = static_cast<int64_t>(lsbTenthMa) * 100;
  if (f == CounterFamily::Bq769x2) return uaPerUserA;
  // ((uaPerUserA << 32) + 1800) / 3600 as three 32-bit long-division steps of 32, 16 and 16 bits: the same
  // value without a 64-bit division (on the Cortex-M0+ that pulled __aeabi_ldivmod, about 1 KiB, into the
  // images).
  const auto x = static_cast<uint32_t>(uaPerUserA);
  const uint32_t q1 = x / 3600, r1 = x % 3600;
  const uint32_t q2 = (r1 << 16) / 3600, r2 = (r1 << 16) % 3600;
  const uint32_t q3 = ((r2 << 16) + 1800) / 3600;
  return static_cast<int64_t>((static_cast<uint64_t>(q1) << 32) + (static_cast<uint64_t>(q2) << 16) + q3);
}
static_assert(uahQ32PerCount(CounterFamily::Bq7690x, 10) == ((1000LL << 32) + 1800) / 3600 &&
                  uahQ32PerCount(CounterFamily::Bq7690x, 1) == ((100LL << 32) + 1800) / 3600 &&
                  uahQ32PerCount(CounterFamily::Bq7690x, 123457) == ((12345700LL << 32) + 1800) / 3600,
              "the long division gives the 64-bit quotient");

// A device time that lags the MCU's by more than this much plus 1/16 of the interval is a restart.
inline constexpr uint32_t kRestartSlackMs = 2000;

// The charge (uAh x 2^32, positive = charged) between two readings taken `mcuElapsed` apart on the MCU's
// clock; `restarted` tells whether the device's counter restarted in between. `perCountQ32` is
// uahQ32PerCount(f, the current LSB), computed once by the caller (its long division is not per reading).
struct ChargeStep {
  int64_t uahQ32 = 0;
  bool restarted = false;
};
constexpr ChargeStep chargeStep(CounterFamily f, int64_t perCountQ32, const ChargeCount& prev,
                                const ChargeCount& now, Duration mcuElapsed) {
  const int32_t deviceMs = static_cast<int32_t>(now.timeMs - prev.timeMs);
  const uint32_t mcuMs = mcuElapsed.toMs();
  const bool restarted =
      deviceMs < 0 || static_cast<uint32_t>(deviceMs) + kRestartSlackMs + mcuMs / 16 < mcuMs;
  const int64_t d =
      restarted ? countDelta(f, restartCount(f), now.count) : countDelta(f, prev.count, now.count);
  return {d * perCountQ32, restarted};
}

}  // namespace fw::app
