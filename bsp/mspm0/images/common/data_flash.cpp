#include "data_flash.hpp"

#include <cstdint>

#include "common/construct_once.hpp"
#include "core/assert.hpp"
#include "flashctl.hpp"
#include "sysclock.hpp"

#if BSP_MSPM0_CHIP_L1306
#include "chip/mspm0l1306.hpp"
#else
#include "chip/mspm0g3507.hpp"
#endif

extern "C" const uint8_t __record_store_start__[];
extern "C" const uint8_t __record_store_end__[];

namespace image {

namespace {

// Both parts program one 64-bit flash word at a time (SLAU846A / SLAU847D NVM "Programming": 64 bits plus 8
// ECC bits if ECC is present; device headers FLASHCTL_SYS_DATAWIDTH 64). The G3507 computes and stores the
// ECC byte (SLASEX6B flash features: ECC); the L1306 has no ECC (SLASEX0D section 8 flash memory lists none,
// where the parts with it list "hardware ECC protection"), so CMDBYTEN enables the data bytes only.
#if BSP_MSPM0_CHIP_L1306
using Chip = bsp::mspm0::chip::Mspm0l1306;
constexpr bool kEcc = false;
#else
using Chip = bsp::mspm0::chip::Mspm0g3507;
constexpr bool kEcc = true;
#endif

}  // namespace

fw::hal::FlashStorage& dataFlash(const bsp::mspm0::FlashFaultWatch* watch) {
  const auto address = static_cast<uint32_t>(reinterpret_cast<uintptr_t>(__record_store_start__));
  const auto sectors = static_cast<uint32_t>(__record_store_end__ - __record_store_start__) /
                       fw::hal::FlashStorage::kSectorBytes;
  FW_ASSERT_MODULE(fw::Module::Bsp, bsp::mspm0::FlashctlStorage::regionFits(address, sectors));
  auto& flash = constructOnce<bsp::mspm0::FlashctlStorage>(bsp::mspm0::FlashctlConfig{
      Chip::kFlashctl, address, __record_store_start__, sectors, kEcc, bsp::mspm0::kBusClockHz / 1000000U});
  flash.watchFaultLine(watch);
  return flash;
}

}  // namespace image
