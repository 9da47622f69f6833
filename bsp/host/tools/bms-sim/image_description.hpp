// ImageDescription: what bms-sim knows of an image from its folder (bsp/mspm0/images/<preset>/image.cmake):
// its preset name, its family (the binding that runs it, sim_<family>.cpp), its board kind (images/common
// board_<kind>.cpp: which output and pins the host board has) and its monitor device. The rows are generated
// from the folders (image_descriptions.hpp, CMakeLists.txt), so bms-sim has no list of its own.
#pragma once

#include <string_view>

namespace bmssim {

struct ImageDescription {
  std::string_view preset;
  std::string_view family;  // bq769x2 | bq79616 | bq4050
  std::string_view board;   // l1306_i2c_slcan | g3507_can
  std::string_view device;  // bq76952, bq76907, bq79616, bq4050
};

}  // namespace bmssim
