#include "sysctl_model.hpp"

#include "mmio_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kSysctl = 0x400AF000;
constexpr uintptr_t kHsclken = kSysctl + 0x1108;
constexpr uintptr_t kHfclkclkcfg = kSysctl + 0x1110;
constexpr uintptr_t kClkstatus = kSysctl + 0x1204;

constexpr uint32_t kHfxtEnable = 1U << 0;  // SYSCTL_HSCLKEN_HFXTEN
constexpr uint32_t kRangeMask = 0x3000;    // SYSCTL_HFCLKCLKCFG_HFXTRSEL
constexpr uint32_t kRange32To48 = 0x3000;
constexpr uint32_t kRange16To32 = 0x2000;
constexpr uint32_t kRangeAndTimeMask = kRangeMask | 0xFF;  // HFXTRSEL 13:12, HFXTTIME 7:0
constexpr uint32_t kHfclkGood = 1U << 8;                   // SYSCTL_CLKSTATUS_HFCLKGOOD
constexpr uint32_t kGoodFromRead = 3;

}  // namespace

void SysctlModel::attach() {
  crystalMissing_ = false;
  readsSinceEnable_ = 0;
  RegisterModel& m = model();
  config_ = 0;
  m.onWrite(kHfclkclkcfg, [this](uint32_t v) {
    if ((model().value(kHsclken) & kHfxtEnable) && ((v ^ config_) & kRangeAndTimeMask) != 0) {
      model().flag(
          "SYSCTL: HFXT range or start-up time changed while HSCLKEN.HFXTEN is set (TI's "
          "DL_SYSCTL_setHFCLKSourceHFXTParams disables the HFXT first)");
    }
    config_ = v;
  });
  m.onWrite(kHsclken, [this](uint32_t) { readsSinceEnable_ = 0; });
  m.onRead(kClkstatus, [this] {
    const RegisterModel& regs = model();
    const bool running = (regs.value(kHsclken) & kHfxtEnable) != 0 &&
                         (regs.value(kHfclkclkcfg) & kRangeMask) == kRange32To48 && !crystalMissing_;
    return running && ++readsSinceEnable_ >= kGoodFromRead ? kHfclkGood : 0U;
  });
}

void SysctlModel::hfxtLeftRunning() {
  config_ = kRange16To32 | 0xFF;
  model().set(kHsclken, kHfxtEnable);
  model().set(kHfclkclkcfg, config_);
}

}  // namespace bsp::mspm0::test
