// The FLASHCTL driver (bsp/mspm0/flashctl.cpp) built for the MSPM0 with the product's start-up and linker
// script, for the twin's FLASHCTL model (flashctl_test.cpp): erase sector 0 of the data region, program two
// words, then the requests the driver must refuse. Each result is a fw::Status value in kResults; kDone is
// set last. Built once per part (FLASH_ECC: the G3507's hardware ECC).
#include <cstdint>

#include "bare_program.hpp"
#include "flashctl.hpp"

extern "C" {
extern const uint8_t __record_store_start__[], __record_store_end__[];
}

volatile uint32_t kResults[8];
volatile uint32_t kDone;

int main() {
  const auto start = reinterpret_cast<uintptr_t>(__record_store_start__);
  const auto sectors = static_cast<uint32_t>(__record_store_end__ - __record_store_start__) / 1024;
  bsp::mspm0::FlashctlStorage flash(
      {0x400CD000, static_cast<uint32_t>(start), __record_store_start__, sectors, FLASH_ECC != 0, 32});
  const uint8_t a[8] = {0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88};
  const uint8_t b[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  kResults[0] = static_cast<uint32_t>(flash.erase(0));
  kResults[1] = static_cast<uint32_t>(flash.program(0, a));
  kResults[2] = static_cast<uint32_t>(flash.program(8, b));
  kResults[3] = static_cast<uint32_t>(flash.program(0, b));   // not erased: refused
  kResults[4] = static_cast<uint32_t>(flash.program(4, b));   // not aligned
  kResults[5] = static_cast<uint32_t>(flash.erase(sectors));  // outside the region
  kResults[6] = static_cast<uint32_t>(flash.program(sectors * 1024, b));
  kResults[7] = sectors;
  kDone = 1;
  for (;;) {
  }
}
