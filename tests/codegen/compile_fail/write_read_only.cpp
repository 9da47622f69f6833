// Must NOT compile: Cell 1 Voltage is a read-only direct command, so encode() does not exist for it.
#include <cstdint>

#include "regmap/bq769x2.hpp"

int main() {
  using namespace fw::regmap;
  const auto wire = encode(bq769x2::cmd::Cell1Voltage, std::int16_t{3700});
  return wire[0];
}
