// The data flash region of a G3507 image as a hal::FlashStorage: the FLASHCTL driver (flashctl.hpp) over
// the sectors the linker script reserves (linker/mspm0_sections.ld __record_store_start__ ..
// __record_store_end__, 4 KiB at 0x7000, outside the image and kept by `bmsctl flash`).
//
// Contract: dataFlash() builds the driver; call it once (thread mode, at start-up: appInit). The region must
// fit FlashctlStorage::regionFits (checked with FW_ASSERT). G3507 images only (ECC on, CPU clock 32 MHz,
// sysclock.hpp): the L1306 images build the record store out.
#pragma once

#include "hal/flash.hpp"

namespace image {

fw::hal::FlashStorage& dataFlash();

}  // namespace image
