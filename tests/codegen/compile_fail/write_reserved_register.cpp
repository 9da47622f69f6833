// Must NOT compile: BQ79616 0x310 is reserved in the datasheet summary (TI B0_reg.h calls it ADC_CTRL4), so
// the map makes it read-only (regmaps/README.md, deviations) and writing it is rejected.
#include <cstdint>

#include "regmap/bq79616.hpp"

int main() {
  using namespace fw::regmap;
  const auto wire = encode(bq79616::reg::AdcCtrl4, std::uint8_t{0x01});
  return wire[0];
}
