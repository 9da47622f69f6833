#include "pin_model.hpp"

#include <string>

#include "mmio_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kIomux = 0x40428000;
constexpr uintptr_t kImask = 0x1028;
constexpr uintptr_t kPolarity15_0 = 0x1390;
constexpr uintptr_t kPolarity31_16 = 0x13A0;

constexpr uint32_t kPc = 1U << 7;
constexpr uint32_t kPfMask = 0x3F;
constexpr uint32_t kPfGpio = 1;
constexpr uint32_t kPullDown = 1U << 16;  // IOMUX_PINCM_PIPD
constexpr uint32_t kPullUp = 1U << 17;    // IOMUX_PINCM_PIPU
constexpr uint32_t kInputEnable = 1U << 18;
constexpr uint32_t kFall = 2;  // GPIO_POLARITY*_DIOn_FALL

}  // namespace

void ActiveLowInput::attach() {
  model().onWrite(port_ + kImask, [this](uint32_t v) {
    if (v & (1U << bit_)) check();
  });
}

bool ActiveLowInput::check() const {
  const RegisterModel& m = model();
  const uint32_t pincm = m.value(kIomux + 4 * pincm_);
  const uint32_t polarity = m.value(port_ + (bit_ < 16 ? kPolarity15_0 : kPolarity31_16));
  const uint32_t edge = (polarity >> (2 * (bit_ & 15))) & 3;
  const std::string pin = std::string("GPIO ") + name_ + ": ";
  bool ok = true;
  auto fail = [&](const char* rule) {
    model().flag(pin + rule);
    ok = false;
  };
  if ((pincm & (kPc | kPfMask | kInputEnable)) != (kPc | kPfGpio | kInputEnable))
    fail("not a connected GPIO input (PINCM.PC, PF 1, INENA; hw_iomux.h)");
  if (edge != kFall) fail("active-low signal without the falling-edge POLARITY (hw_gpio.h ..._FALL = 2)");
  if (output_ == Output::OpenDrain && (pincm & (kPullUp | kPullDown)) != kPullUp)
    fail("open-drain signal without the internal pull-up (PINCM.PIPU bit 17, hw_iomux.h IOMUX_PINCM_PIPU)");
  return ok;
}

}  // namespace bsp::mspm0::test
