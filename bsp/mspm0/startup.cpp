// Reset handler for both MSPM0 parts: paint the stack guard, copy .data, zero .bss, call main. No
// constructors: every global of the images is constant-initialized (the link fails on an .init_array
// entry, linker/mspm0_sections.ld), and what needs run-time set-up is built in main(). The vector tables are
// per chip (vectors_mspm0l1306.cpp, vectors_mspm0g3507.cpp); the symbols come from linker/mspm0.ld.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/assert.hpp"
#include "watchdog.hpp"

extern "C" {
extern uint32_t __data_load__, __data_start__, __data_end__, __bss_start__, __bss_end__;
extern uint32_t __stack_limit__[];
int main();
[[noreturn]] void Reset_Handler();
}

extern "C" void Reset_Handler() {
  // memcpy/memset are this firmware's own (runtime.cpp), nothing from the C library: safe before .data and
  // .bss exist. Sizes in bytes from the linker symbols (each region is word aligned, possibly empty).
  // The guard words the watchdog's feed checks.
  for (uint32_t i = 0; i < bsp::mspm0::kStackGuardWords; ++i)
    __stack_limit__[i] = bsp::mspm0::kStackGuardPattern;
  const auto bytes = [](const uint32_t& begin, const uint32_t& end) {
    return static_cast<size_t>(reinterpret_cast<uintptr_t>(&end) - reinterpret_cast<uintptr_t>(&begin));
  };
  memcpy(&__data_start__, &__data_load__, bytes(__data_start__, __data_end__));
  memset(&__bss_start__, 0, bytes(__bss_start__, __bss_end__));
  main();
  fw::onFault(fw::Module::Bsp, static_cast<uint16_t>(__LINE__));  // main() never returns
}
