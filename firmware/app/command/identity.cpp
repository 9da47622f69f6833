#include "app/command/identity.hpp"

#include "app/build_id.hpp"  // FW_VERSION_*, FW_BUILD_ID (generated when the build was configured)

#ifndef FW_IMAGE_ID
#define FW_IMAGE_ID 0
#endif

namespace fw::app::command {

const FirmwareIdentity kFirmwareIdentity{FW_VERSION_MAJOR, FW_VERSION_MINOR, FW_VERSION_PATCH,
                                         FW_BUILD_ID & 0xFFFFFFU, FW_IMAGE_ID};

}  // namespace fw::app::command
