// Must compile: the same operations on descriptors whose access allows them, plus the concepts a driver uses.
// If this stops compiling, the compile-fail tests next to it prove nothing.
#include <array>
#include <cstdint>

#include "regmap/bq769x2.hpp"
#include "regmap/bq79616.hpp"

namespace {

using namespace fw::regmap;

// A driver-style template constrained like the real ones.
template <Readable D>
constexpr typename D::value_type readBack(D d, std::span<const std::uint8_t, D::size> wire) {
  return decode(d, wire);
}

template <CommandOnly D>
constexpr std::uint16_t subcommandCode(D) {
  return static_cast<std::uint16_t>(D::address);
}

}  // namespace

int main() {
  const std::array<std::uint8_t, 2> wire{0x74, 0x0E};
  const std::int16_t mv = readBack(bq769x2::cmd::Cell1Voltage, wire);
  const auto prot = encode(bq769x2::dm::EnabledProtectionsA, bq769x2::bits::SafetyA{}.with_cuv(true));
  const auto ctrl = encode(bq79616::reg::Control1, bq79616::bits::Control1{}.with_send_wake(true));
  static_assert(subcommandCode(bq769x2::sub::FetEnable) == 0x0022);
  static_assert(ConfigUpdateOnly<decltype(bq769x2::dm::EnabledProtectionsA)>);
  static_assert(WriteOneToClear<decltype(bq769x2::cmd::AlarmStatus)>);
  return (mv == 3700 && prot[0] == 0x04 && ctrl[0] == 0x20) ? 0 : 1;
}
