// Vector table of the MSPM0G3507: initial stack pointer, the ARMv6-M system exceptions and the 32 external
// interrupts at the IRQ numbers of TI's MSPM0G3507 device header (mspm0-sdk, the IRQn_Type enum). Unused
// and reserved entries point to Default_Handler, which records the exception number and resets (fault.cpp).
// Handlers are weak aliases of Default_Handler: an image's board file defines the ones it uses, and the ELF
// test (tests/firmware) checks that every peripheral the image uses has its own handler.
#include <cstdint>

#include "fault.hpp"

extern "C" {
extern uint32_t __stack_top__;
void Reset_Handler();
void HardFault_Handler();

// Every interrupt without a driver lands here (the aliases below need it in this translation unit).
void Default_Handler() {
  bsp::mspm0::unexpectedInterrupt();
}

// clang-format off
void NMI_Handler() __attribute__((weak, alias("Default_Handler")));
void SVC_Handler() __attribute__((weak, alias("Default_Handler")));
void PendSV_Handler() __attribute__((weak, alias("Default_Handler")));
void SysTick_Handler() __attribute__((weak, alias("Default_Handler")));
void GROUP0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void GROUP1_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void TIMG8_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void UART3_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void ADC0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void ADC1_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void CANFD0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void DAC0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void SPI0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void SPI1_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void UART1_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void UART2_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void UART0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void TIMG0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void TIMG6_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void TIMA0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void TIMA1_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void TIMG7_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void TIMG12_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void I2C0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void I2C1_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void AES_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void RTC_IRQHandler() __attribute__((weak, alias("Default_Handler")));
void DMA_IRQHandler() __attribute__((weak, alias("Default_Handler")));
// clang-format on
}

using Vector = void (*)();

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
    GROUP0_IRQHandler,  // IRQ 0
    GROUP1_IRQHandler,  // IRQ 1
    TIMG8_IRQHandler,   // IRQ 2
    UART3_IRQHandler,   // IRQ 3
    ADC0_IRQHandler,    // IRQ 4
    ADC1_IRQHandler,    // IRQ 5
    CANFD0_IRQHandler,  // IRQ 6
    DAC0_IRQHandler,    // IRQ 7
    Default_Handler,    // IRQ 8
    SPI0_IRQHandler,    // IRQ 9
    SPI1_IRQHandler,    // IRQ 10
    Default_Handler,    // IRQ 11
    Default_Handler,    // IRQ 12
    UART1_IRQHandler,   // IRQ 13
    UART2_IRQHandler,   // IRQ 14
    UART0_IRQHandler,   // IRQ 15
    TIMG0_IRQHandler,   // IRQ 16
    TIMG6_IRQHandler,   // IRQ 17
    TIMA0_IRQHandler,   // IRQ 18
    TIMA1_IRQHandler,   // IRQ 19
    TIMG7_IRQHandler,   // IRQ 20
    TIMG12_IRQHandler,  // IRQ 21
    Default_Handler,    // IRQ 22
    Default_Handler,    // IRQ 23
    I2C0_IRQHandler,    // IRQ 24
    I2C1_IRQHandler,    // IRQ 25
    Default_Handler,    // IRQ 26
    Default_Handler,    // IRQ 27
    AES_IRQHandler,     // IRQ 28
    Default_Handler,    // IRQ 29
    RTC_IRQHandler,     // IRQ 30
    DMA_IRQHandler,     // IRQ 31
};
