#include "scenario_command.hpp"

#include "commands/command_frames.hpp"

namespace bmssim {

std::string checkCommand(const std::string& message, const std::vector<std::string>& words, size_t& bad) {
  bmstool::CommandBuilder builder;
  std::string error;
  bad = 0;
  if (bmstool::findMessage(message) == nullptr) {
    (void)builder.build(message, {}, error);
    return error;
  }
  for (size_t i = 0; i < words.size(); ++i) {
    if (!builder.build(message, {words[i]}, error)) {
      bad = i + 1;
      return error;
    }
  }
  return {};
}

}  // namespace bmssim
