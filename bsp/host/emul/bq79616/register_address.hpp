// The 16-bit address of a BQ79616 register descriptor of the generated map (regmap/bq79616.hpp), for the
// emulator's switch cases and constants: one helper for chain_emulator.cpp, balancing.cpp and open_wire.cpp.
#pragma once

#include <cstdint>

namespace bsp::host::bq79616_emul {

template <class Register>
constexpr uint16_t at(Register) {
  return static_cast<uint16_t>(Register::address);
}

}  // namespace bsp::host::bq79616_emul
