#include "app/monitors/bq4050_app.hpp"

namespace fw::app {

uint8_t blockedPaths(const drivers::bq4050::Measurement& m) {
  using S = regmap::bq4050::bits::SafetyStatus;
  constexpr uint32_t kCharge = S::cov_mask | S::occ1_mask | S::occ2_mask | S::ascc_mask | S::asccl_mask |
                               S::otc_mask | S::utc_mask | S::pto_mask | S::cto_mask | S::oc_mask |
                               S::chgc_mask | S::chgv_mask | S::pchgc_mask;
  constexpr uint32_t kDischarge = S::cuv_mask | S::cuvc_mask | S::ocd1_mask | S::ocd2_mask | S::aold_mask |
                                  S::aoldl_mask | S::ascd_mask | S::ascdl_mask | S::otd_mask | S::utd_mask;
  const uint32_t safety = m.safetyStatus.raw();
  const bool both = (safety & S::otf_mask) != 0 || m.pfStatus != 0;
  return static_cast<uint8_t>(((both || (safety & kCharge) != 0) ? 1 : 0) |
                              ((both || (safety & kDischarge) != 0) ? 2 : 0));
}

// The image's monitor task: its code (the loop with the gauge's part folded in) is compiled here once.
template class MonitorTask<Bq4050Device>;

}  // namespace fw::app
