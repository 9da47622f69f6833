#include "image_sim.hpp"

namespace bmssim {
namespace {
std::vector<ImageEntry>& registry() {
  static std::vector<ImageEntry> entries;
  return entries;
}
}  // namespace

ImageRegistrar::ImageRegistrar(ImageEntry entry) {
  registry().push_back(entry);
}
const std::vector<ImageEntry>& images() {
  return registry();
}

}  // namespace bmssim
