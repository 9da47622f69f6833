#include "image_sim.hpp"

#include "app/publish/slcan.hpp"

namespace bmssim {
namespace {
std::vector<ImageEntry>& registry() {
  static std::vector<ImageEntry> entries;
  return entries;
}
}  // namespace

namespace {
std::string slcanLine(const fw::hal::CanFrame& frame) {
  uint8_t text[fw::app::slcan::kMaxEncodedLength];
  return std::string(reinterpret_cast<const char*>(text), fw::app::slcan::encode(frame, text));
}
}  // namespace

bool ImageSim::sendFrame(const fw::hal::CanFrame& frame) {
  if (canSend(frame)) return true;
  const std::string line = std::string(slcanOpened_ ? "" : "O\r") + slcanLine(frame);
  if (!serialSend(line)) return false;
  slcanOpened_ = true;
  return true;
}

bool ImageSim::setFlood(std::function<std::optional<fw::hal::CanFrame>()> source) {
  if (canFlood(source)) return true;
  if (!slcanText()) return false;
  serialFlood_ = std::move(source);
  pumpSerialFlood();
  return true;
}

// The line stays full: another line goes out whenever less than one is waiting (each step is 1 ms, about
// 11 bytes at 115 200 Bd; a line is at most 27).
void ImageSim::pumpSerialFlood() {
  while (serialFlood_ && serialBacklog() < 32) {
    const auto f = serialFlood_();
    if (!f) break;
    if (!sendFrame(*f)) break;
  }
}

ImageRegistrar::ImageRegistrar(ImageEntry entry) {
  registry().push_back(entry);
}
const std::vector<ImageEntry>& images() {
  return registry();
}

}  // namespace bmssim
