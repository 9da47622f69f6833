// What Identify answers about the firmware: version, build and image (identity.cpp; the chip's own identity
// comes from hal::SystemControl).
//
// FW_VERSION_MAJOR/MINOR/PATCH: the project version (CMake project(VERSION)); FW_BUILD_ID: the first six hex
// digits of the source's git commit when the build was configured (0 outside git), both in a header CMake
// generates for identity.cpp alone (a new commit rebuilds one file); FW_IMAGE_ID: the image option (bms.yaml
// IdentifyVersion.Image: 1..5, 0 = a host build).
#pragma once

#include <cstdint>

namespace fw::app::command {

struct FirmwareIdentity {
  uint8_t major, minor, patch;
  uint32_t buildId;  // 24 bits
  uint8_t image;
};

extern const FirmwareIdentity kFirmwareIdentity;

}  // namespace fw::app::command
