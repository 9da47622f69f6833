#include "data_flash.hpp"

#include <cstdint>

#include "chip/mspm0g3507.hpp"
#include "common/construct_once.hpp"
#include "core/assert.hpp"
#include "flashctl.hpp"
#include "sysclock.hpp"

extern "C" const uint8_t __record_store_start__[];
extern "C" const uint8_t __record_store_end__[];

namespace image {

namespace {

// The G3507 computes and stores ECC for each flash word (SLAU846A FLASHCTL; flashctl.hpp).
constexpr bool kEcc = true;

}  // namespace

fw::hal::FlashStorage& dataFlash() {
  const auto address = static_cast<uint32_t>(reinterpret_cast<uintptr_t>(__record_store_start__));
  const auto sectors = static_cast<uint32_t>(__record_store_end__ - __record_store_start__) /
                       fw::hal::FlashStorage::kSectorBytes;
  FW_ASSERT_MODULE(fw::Module::Bsp, bsp::mspm0::FlashctlStorage::regionFits(address, sectors));
  return constructOnce<bsp::mspm0::FlashctlStorage>(
      bsp::mspm0::FlashctlConfig{bsp::mspm0::chip::Mspm0g3507::kFlashctl, address, __record_store_start__,
                                 sectors, kEcc, bsp::mspm0::kBusClockHz / 1000000U});
}

}  // namespace image
