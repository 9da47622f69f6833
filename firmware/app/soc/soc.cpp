#include "app/soc/soc.hpp"

namespace fw::app {

namespace {

// uAh to uAh x 2^32. A pack file's capacity is at most 1 048 574 mAh (regmapgen pack), so a charge up to the
// capacity in uAh, capacityMah x 1000, fits 32 bits and only the shift is 64-bit (the Cortex-M0+ has no
// 64-bit multiply: __aeabi_lmul).
constexpr int64_t toQ32(uint32_t uah) {
  return static_cast<int64_t>(uint64_t{uah} << 32);
}
static_assert(1048574ULL * 1000 <= 0xFFFFFFFFULL);

int64_t capacityQ32(const SocConfig& c) {
  return toQ32(c.capacityMah * 1000U);
}

}  // namespace

OcvEstimate ocvEstimate(const SocConfig& c, int16_t cellMv) {
  const int16_t* t = c.ocvMv;
  if (cellMv <= t[0]) return {0, t[1] - t[0] >= c.ocvMinStepMv};
  for (uint8_t i = 0; i + 1 < kOcvPoints; ++i) {
    const int32_t lo = t[i], hi = t[i + 1];
    if (cellMv >= hi) continue;
    // Linear between the two points around the voltage: 100 per 10 % step.
    const uint32_t within = static_cast<uint32_t>((cellMv - lo) * 100) / static_cast<uint32_t>(hi - lo);
    return {static_cast<uint16_t>(i * 100 + within), hi - lo >= c.ocvMinStepMv};
  }
  return {1000, t[kOcvPoints - 1] - t[kOcvPoints - 2] >= c.ocvMinStepMv};
}

void StateOfCharge::set(uint32_t permille, SocBasis basis) {
  // capacity x permille / 1000 in uAh is capacityMah x permille (no division), then x 2^32.
  state_->chargeQ32 = toQ32(config_.capacityMah * permille);
  state_->basis = basis;
}

void StateOfCharge::restore(uint16_t permille) {
  if (known() || permille > 1000) return;
  set(permille, SocBasis::Restored);
}

void StateOfCharge::update(const SocInputs& in) {
  State& s = *state_;
  const Duration interval = s.started ? elapsed(s.lastAt, in.now) : Duration{};
  s.lastAt = in.now;
  s.started = true;
  // Count what the device counted since its last reading.
  if (in.counted) {
    if (s.haveLast) {
      const ChargeStep step = chargeStep(family_, perCountQ32_, s.last, in.count, interval);
      if (step.restarted) ++s.restarts;
      if (known()) s.chargeQ32 += step.uahQ32;
    }
    s.last = in.count;
    s.haveLast = true;
  }
  // Rest: the current stayed small since the previous scan.
  const int32_t magnitude = in.currentMa < 0 ? -in.currentMa : in.currentMa;
  if (magnitude < config_.restCurrentMa) {
    if (s.rest.us < 0x80000000U) s.rest = s.rest + interval;
    if (s.sinceFix.us < 0x80000000U) s.sinceFix = s.sinceFix + interval;
  } else {
    s.rest = {};
    s.sinceFix = {};
  }
  if (in.cells) {
    if (in.maxCellMv >= config_.fullCellMv && in.currentMa >= 0) {
      set(1000, SocBasis::Full);
    } else if (in.minCellMv <= config_.emptyCellMv && in.currentMa <= 0) {
      set(0, SocBasis::Empty);
    } else if (!known() && magnitude < config_.restCurrentMa) {
      set(ocvEstimate(config_, in.avgCellMv).permille, SocBasis::Ocv);
    } else if (s.rest >= config_.restTime && s.sinceFix >= config_.restTime) {
      const OcvEstimate e = ocvEstimate(config_, in.avgCellMv);
      s.sinceFix = {};
      if (e.resolves) set(e.permille, SocBasis::Ocv);
    }
  }
  if (s.chargeQ32 < 0) s.chargeQ32 = 0;
  if (s.chargeQ32 > capacityQ32(config_)) s.chargeQ32 = capacityQ32(config_);
}

uint32_t StateOfCharge::remainingMah() const {
  if (!known()) return 0;
  // uAh to mAh: a division by a constant (the compiler multiplies).
  return static_cast<uint32_t>(state_->chargeQ32 >> 32) / 1000U;
}

uint16_t StateOfCharge::permille() const {
  if (!known() || config_.capacityMah == 0) return 0;
  const uint32_t uah = static_cast<uint32_t>(state_->chargeQ32 >> 32);
  // Rounded to the nearest 0.1 %: uAh / capacity-in-uAh-per-permille (capacityMah uAh), 32-bit.
  return static_cast<uint16_t>((uah + config_.capacityMah / 2) / config_.capacityMah);
}

}  // namespace fw::app
