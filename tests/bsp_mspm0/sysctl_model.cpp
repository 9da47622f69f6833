#include "sysctl_model.hpp"

#include "mmio_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kSysctl = 0x400AF000;
constexpr uintptr_t kHsclken = kSysctl + 0x1108;
constexpr uintptr_t kHfclkclkcfg = kSysctl + 0x1110;
constexpr uintptr_t kClkstatus = kSysctl + 0x1204;
constexpr uintptr_t kSysosccfg = kSysctl + 0x1100;
constexpr uintptr_t kRstcause = kSysctl + 0x1220;
constexpr uintptr_t kSysoscfclctl = kSysctl + 0x1310;

constexpr uint32_t kHfxtEnable = 1U << 0;  // SYSCTL_HSCLKEN_HFXTEN
constexpr uint32_t kRangeMask = 0x3000;    // SYSCTL_HFCLKCLKCFG_HFXTRSEL
constexpr uint32_t kRange32To48 = 0x3000;
constexpr uint32_t kRange16To32 = 0x2000;
constexpr uint32_t kRangeAndTimeMask = kRangeMask | 0xFF;  // HFXTRSEL 13:12, HFXTTIME 7:0
constexpr uint32_t kHfclkGood = 1U << 8;                   // SYSCTL_CLKSTATUS_HFCLKGOOD
constexpr uint32_t kGoodFromRead = 3;
constexpr uint32_t kFclKey = 0x2A, kSetUseFcl = 1U << 0, kSetUseExRes = 1U << 1;  // SYSOSCFCLCTL
constexpr uint32_t kFclMode = 1U << 24;                                           // CLKSTATUS.FCLMODE

}  // namespace

void SysctlModel::attach() {
  crystalMissing_ = noExResSelect_ = fclOn_ = false;
  cause_ = 0;
  readsSinceEnable_ = 0;
  RegisterModel& m = model();
  m.onWrite(kSysoscfclctl, [this](uint32_t v) {
    if ((v >> 24) != kFclKey) {
      model().flag(
          "SYSCTL: SYSOSCFCLCTL written without KEY 0x2A: the part ignores it (hw_sysctl SYSOSCFCLCTL.KEY)");
      return;
    }
    if (noExResSelect_ && (v & kSetUseExRes)) {
      model().flag(
          "SYSCTL: SYSOSCFCLCTL.SETUSEEXRES on a part without it (MSPM0L11xx/L13xx: external ROSC only)");
    }
    if (!model().lastWrite(kSysosccfg)) {
      model().flag(
          "SYSCTL: FCL enabled before SYSOSCCFG selected the SYSOSC frequency (TI's order: setSYSOSCFreq, "
          "then "
          "enableSYSOSCFCL)");
    }
    if (v & kSetUseFcl) fclOn_ = true;  // locked on until the next BOOTRST
  });
  m.onRead(kRstcause, [this] {
    const uint32_t id = cause_;
    cause_ = 0;  // read-to-clear
    return id;
  });
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
    return (running && ++readsSinceEnable_ >= kGoodFromRead ? kHfclkGood : 0U) | (fclOn_ ? kFclMode : 0U);
  });
}

void SysctlModel::resetCause(uint32_t id) {
  cause_ = id;
}

void SysctlModel::hfxtLeftRunning() {
  config_ = kRange16To32 | 0xFF;
  model().set(kHsclken, kHfxtEnable);
  model().set(kHfclkclkcfg, config_);
}

}  // namespace bsp::mspm0::test
