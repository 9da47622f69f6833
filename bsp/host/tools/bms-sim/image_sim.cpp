#include "image_sim.hpp"

#include "app/publish/slcan.hpp"
#include "image_descriptions.hpp"

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

namespace {
// What a board kind (images/common/board_<kind>.cpp) sends its results on.
std::string outputOf(std::string_view board) {
  if (board == "l1306_i2c_slcan") return "SLCAN on the back-channel UART";
  if (board == "g3507_can") return "CAN out";
  return "board " + std::string(board);
}
}  // namespace

ImageRegistrar::ImageRegistrar(std::string_view family, int defaultDevices, BindImage bind) {
  for (const ImageDescription& d : kImageDescriptions) {
    if (d.family != family) continue;
#ifdef BMS_SIM_IMAGE
    if (d.preset != BMS_SIM_IMAGE) continue;  // an image's own simulator runs that image only
#endif
    ImageBinding b = bind(d);
    auto& entries = registry();
    // In name order, whatever order the bindings' registrars run in.
    auto at = entries.begin();
    while (at != entries.end() && at->image < d.preset)
      ++at;
    entries.insert(at, {std::string(d.preset), b.device + ", " + outputOf(d.board), defaultDevices, b.make,
                        std::move(b.missing)});
  }
}
const std::vector<ImageEntry>& images() {
  return registry();
}

}  // namespace bmssim
