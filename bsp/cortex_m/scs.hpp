// ARMv6-M System Control Space registers used by the BSPs (ARMv6-M ARM B3.2-B3.4): SysTick, SCB, NVIC.
#pragma once

#include <cstdint>

namespace bsp::scs {

inline volatile uint32_t& reg(uint32_t address) {
  return *reinterpret_cast<volatile uint32_t*>(address);
}

// SysTick (B3.3)
inline constexpr uint32_t kSystCsr =
    0xE000E010;  // ENABLE bit0, TICKINT bit1, CLKSOURCE bit2, COUNTFLAG bit16
inline constexpr uint32_t kSystRvr = 0xE000E014;
inline constexpr uint32_t kSystCvr = 0xE000E018;
// SCB (B3.2)
inline constexpr uint32_t kScbIcsr = 0xE000ED04;  // PENDSTSET bit26, PENDSTCLR bit25
inline constexpr uint32_t kScbVtor = 0xE000ED08;
inline constexpr uint32_t kScbAircr = 0xE000ED0C;
inline constexpr uint32_t kIcsrPendStSet = 1U << 26;
// NVIC (B3.4)
inline constexpr uint32_t kNvicIser = 0xE000E100;
inline constexpr uint32_t kNvicIcer = 0xE000E180;
inline constexpr uint32_t kNvicIspr = 0xE000E200;
inline constexpr uint32_t kNvicIcpr = 0xE000E280;
inline constexpr uint32_t kNvicIpr0 = 0xE000E400;

inline void nvicEnable(unsigned irq) {
  reg(kNvicIser) = 1U << irq;
}
inline void nvicDisable(unsigned irq) {
  reg(kNvicIcer) = 1U << irq;
}
inline void nvicSetPending(unsigned irq) {
  reg(kNvicIspr) = 1U << irq;
}
inline void nvicClearPending(unsigned irq) {
  reg(kNvicIcpr) = 1U << irq;
}

}  // namespace bsp::scs
