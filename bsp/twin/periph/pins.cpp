#include "periph/pins.hpp"

#include <cstdio>

#include "periph/gpio.hpp"

namespace twin {

Pins::Pins(Machine& machine, std::span<const PinId> pins)
    : machine_(machine), pins_(pins.begin(), pins.end()) {
  size_t count = 0;
  for (const PinId& p : pins_)
    count = std::max<size_t>(count, p.pincm + 1U);
  pincm_.assign(count, 0);
  level_.assign(count, false);
  external_.assign(count, Drive::None);
  boardPullUp_.assign(count, false);
  functionDrive_.assign(count, {0, Drive::None});
  observers_.resize(count);
  machine.onReset([this](ResetKind) { reset(); });
}

void Pins::reset() {
  // IOMUX is reset by SYSRST and above (reset level tables, "IOMUX" column): every pin disconnected.
  std::fill(pincm_.begin(), pincm_.end(), 0);
  for (const PinId& p : pins_)
    refresh(p.pincm);
}

const PinId* Pins::find(int port, int bit) const {
  for (const PinId& p : pins_) {
    if (p.port == port && p.bit == bit) return &p;
  }
  return nullptr;
}

bool Pins::read(uint32_t offset, unsigned bytes, uint32_t& value) {
  const uint32_t index = offset / 4;
  if (bytes != 4 || (offset & 3U) != 0 || index == 0 || index >= pincm_.size()) return false;
  value = pincm_[index];
  return true;
}

bool Pins::write(uint32_t offset, unsigned bytes, uint32_t value) {
  const uint32_t index = offset / 4;
  if (bytes != 4 || (offset & 3U) != 0 || index == 0 || index >= pincm_.size()) return false;
  pincm_[index] = value;
  refresh(static_cast<int>(index));
  return true;
}

Drive Pins::mcuDrive(int index) const {
  const uint32_t v = pincm(index);
  const auto& [pf, drive] = functionDrive_[static_cast<size_t>(index)];
  if (pf != 0 && (v & (kPc | 0x3FU)) == (kPc | pf)) return drive;
  if ((v & (kPc | 0x3FU)) != (kPc | kPfGpio)) return Drive::None;
  for (const PinId& p : pins_) {
    if (p.pincm != index) continue;
    const Gpio* gpio = ports_[p.port];
    if (gpio == nullptr || !gpio->powered() || ((gpio->doe() >> p.bit) & 1U) == 0) return Drive::None;
    if ((gpio->dout() >> p.bit) & 1U) return (v & kHiZ1) ? Drive::None : Drive::High;
    return Drive::Low;
  }
  return Drive::None;
}

void Pins::refresh(int index) {
  const auto i = static_cast<size_t>(index);
  const Drive mcu = mcuDrive(index);
  const Drive ext = external_[i];
  const uint32_t v = pincm_[i];
  bool level;
  if (mcu == Drive::Low || ext == Drive::Low) {
    level = false;
  } else if (mcu == Drive::High || ext == Drive::High || boardPullUp_[i] || (v & kPullUp)) {
    level = true;
  } else {
    level = false;  // pulled down, or floating (recorded when a GPIO input reads it)
  }
  if (level == level_[i]) return;
  level_[i] = level;
  for (const PinId& p : pins_) {
    if (p.pincm == index && ports_[p.port] != nullptr) ports_[p.port]->padChanged(p.bit, level);
  }
  for (auto& observer : observers_[i])
    observer(level);
}

void Pins::refreshPort(int port) {
  for (const PinId& p : pins_) {
    if (p.port == port) refresh(p.pincm);
  }
}

bool Pins::floating(int index) const {
  const auto i = static_cast<size_t>(index);
  return mcuDrive(index) == Drive::None && external_[i] == Drive::None && !boardPullUp_[i] &&
         (pincm_[i] & (kPullUp | kPullDown)) == 0;
}

std::string Pins::pinName(int index) const {
  for (const PinId& p : pins_) {
    if (p.pincm == index)
      return std::string("P") + static_cast<char>('A' + p.port) + std::to_string(p.bit) + " (PINCM" +
             std::to_string(index) + ")";
  }
  return "PINCM" + std::to_string(index);
}

bool Pins::requireInput(int index, const std::string& function) {
  if (inputEnabled(index)) return true;
  char buf[32];
  std::snprintf(buf, sizeof buf, "PINCM 0x%08X", pincm(index));
  machine_.violate(Rule::InputEnable, function + " on " + pinName(index) + " without IOMUX INENA (" + buf +
                                          "): the input reads 0 on silicon");
  return false;
}

void Pins::noteFloatingRead(const PinId& pin) {
  floating_.insert(std::string("P") + static_cast<char>('A' + pin.port) + std::to_string(pin.bit));
}

void Pins::setExternal(int index, Drive drive) {
  external_[static_cast<size_t>(index)] = drive;
  refresh(index);
}

void Pins::setFunctionDrive(int index, uint32_t pf, Drive drive) {
  functionDrive_[static_cast<size_t>(index)] = {pf, drive};
  refresh(index);
}

void Pins::setBoardPullUp(int index, bool on) {
  boardPullUp_[static_cast<size_t>(index)] = on;
  refresh(index);
}

void Pins::onChange(int index, std::function<void(bool)> observer) {
  observers_[static_cast<size_t>(index)].push_back(std::move(observer));
}

}  // namespace twin
