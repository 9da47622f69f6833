// The send and flood steps of a scenario (scenario.hpp): frames of the CAN catalogue built by name
// (bsp/host/tools/commands/command_frames.hpp).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace bmssim {

// Checks `message` and its Signal=value `words` against the catalogue: "" when a frame can be built, else
// the message, with `bad` the word at fault (1-based; 0: the message itself).
std::string checkCommand(const std::string& message, const std::vector<std::string>& words, size_t& bad);

}  // namespace bmssim
