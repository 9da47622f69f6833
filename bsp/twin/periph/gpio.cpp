#include "periph/gpio.hpp"

#include <string>

namespace twin {

namespace {
constexpr uint32_t kDout = 0x1280, kDoutSet = 0x1290, kDoutClr = 0x12A0, kDoutTgl = 0x12B0;
constexpr uint32_t kDoe = 0x12C0, kDoeSet = 0x12D0, kDoeClr = 0x12E0, kDin = 0x1380;
constexpr uint32_t kPolarityLow = 0x1390, kPolarityHigh = 0x13A0;
constexpr uint32_t kRise = 1, kFall = 2;
}  // namespace

Gpio::Gpio(Machine& machine, const char* name, int port, Pins& pins)
    : Peripheral(machine, name), port_(port), pins_(pins) {
  pins.attachPort(port, *this);
}

void Gpio::resetRegisters() {
  dout_ = doe_ = 0;
  polarity_[0] = polarity_[1] = 0;
  outputsChanged();
}

void Gpio::padChanged(int bit, bool level) {
  const PinId* pin = pins_.find(port_, bit);
  if (pin == nullptr || !powered()) return;
  const uint32_t cm = pins_.pincm(pin->pincm);
  if ((cm & (Pins::kPc | 0x3FU)) != (Pins::kPc | Pins::kPfGpio)) return;
  const uint32_t pol = (polarity_[bit >> 4] >> (2 * (bit & 15))) & 3U;
  const bool edge = (level && (pol & kRise)) || (!level && (pol & kFall));
  // An edge the firmware listens for (POLARITY and IMASK set) on a pin whose input buffer is off: silicon
  // never sees it (PIN-INENA).
  if ((cm & Pins::kInputEnable) == 0) {
    if (edge && (cpuInt_.imask & (1U << bit)) != 0)
      pins_.requireInput(pin->pincm, name() + std::string(" edge input DIO") + std::to_string(bit));
    return;
  }
  if (edge) raise(1U << bit);
}

bool Gpio::readRegister(uint32_t offset, uint32_t& value) {
  switch (offset) {
    case kDout:
      value = dout_;
      return true;
    case kDoe:
      value = doe_;
      return true;
    case kDoutSet:
    case kDoutClr:
    case kDoutTgl:
    case kDoeSet:
    case kDoeClr:
      value = 0;
      return true;  // write-only
    case kPolarityLow:
      value = polarity_[0];
      return true;
    case kPolarityHigh:
      value = polarity_[1];
      return true;
    case kDin: {
      value = 0;
      for (int bit = 0; bit < 32; ++bit) {
        const PinId* pin = pins_.find(port_, bit);
        if (pin == nullptr || (pins_.pincm(pin->pincm) & Pins::kInputEnable) == 0) continue;
        // A floating GPIO input reads anything on the part; the twin reads 0 and records it.
        if (pins_.routed(pin->pincm, Pins::kPfGpio) && pins_.floating(pin->pincm))
          pins_.noteFloatingRead(*pin);
        if (pins_.level(pin->pincm)) value |= 1U << bit;
      }
      return true;
    }
    default:
      return false;
  }
}

bool Gpio::writeRegister(uint32_t offset, uint32_t value) {
  switch (offset) {
    case kDout:
      dout_ = value;
      break;
    case kDoutSet:
      dout_ |= value;
      break;
    case kDoutClr:
      dout_ &= ~value;
      break;
    case kDoutTgl:
      dout_ ^= value;
      break;
    case kDoe:
      doe_ = value;
      break;
    case kDoeSet:
      doe_ |= value;
      break;
    case kDoeClr:
      doe_ &= ~value;
      break;
    case kPolarityLow:
      polarity_[0] = value;
      return true;
    case kPolarityHigh:
      polarity_[1] = value;
      return true;
    case kDin:
      return true;  // read-only
    default:
      return false;
  }
  outputsChanged();
  return true;
}

}  // namespace twin
