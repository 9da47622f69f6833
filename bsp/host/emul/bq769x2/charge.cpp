// Bq769xEmulator, the accumulated charge: the device integrates the current it measures into a charge
// counter with its accumulation time, which the host reads with one subcommand and clears with another.
//   BQ769x2: DASTATUS6 (0x0076) bytes 0-3 the integer part (I4, userAh), 4-7 the fraction (U4, 1/2^32
//     userAh), 8-11 the accumulated time (U4, s) (SLUUBY2B DASTATUS6; TI's bq769x2_control_i2c
//     BQ769x2_ReadPassQ reads the same bytes; the integer part is signed, TI answer E2E 970294); RESET_PASSQ
//     (0x0082) clears it, after which the fraction reads 0x7FFFFFFF, half a userAh (E2E 970294).
//   BQ7690x: PASSQ (0x0004) bytes 0-3 the low 32 bits and 4-7 the high 16 bits, sign-extended, of a signed
//     48-bit count in userA-seconds, 8-11 the accumulated time in 250 ms (SLUUCJ0 PASSQ; TI's
//     bq7690x_control_i2c reads PASSQLSB/PASSQMSB/PASSQTIME); RESET_PASSQ (0x0005) clears it. The unit is the
//     description's userA-seconds (the table's unit column says 0.25-userA-sec: regmaps/README.md).
// userA is the unit DA Configuration[USER_AMPS] sets (the BQ7690x: 1 mA, its default). The counter follows
// the true current, not the 16-bit CC2 report (which saturates): the device integrates its coulomb
// counter's raw conversions. A reset or power-up clears it as RESET_PASSQ does (the firmware's assumption,
// listed in regmaps/README.md: no TI text found says what a reset leaves). The count wraps at the field's
// width (2^31 userAh; 2^47 userA-s), as a fixed-width register does.
#include "bq769x2/emulator.hpp"
#include "core/bytes.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq769x2.hpp"

namespace bsp::host {

namespace {
namespace m2 = fw::regmap::bq769x2;
constexpr uint64_t kUsPerHour = 3600000000ULL;
}  // namespace

int32_t Bq769xEmulator::userAmpTenthMa() const {
  if (bq7690x()) return 10;
  static constexpr int32_t kTenthMaPerLsb[4] = {1, 10, 100, 1000};
  return kTenthMaPerLsb[dataMemory(m2::dm::DaConfiguration.address, 1) & 3];
}

void Bq769xEmulator::integrateCharge() {
  const uint64_t now = clock_.nowUs();
  chargeMaUs_ += static_cast<__int128>(currentMa_) * static_cast<int64_t>(now - chargeAtUs_);
  trueChargeMaUs_ += static_cast<int64_t>(currentMa_) * static_cast<int64_t>(now - chargeAtUs_);
  chargeAtUs_ = now;
}

void Bq769xEmulator::resetCharge() {
  integrateCharge();
  chargeMaUs_ = 0;
  chargeBase_ = bq7690x() ? 0 : 0x7FFFFFFF;  // BQ769x2: the fraction reads half a userAh (E2E 970294)
  chargeSinceUs_ = clock_.nowUs();
}

void Bq769xEmulator::presetChargeCount(int64_t count) {
  integrateCharge();
  chargeMaUs_ = 0;
  chargeBase_ = count;
}

int64_t Bq769xEmulator::chargeCount() {
  integrateCharge();
  const __int128 tenthMaUsPerUserUnit =
      static_cast<__int128>(userAmpTenthMa()) * (bq7690x() ? 1000000 : static_cast<int64_t>(kUsPerHour));
  // BQ769x2: userAh x 2^32; BQ7690x: userA-s. mA x us x 10 = 0.1 mA x us.
  const __int128 scaled = bq7690x()
                              ? chargeMaUs_ * 10 / tenthMaUsPerUserUnit
                              : (chargeMaUs_ * 10 * (static_cast<__int128>(1) << 32)) / tenthMaUsPerUserUnit;
  const uint64_t raw =
      static_cast<uint64_t>(chargeBase_) + static_cast<uint64_t>(static_cast<int64_t>(scaled));
  // The register's width: 64-bit fixed point (BQ769x2), 48 bits sign-extended (BQ7690x).
  return bq7690x() ? static_cast<int64_t>(raw << 16) >> 16 : static_cast<int64_t>(raw);
}

uint8_t Bq769xEmulator::fillCharge(uint8_t* data) {
  const int64_t count = chargeCount();
  const uint64_t sinceUs = clock_.nowUs() - chargeSinceUs_;
  const uint64_t u = static_cast<uint64_t>(count);
  fw::bytes::storeLe32(data, static_cast<uint32_t>(bq7690x() ? u : u >> 32));
  fw::bytes::storeLe32(data + 4, static_cast<uint32_t>(bq7690x() ? static_cast<uint64_t>(count >> 32) : u));
  fw::bytes::storeLe32(data + 8, static_cast<uint32_t>(bq7690x() ? sinceUs / 250000 : sinceUs / 1000000));
  // DASTATUS6 fills its 32 bytes (bytes 12.. the pin ADC counts, left 0 here); PASSQ reports 12.
  return bq7690x() ? 12 : 32;
}

}  // namespace bsp::host
