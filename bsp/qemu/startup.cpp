// Start-up for the QEMU test target (qemu-system-arm -M microbit: a Cortex-M0, ARMv6-M, flash at 0x0 and
// 16 KiB of RAM at 0x20000000). Vector table, reset handler (copy .data, zero .bss, run constructors, call
// main), and fault handling that turns a HardFault or a failed FW_ASSERT into a failing exit code.
#include <cstdint>

#include "core/assert.hpp"
#include "semihosting.hpp"

extern "C" {
extern uint32_t __data_load__, __data_start__, __data_end__, __bss_start__, __bss_end__, __stack_top__;
extern void (*__init_array_start)();
extern void (*__init_array_end)();
int main();

void Reset_Handler();
void HardFault_Handler();
void Default_Handler();
void NMI_Handler() __attribute__((weak, alias("Default_Handler")));
void SVC_Handler() __attribute__((weak, alias("Default_Handler")));
void PendSV_Handler() __attribute__((weak, alias("Default_Handler")));
void SysTick_Handler() __attribute__((weak, alias("Default_Handler")));
// External interrupts 0..31; tests override the ones they use (the name encodes the IRQ number).
// clang-format off
#define BSP_IRQ(n) void Irq##n##_Handler() __attribute__((weak, alias("Default_Handler")));
BSP_IRQ(0) BSP_IRQ(1) BSP_IRQ(2) BSP_IRQ(3) BSP_IRQ(4) BSP_IRQ(5) BSP_IRQ(6) BSP_IRQ(7)
BSP_IRQ(8) BSP_IRQ(9) BSP_IRQ(10) BSP_IRQ(11) BSP_IRQ(12) BSP_IRQ(13) BSP_IRQ(14) BSP_IRQ(15)
BSP_IRQ(16) BSP_IRQ(17) BSP_IRQ(18) BSP_IRQ(19) BSP_IRQ(20) BSP_IRQ(21) BSP_IRQ(22) BSP_IRQ(23)
BSP_IRQ(24) BSP_IRQ(25) BSP_IRQ(26) BSP_IRQ(27) BSP_IRQ(28) BSP_IRQ(29) BSP_IRQ(30) BSP_IRQ(31)
// clang-format on
#undef BSP_IRQ
}

using Vector = void (*)();

// ARMv6-M vector table: initial SP, 15 system exceptions (reserved ones zero), 32 external interrupts.
__attribute__((section(".isr_vector"), used)) const Vector kVectors[16 + 32] = {
    reinterpret_cast<Vector>(&__stack_top__),
    Reset_Handler,
    NMI_Handler,
    HardFault_Handler,
    nullptr,
    nullptr,
    nullptr,
    nullptr,
    nullptr,
    nullptr,
    nullptr,
    SVC_Handler,
    nullptr,
    nullptr,
    PendSV_Handler,
    SysTick_Handler,
    Irq0_Handler,
    Irq1_Handler,
    Irq2_Handler,
    Irq3_Handler,
    Irq4_Handler,
    Irq5_Handler,
    Irq6_Handler,
    Irq7_Handler,
    Irq8_Handler,
    Irq9_Handler,
    Irq10_Handler,
    Irq11_Handler,
    Irq12_Handler,
    Irq13_Handler,
    Irq14_Handler,
    Irq15_Handler,
    Irq16_Handler,
    Irq17_Handler,
    Irq18_Handler,
    Irq19_Handler,
    Irq20_Handler,
    Irq21_Handler,
    Irq22_Handler,
    Irq23_Handler,
    Irq24_Handler,
    Irq25_Handler,
    Irq26_Handler,
    Irq27_Handler,
    Irq28_Handler,
    Irq29_Handler,
    Irq30_Handler,
    Irq31_Handler,
};

extern "C" void Reset_Handler() {
  // Word loops rather than memcpy/memset: the C library is not needed before main.
  for (uint32_t *src = &__data_load__, *dst = &__data_start__; dst < &__data_end__;)
    *dst++ = *src++;
  for (uint32_t* dst = &__bss_start__; dst < &__bss_end__;)
    *dst++ = 0;
  for (void (**ctor)() = &__init_array_start; ctor < &__init_array_end; ++ctor)
    (*ctor)();
  bsp::qemu::exit(main());
}

extern "C" void HardFault_Handler() {
  bsp::qemu::print("HardFault\n");
  bsp::qemu::exit(99);
}

extern "C" void Default_Handler() {
  bsp::qemu::print("unexpected interrupt\n");
  bsp::qemu::exit(98);
}

namespace fw {
void onFault(Module module, uint16_t line) {
  bsp::qemu::print("FW_ASSERT failed: module ");
  bsp::qemu::printUnsigned(static_cast<uint32_t>(module));
  bsp::qemu::print(" line ");
  bsp::qemu::printUnsigned(line);
  bsp::qemu::print("\n");
  bsp::qemu::exit(97);
}
}  // namespace fw

// libstdc++ headers may reference abort on "impossible" paths; keep newlib's (which pulls signal and malloc)
// out of the image.
extern "C" [[noreturn]] void abort() {
  bsp::qemu::print("abort\n");
  bsp::qemu::exit(96);
}
