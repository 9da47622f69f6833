// What Identify answers about the firmware: version, build and image (the chip's own identity comes from
// hal::SystemControl).
//
// kVersion: the project version (CMake project(VERSION), generated into app/version.hpp, as the Startup
// message carries it). kBuildId: the first six hex digits of the source's git commit when the build was
// configured (0 outside git), in identity.cpp alone (its generated header changes with every commit).
// kImage: the image option FW_IMAGE_ID (app/config.hpp).
#pragma once

#include <cstdint>

#include "app/config.hpp"
#include "app/version.hpp"

namespace fw::app::command {

struct Version {
  uint8_t major, minor, patch;
};
inline constexpr Version kVersion{kFirmwareVersionMajor, kFirmwareVersionMinor, kFirmwareVersionPatch};
inline constexpr uint8_t kImage = FW_IMAGE_ID;
extern const uint32_t kBuildId;  // 24 bits

}  // namespace fw::app::command
