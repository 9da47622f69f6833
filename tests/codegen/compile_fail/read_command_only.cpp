// Must NOT compile: FET_ENABLE is a command-only subcommand; there is no data to decode.
#include <array>
#include <cstdint>

#include "regmap/bq769x2.hpp"

int main() {
  using namespace fw::regmap;
  const std::array<std::uint8_t, 0> nothing{};
  const auto value = decode(bq769x2::sub::FetEnable, nothing);
  return value == NoData{} ? 0 : 1;
}
