// Window watchdog (WWDT) registers. Source: mspm0*.tsv rows "WWDT.*", "WWDT_*" and note "WWDT restart"
// (MSPM0 TRM SLAU846A section 24). The WWDT counts LFCLK (32 768 Hz) divided by CLKDIV + 1.
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::wwdt {

struct Control {
  Reg ctl0;    // 0x1100
  Reg ctl1;    // 0x1104
  Reg cntrst;  // 0x1108
  Reg stat;    // 0x110C
};
inline constexpr uintptr_t kControlOffset = 0x1100;
static_assert(kControlOffset + offsetof(Control, cntrst) == 0x1108);

inline Control& control(uintptr_t base) {
  return mmio::block<Control>(base + kControlOffset);
}

inline constexpr uint32_t kCtl0Key = 0xC9000000;
inline constexpr uint32_t kPerShift = 4;  // PER 6:4: 0 = 2^25 ... 3 = 2^15 ... 7 = 2^6 counts
inline constexpr uint32_t kPer2Pow15 = 3;
inline constexpr uint32_t kRestart = 0xA7;

}  // namespace bsp::mspm0::reg::wwdt
