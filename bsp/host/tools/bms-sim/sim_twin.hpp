// bms-sim --elf: the firmware image itself on the MSPM0 instruction-level twin (bsp/twin) instead of the
// application built for the host BSP. The image is the ELF; --image, when given too, must name the same one
// (identify() reads it from the ELF: the part from its stack, the monitor from its driver code).
#pragma once

#include <memory>
#include <string>

#include "image_sim.hpp"

namespace bmssim {

// Loads `options.elf` and builds its board, setting `options.image` to the image it is; nullptr with `error`
// set if the file is not one of the images or does not match the `options.image` given.
std::unique_ptr<ImageSim> makeTwinSim(SimOptions& options, std::string& error);

}  // namespace bmssim
