#include "periph/cpuss.hpp"

namespace twin {

namespace {
constexpr uint32_t kGroups = 0x1100, kGroupStride = 0x30, kCtl = 0x1300;
constexpr uint32_t kCtlFields = 0x7;  // PREFETCH, ICACHE, LITEN (cpuss.hpp)
}  // namespace

Cpuss::Cpuss(Machine& machine) : machine_(machine) {
  machine.onReset([this](ResetKind) { ctl_ = kCtlAtReset; });
}

void Cpuss::setMember(int group, int index, bool asserted) {
  uint32_t& ris = ris_[static_cast<size_t>(group)];
  const uint32_t bit = 1U << (index - 1);
  ris = asserted ? (ris | bit) : (ris & ~bit);
  if (group <= 1) machine_.setIrq(group, ris != 0);  // GROUP0 = IRQ 0, GROUP1 = IRQ 1
}

bool Cpuss::read(uint32_t offset, unsigned bytes, uint32_t& value) {
  if (bytes != 4) return false;
  if (offset == kCtl) {
    value = ctl_;
    return true;
  }
  if (offset < kGroups || offset >= kGroups + 5 * kGroupStride) return false;
  const size_t g = (offset - kGroups) / kGroupStride;
  switch ((offset - kGroups) % kGroupStride) {
    case 0x00:
      value = ris_[g] ? static_cast<uint32_t>(__builtin_ctz(ris_[g])) + 1 : 0;
      return true;
    case 0x08:
      value = members_[g];
      return true;
    case 0x10:
    case 0x18:
      value = ris_[g];
      return true;
    case 0x20:
    case 0x28:
      value = 0;
      return true;
    default:
      return false;
  }
}

bool Cpuss::write(uint32_t offset, unsigned bytes, uint32_t value) {
  if (bytes != 4) return false;
  if (offset == kCtl) {
    ctl_ = value & kCtlFields;
    return true;
  }
  // The group registers are read-only, ISET/ICLR have nothing to act on (the members are levels).
  return offset >= kGroups && offset < kGroups + 5 * kGroupStride;
}

}  // namespace twin
