// Reset handler for both MSPM0 parts: paint the stack guard, copy .data, zero .bss, run constructors, call
// main. The vector tables are per chip (vectors_mspm0l1306.cpp, vectors_mspm0g3507.cpp); the symbols come
// from linker/mspm0.ld.
#include <cstdint>

#include "core/assert.hpp"
#include "watchdog.hpp"

extern "C" {
extern uint32_t __data_load__, __data_start__, __data_end__, __bss_start__, __bss_end__;
extern uint32_t __stack_limit__[];
extern void (*__init_array_start)();
extern void (*__init_array_end)();
int main();
[[noreturn]] void Reset_Handler();
}

extern "C" void Reset_Handler() {
  // Word loops rather than memcpy/memset: nothing from the C library is needed before main.
  for (uint32_t i = 0; i < bsp::mspm0::kStackGuardWords; ++i)
    __stack_limit__[i] = bsp::mspm0::kStackGuardPattern;
  for (uint32_t *src = &__data_load__, *dst = &__data_start__; dst < &__data_end__;)
    *dst++ = *src++;
  for (uint32_t* dst = &__bss_start__; dst < &__bss_end__;)
    *dst++ = 0;
  for (void (**ctor)() = &__init_array_start; ctor < &__init_array_end; ++ctor)
    (*ctor)();
  main();
  fw::onFault(fw::Module::Bsp, static_cast<uint16_t>(__LINE__));  // main() never returns
}
