#include "cpu/scs.hpp"

namespace twin {

namespace {

// Offsets from 0xE000E000 (DDI 0419E B3.2.2, B3.3.2, B3.4.2).
constexpr uint32_t kSystCsr = 0x010, kSystRvr = 0x014, kSystCvr = 0x018, kSystCalib = 0x01C;
constexpr uint32_t kIser = 0x100, kIcer = 0x180, kIspr = 0x200, kIcpr = 0x280, kIpr0 = 0x400, kIpr7 = 0x41C;
constexpr uint32_t kCpuid = 0xD00, kIcsr = 0xD04, kVtor = 0xD08, kAircr = 0xD0C, kScr = 0xD10, kCcr = 0xD14;
constexpr uint32_t kShpr2 = 0xD1C, kShpr3 = 0xD20;

constexpr uint32_t kCsrEnable = 1U << 0, kCsrTickint = 1U << 1, kCsrClksource = 1U << 2;
constexpr uint32_t kCsrCountflag = 1U << 16;
// CPUID of a Cortex-M0+ r0p1 (DDI 0484C 4.3.1); CCR: STKALIGN and UNALIGN_TRP read as one (B3.2.8).
constexpr uint32_t kCpuidValue = 0x410CC601;
constexpr uint32_t kCcrValue = (1U << 9) | (1U << 3);
constexpr uint32_t kVectKey = 0x05FA;
constexpr uint32_t kAircrSysResetReq = 1U << 2;

}  // namespace

Scs::Scs(Core& core, Nvic& nvic, Timeline& timeline, std::function<void()> resetRequest)
    : core_(core),
      nvic_(nvic),
      timeline_(timeline),
      resetRequest_(std::move(resetRequest)),
      systickZero_(timeline, [this] { onSystickZero(); }) {}

void Scs::reset() {
  csr_ = rvr_ = loadedValue_ = 0;
  countFlag_ = false;
  scr_ = 0;
  systickZero_.cancel();
}

uint32_t Scs::systickValue() const {
  if ((csr_ & kCsrEnable) == 0) return loadedValue_;
  const uint64_t elapsed = timeline_.now() - loadedAt_;
  if (elapsed <= loadedValue_) return loadedValue_ - static_cast<uint32_t>(elapsed);
  if (rvr_ == 0) return 0;  // a zero reload value stops the counter at its next wrap (B3.3.3)
  const uint64_t sinceReload = elapsed - loadedValue_ - 1;
  return rvr_ - static_cast<uint32_t>(sinceReload % (static_cast<uint64_t>(rvr_) + 1));
}

void Scs::armSystick() {
  systickZero_.cancel();
  if ((csr_ & kCsrEnable) == 0) return;
  // The next transition to zero after now.
  const uint64_t elapsed = timeline_.now() - loadedAt_;
  if (elapsed < loadedValue_) {
    systickZero_.at(loadedAt_ + loadedValue_);
  } else if (rvr_ != 0) {
    const uint64_t period = static_cast<uint64_t>(rvr_) + 1;
    const uint64_t k = (elapsed - loadedValue_) / period + 1;
    systickZero_.at(loadedAt_ + loadedValue_ + k * period);
  }
}

void Scs::onSystickZero() {
  countFlag_ = true;
  if (csr_ & kCsrTickint) nvic_.setPending(Nvic::kSystick);
  armSystick();
}

bool Scs::read(uint32_t offset, unsigned bytes, uint32_t& value) {
  if (bytes != 4) return false;
  switch (offset) {
    case kSystCsr:
      value = csr_ | (countFlag_ ? kCsrCountflag : 0);
      countFlag_ = false;  // COUNTFLAG clears on read (B3.3.3)
      return true;
    case kSystRvr:
      value = rvr_;
      return true;
    case kSystCvr:
      value = systickValue();
      return true;
    case kSystCalib:
      value = 1U << 31;
      return true;  // NOREF: no reference clock (B3.3.6)
    case kIser:
    case kIcer:
      value = nvic_.enabledIrqs();
      return true;
    case kIspr:
    case kIcpr:
      value = nvic_.pendingIrqs();
      return true;
    case kCpuid:
      value = kCpuidValue;
      return true;
    case kIcsr: {
      const int pending = nvic_.highestPending();
      value = core_.ipsr() | (static_cast<uint32_t>(pending) << 12) |
              ((nvic_.pendingIrqs() != 0) ? 1U << 22 : 0) | (nvic_.pending(Nvic::kPendsv) ? 1U << 28 : 0) |
              (nvic_.pending(Nvic::kSystick) ? 1U << 26 : 0);
      return true;
    }
    case kVtor:
      value = core_.vtor();
      return true;
    case kAircr:
      value = 0xFA050000;
      return true;  // VECTKEYSTAT reads 0xFA05, little endian (B3.2.6)
    case kScr:
      value = scr_;
      return true;
    case kCcr:
      value = kCcrValue;
      return true;
    case kShpr2:
      value = static_cast<uint32_t>(nvic_.priorityField(Nvic::kSvcall)) << 24;
      return true;
    case kShpr3:
      value = static_cast<uint32_t>(nvic_.priorityField(Nvic::kSystick)) << 24 |
              static_cast<uint32_t>(nvic_.priorityField(Nvic::kPendsv)) << 16;
      return true;
    default:
      break;
  }
  if (offset >= kIpr0 && offset <= kIpr7) {
    const int first = Nvic::kIrq0 + static_cast<int>(offset - kIpr0);
    value = 0;
    for (int i = 0; i < 4; ++i)
      value |= static_cast<uint32_t>(nvic_.priorityField(first + i)) << (8 * i);
    return true;
  }
  return false;
}

bool Scs::write(uint32_t offset, unsigned bytes, uint32_t value) {
  if (bytes != 4) return false;
  switch (offset) {
    case kSystCsr:
      if ((value & kCsrEnable) && (value & kCsrClksource) == 0) {
        core_.halt("SysTick enabled on the reference clock (CLKSOURCE = 0), which the twin does not model");
        return true;
      }
      loadedValue_ = systickValue();
      loadedAt_ = timeline_.now();
      csr_ = value & (kCsrEnable | kCsrTickint | kCsrClksource);
      armSystick();
      return true;
    case kSystRvr:
      loadedValue_ = systickValue();
      loadedAt_ = timeline_.now();
      rvr_ = value & 0x00FFFFFF;
      armSystick();
      return true;
    case kSystCvr:  // any write clears the counter and COUNTFLAG (B3.3.4)
      loadedValue_ = 0;
      loadedAt_ = timeline_.now();
      countFlag_ = false;
      armSystick();
      return true;
    case kSystCalib:
      return true;  // read-only
    case kIser:
      nvic_.enableIrqs(value);
      return true;
    case kIcer:
      nvic_.disableIrqs(value);
      return true;
    case kIspr:
    case kIcpr:
      for (int i = 0; i < 32; ++i) {
        if ((value >> i) & 1U) {
          offset == kIspr ? nvic_.setPending(Nvic::kIrq0 + i) : nvic_.clearPending(Nvic::kIrq0 + i);
        }
      }
      return true;
    case kIcsr:
      if (value & (1U << 31)) nvic_.setPending(Nvic::kNmi);
      if (value & (1U << 28)) nvic_.setPending(Nvic::kPendsv);
      if (value & (1U << 27)) nvic_.clearPending(Nvic::kPendsv);
      if (value & (1U << 26)) nvic_.setPending(Nvic::kSystick);
      if (value & (1U << 25)) nvic_.clearPending(Nvic::kSystick);
      return true;
    case kVtor:
      core_.setVtor(value);
      return true;
    case kAircr:
      if ((value >> 16) == kVectKey && (value & kAircrSysResetReq)) resetRequest_();
      return true;
    case kScr:
      scr_ = value & 0x16;
      core_.setSleepOnExit((scr_ & 0x2) != 0);  // SLEEPONEXIT (B3.2.7)
      return true;
    case kCcr:
      return true;  // read-only on ARMv6-M
    case kShpr2:
      nvic_.setPriorityField(Nvic::kSvcall, static_cast<uint8_t>(value >> 24));
      return true;
    case kShpr3:
      nvic_.setPriorityField(Nvic::kSystick, static_cast<uint8_t>(value >> 24));
      nvic_.setPriorityField(Nvic::kPendsv, static_cast<uint8_t>(value >> 16));
      return true;
    default:
      break;
  }
  if (offset >= kIpr0 && offset <= kIpr7) {
    const int first = Nvic::kIrq0 + static_cast<int>(offset - kIpr0);
    for (int i = 0; i < 4; ++i)
      nvic_.setPriorityField(first + i, static_cast<uint8_t>(value >> (8 * i)));
    return true;
  }
  return false;
}

}  // namespace twin
