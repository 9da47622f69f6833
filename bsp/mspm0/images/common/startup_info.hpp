// The Startup message's content for an image's application (app/publish/publish_status.hpp StartupInfo):
// the BSP's start-up report (fault.hpp takeStartupReport: the reset cause the board read in bringUp(),
// board.system.identity().resetCause, and the fault record where the reset kept SRAM). Call once, from
// appInit(). Defined in startup_info.cpp (a stand-in board, such as
// the QEMU benchmark's, gives its own).
#pragma once

#include "app/publish/publish_status.hpp"

namespace image {

fw::app::StartupInfo startupInfo(uint8_t resetCause);

}  // namespace image
