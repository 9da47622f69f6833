#include "timg_model.hpp"

#include <algorithm>

#include "mmio_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kImask = 0x1028, kMis = 0x1038, kIset = 0x1040, kIclr = 0x1048;
constexpr uintptr_t kCtr = 0x1800, kLoadReg = 0x1808, kCc0 = 0x1810, kCc1 = 0x1814;

}  // namespace

void TimgModel::attach() {
  ticks_ = 0;
  ris_ = 0;
  RegisterModel& m = model();
  m.onRead(base_ + kCtr, [this] { return counter(); });
  m.onRead(base_ + kMis, [this] { return pending(); });
  m.onWrite(base_ + kIclr, [this](uint32_t v) { ris_ &= ~v; });
  m.onWrite(base_ + kIset, [this](uint32_t v) { ris_ |= v; });
}

uint32_t TimgModel::reg(uintptr_t offset) const {
  return model().value(base_ + offset);
}

uint32_t TimgModel::counter() const {
  const uint64_t period = static_cast<uint64_t>(reg(kLoadReg) & 0xFFFF) + 1;
  return static_cast<uint32_t>(ticks_ % period);
}

uint32_t TimgModel::pending() const {
  return ris_ & reg(kImask);
}

bool TimgModel::runUntilInterrupt(uint64_t limit) {
  const uint64_t period = static_cast<uint64_t>(reg(kLoadReg) & 0xFFFF) + 1;
  const uint64_t end = ticks_ + limit;
  while (pending() == 0 && ticks_ < end) {
    // The next tick on which the counter becomes one of the event values (1 .. period ticks ahead).
    const uint32_t c = counter();
    auto until = [&](uint32_t value) { return (value + period - 1 - c) % period + 1; };
    const uint64_t load = until(reg(kLoadReg) & 0xFFFF), cc0 = until(reg(kCc0) & 0xFFFF),
                   cc1 = until(reg(kCc1) & 0xFFFF);
    const uint64_t step = std::min({load, cc0, cc1, end - ticks_});
    ticks_ += step;
    if (step == load) ris_ |= kLoad;
    if (step == cc0) ris_ |= kCcu0;
    if (step == cc1) ris_ |= kCcu1;
  }
  return pending() != 0;
}

}  // namespace bsp::mspm0::test
