// SocView: the state of charge as a monitor publishes it in the pack view (app/pack/pack_view.hpp), for CAN
// PackSummary.StateOfCharge (%) and the StateOfCharge message (0.1 %, mAh, basis; bms.yaml).
//
// Written by the monitor task only: the BQ769x2/BQ7690x applications from app/soc's count after each
// validated scan, the BQ4050 application from the gauge's own RelativeStateOfCharge, RemainingCapacity and
// FullChargeCapacity. Basis Unknown (zero, the state the images start from) means nothing is known: every
// output goes out not available. Builds without the state of charge (FW_SOC=0: L1306-BQ76952, BQ79616) keep
// an empty SocView, so the view costs them no RAM and the messages go out not available.
#pragma once

#include <cstdint>
#include <type_traits>

#include "app/config.hpp"

namespace fw::app {

inline constexpr bool kSoc = FW_SOC != 0;

// How the value was last set (CAN StateOfCharge.Basis): zero is "nothing known yet".
enum class SocBasis : uint8_t { Unknown = 0, Ocv = 1, Full = 2, Empty = 3, Restored = 4, Gauge = 5 };

struct CountedSocView {
  uint32_t remainingMah = 0;
  uint32_t fullChargeMah = 0;  // the capacity the value is a share of
  uint16_t permille = 0;       // 0..1000
  SocBasis basis = SocBasis::Unknown;

  bool known() const { return basis != SocBasis::Unknown; }
  void set(uint16_t p, uint32_t remaining, uint32_t full, SocBasis b) {
    permille = p, remainingMah = remaining, fullChargeMah = full, basis = b;
  }
};
struct NoSocView {  // the same names, all constant: nothing known
  static constexpr uint32_t remainingMah = 0;
  static constexpr uint32_t fullChargeMah = 0;
  static constexpr uint16_t permille = 0;
  static constexpr SocBasis basis = SocBasis::Unknown;

  static constexpr bool known() { return false; }
  void set(uint16_t, uint32_t, uint32_t, SocBasis) {}
};
using SocView = std::conditional_t<kSoc, CountedSocView, NoSocView>;

}  // namespace fw::app
