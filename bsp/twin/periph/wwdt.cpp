#include "periph/wwdt.hpp"

#include <cstdio>

#include "machine.hpp"

namespace twin {

namespace {
constexpr uint32_t kCtl0 = 0x1100, kCtl1 = 0x1104, kCntrst = 0x1108, kStat = 0x110C;
constexpr uint32_t kCtl0Key = 0xC9, kCtl1Key = 0xBE;  // hw_wwdt.h WWDTCTL0/1 KEY_UNLOCK_W
constexpr uint32_t kRestartValue = 0xA7;
constexpr uint32_t kModeInterval = 1U << 16;
constexpr uint32_t kPeriodBits[8] = {25, 21, 18, 15, 12, 10, 8, 6};
// Closed window in 1/16 of the period: 0, 12.5, 18.75, 25, 50, 75, 81.25, 87.5 % (WINDOWx_SIZE_*).
constexpr uint32_t kWindowSixteenths[8] = {0, 2, 3, 4, 8, 12, 13, 14};
constexpr uint64_t kLfclkHz = 32768;
}  // namespace

Wwdt::Wwdt(Machine& machine, const char* name)
    : Peripheral(machine, name), timeout_(machine.timeline(), [this] {
        violation("the period expired without a restart (WWDTCNTRST)");
      }) {}

void Wwdt::resetRegisters() {
  ctl0_ = ctl1_ = 0;
  running_ = false;
  timeout_.cancel();
}

uint64_t Wwdt::periodCycles() const {
  const uint64_t counts = (1ULL << kPeriodBits[(ctl0_ >> 4) & 7U]) * ((ctl0_ & 7U) + 1);
  return counts * machine_.clockHz() / kLfclkHz;
}

void Wwdt::violation(const std::string& why) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s violation: %s", name(), why.c_str());
  machine_.requestReset(ResetKind::Bootrst, buf, rstcause::kBootWwdt0);
}

bool Wwdt::readRegister(uint32_t offset, uint32_t& value) {
  switch (offset) {
    case kCtl0:
      value = ctl0_ & 0x00FFFFFFU;
      return true;
    case kCtl1:
      value = ctl1_ & 0x00FFFFFFU;
      return true;
    case kCntrst:
      value = 0;
      return true;  // "Read as 0"
    case kStat:
      value = running_ ? 1U : 0U;
      return true;
    default:
      return false;
  }
}

bool Wwdt::writeRegister(uint32_t offset, uint32_t value) {
  switch (offset) {
    case kCtl0:
      if (!machine_.checkKey(std::string(name()) + " WWDTCTL0", value, kCtl0Key)) return true;
      ctl0_ = value;
      if (value & kModeInterval) {
        stop("WWDTCTL0 selects interval-timer mode, not modelled");
        return true;
      }
      running_ = true;
      startedAt_ = machine_.now();
      timeout_.at(startedAt_ + periodCycles());
      return true;
    case kCtl1:
      if (machine_.checkKey(std::string(name()) + " WWDTCTL1", value, kCtl1Key)) ctl1_ = value;
      return true;
    case kCntrst: {
      if (!running_) return true;
      if (value != kRestartValue) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "WWDTCNTRST written with 0x%X instead of 0xA7", value);
        violation(buf);
        return true;
      }
      const uint32_t window = (ctl1_ & 1U) ? (ctl0_ >> 12) & 7U : (ctl0_ >> 8) & 7U;
      const uint64_t closed = periodCycles() * kWindowSixteenths[window] / 16;
      if (machine_.now() - startedAt_ < closed) {
        violation("restart inside the closed window");
        return true;
      }
      startedAt_ = machine_.now();
      timeout_.at(startedAt_ + periodCycles());
      if (restartHook_) restartHook_();
      return true;
    }
    case kStat:
      return true;
    default:
      return false;
  }
}

}  // namespace twin
