// The data flash region of an image as a hal::FlashStorage: the FLASHCTL driver (flashctl.hpp) over
// the sectors the linker script reserves (linker/mspm0_sections.ld __record_store_start__ ..
// __record_store_end__, 4 KiB at 0x7000, outside the image and kept by `bmsctl flash`).
//
// Contract: dataFlash() builds the driver; call it once (thread mode, at start-up: appInit). The region must
// fit FlashctlStorage::regionFits (checked with FW_ASSERT). Either part (CPU clock 32 MHz, sysclock.hpp): ECC
// on the G3507, none on the L1306 (BSP_MSPM0_CHIP_L1306, set by bsp/mspm0/CMakeLists.txt). Linked by the
// images that build the record store (FW_RECORD_STORE). `watch` (nullptr: none): the fault line the driver's
// wait watches during each program and erase (FlashctlStorage::watchFaultLine: an SRAM object that outlives
// the driver).
#pragma once

#include "flashctl.hpp"
#include "hal/flash.hpp"

namespace image {

fw::hal::FlashStorage& dataFlash(const bsp::mspm0::FlashFaultWatch* watch = nullptr);

}  // namespace image
