#include "periph/sysctl.hpp"

#include <algorithm>
#include <cstdio>

namespace twin {

namespace {

constexpr uint32_t kSysosccfg = 0x1100, kMclkcfg = 0x1104, kHsclken = 0x1108, kHsclkcfg = 0x110C;
constexpr uint32_t kHfclkclkcfg = 0x1110, kGenclkcfg = 0x1138, kClkstatus = 0x1204;
constexpr uint32_t kResetlevel = 0x1300, kResetcmd = 0x1304, kRstcause = 0x1220, kSysoscfclctl = 0x1310;

// SHUTDNSTORE0..3 (0x1400..0x140C, one byte each: hw_sysctl_mspm0l11xx_l13xx.h, _g1x0x_g3x0x.h). Firmware
// reads one after clearing CPUSS CTL.PREFETCH (CPU_ERR_02, SLAZ742G; bsp/mspm0/power_policy.cpp).
constexpr uint32_t kShutdnstore0 = 0x1400, kShutdnstoreCount = 4;
constexpr uint32_t kPmodecfg = 0x1140;     // SOCLOCK.PMODECFG (hw_sysctl_mspm0l11xx_l13xx.h, _g1x0x_g3x0x.h)
constexpr uint32_t kSysoscFreqMask = 0x3;  // SYSOSCCFG.FREQ, 0 = base 32 MHz
// SYSOSCCFG.USE4MHZSTOP (bit 8) and DISABLESTOP (bit 9), MCLKCFG.STOPCLKSTBY (bit 21), PMODECFG.DSLEEP (1:0:
// 0 STOP, 1 STANDBY, 2 SHUTDOWN) (hw_sysctl; the modes they select: power_mode.hpp).
constexpr uint32_t kUse4MhzStop = 1U << 8, kDisableStop = 1U << 9, kStopClkStby = 1U << 21;
constexpr uint32_t kDsleepMask = 0x3, kDsleepStandby = 1, kDsleepShutdown = 2;
constexpr uint32_t kMclkMdivMask = 0xF;   // MCLKCFG.MDIV
constexpr uint32_t kMclkUdivMask = 0x30;  // MCLKCFG.UDIV (ULPCLK divider)
constexpr uint32_t kMclkUseHsclk = 1U << 16, kMclkUseLfclk = 1U << 20;
constexpr uint32_t kHfxtEnable = 1U << 0;                 // HSCLKEN.HFXTEN
constexpr uint32_t kHfxtTimeMask = 0xFF;                  // HFCLKCLKCFG.HFXTTIME, 64 us units
constexpr uint32_t kHfxtRangeMask = 0x3000;               // HFCLKCLKCFG.HFXTRSEL
constexpr uint32_t kHfclkFaultCheck = 1U << 28;           // HFCLKCLKCFG.HFCLKFLTCHK
constexpr uint32_t kCanclkSysPll = 1U << 8;               // GENCLKCFG.CANCLKSRC
constexpr uint32_t kHfclkGood = 1U << 8;                  // CLKSTATUS.HFCLKGOOD
constexpr uint32_t kHfclkOff = 1U << 13;                  // CLKSTATUS.HFCLKOFF
constexpr uint32_t kResetKey = 0xE4, kResetGo = 1U << 0;  // RESETCMD KEY 31:24, GO bit 0
constexpr uint32_t kFclKey = 0x2A, kSetUseFcl = 1U << 0, kSetUseExRes = 1U << 1;  // SYSOSCFCLCTL
constexpr uint32_t kFclMode = 1U << 24;                                           // CLKSTATUS.FCLMODE

}  // namespace

Sysctl::Sysctl(Machine& machine, bool hasHfxt) : machine_(machine), hasHfxt_(hasHfxt) {
  machine.onReset([this](ResetKind kind) { reset(kind); });
  machine.setDeepSleepMode([this] { return deepSleepMode(); });
}

PowerMode Sysctl::deepSleepMode() const {
  if ((pmodecfg_ & kDsleepMask) == kDsleepStandby)
    return (mclkcfg_ & kStopClkStby) ? PowerMode::Standby1 : PowerMode::Standby0;
  if (sysosccfg_ & kDisableStop) return PowerMode::Stop2;
  return (sysosccfg_ & kUse4MhzStop) ? PowerMode::Stop1 : PowerMode::Stop0;
}

void Sysctl::reset(ResetKind kind) {
  sysosccfg_ = mclkcfg_ = hsclkcfg_ = genclkcfg_ = resetLevel_ = pmodecfg_ = 0;
  sysoscFreqWritten_ = false;
  // The FCL stays on until the next BOOTRST ("Once enabled, this state is locked until the next BOOTRST",
  // hw_sysctl SYSOSCFCLCTL.SETUSEFCL; a BOOTRST resets "SYSOSC FCL mode (if enabled)", SLAU847F, BOOTRST
  // section).
  if (kind != ResetKind::Sysrst) fclMode_ = false;
  // "Some crystal configurations are retained in lower reset levels" (TI driverlib,
  // DL_SYSCTL_setHFCLKSourceHFXTParams): the HFXT keeps running through a SYSRST.
  if (kind != ResetKind::Sysrst) {
    hsclken_ = hfclkclkcfg_ = 0;
    hfxtGoodAt_ = UINT64_MAX;
  }
}

bool Sysctl::canClockRunning() const {
  return hasHfxt_ && crystalFitted_ && (genclkcfg_ & kCanclkSysPll) == 0 && machine_.now() >= hfxtGoodAt_;
}

uint32_t Sysctl::hfclkStatus() {
  const uint64_t now = machine_.now();
  if (!hasHfxt_ || now < hfxtGoodAt_) return 0;
  if (crystalFitted_) return kHfclkGood;
  // HFXT-WAIT-UNBOUNDED (rules.hpp): a poll is reads no more than 1 ms apart; 20 ms of it after the
  // monitor's verdict, 40 times the data sheet's 0.5 ms start-up (SLASEX6B) and longer than the longest
  // HFXTTIME (255 x 64 us = 16.3 ms), is a wait without a bound.
  const uint64_t ms = 1000 * machine_.cyclesPerUs();
  if (now - lastPoll_ > ms) pollStart_ = now;
  lastPoll_ = now;
  if (now - std::max(pollStart_, hfxtGoodAt_) >= 20 * ms)
    machine_.violate(Rule::HfxtWaitUnbounded,
                     "SYSCTL: CLKSTATUS polled for 20 ms after the HFXT start-up monitor set HFCLKOFF (no "
                     "crystal): HFCLKGOOD never comes, a wait for it without a bound hangs the part");
  return kHfclkOff;
}

std::string Sysctl::canClockProblem() const {
  constexpr uint32_t kSysPllEnable = 1U << 8;  // HSCLKEN.SYSPLLEN
  if (genclkcfg_ & kCanclkSysPll) {
    if ((hsclken_ & kSysPllEnable) == 0)
      return "GENCLKCFG.CANCLKSRC selects SYSPLLCLK1 and the SYSPLL is off (HSCLKEN.SYSPLLEN clear)";
    return "";
  }
  if ((hsclken_ & kHfxtEnable) == 0)
    return "GENCLKCFG.CANCLKSRC selects HFCLK and the HFXT was never started (HSCLKEN.HFXTEN clear)";
  return "";
}

bool Sysctl::read(uint32_t offset, unsigned bytes, uint32_t& value) {
  if (bytes != 4) return false;
  if (offset >= kShutdnstore0 && offset < kShutdnstore0 + 4 * kShutdnstoreCount && offset % 4 == 0) {
    value = shutdnStore_[(offset - kShutdnstore0) / 4];
    return true;
  }
  switch (offset) {
    case kSysosccfg:
      value = sysosccfg_;
      return true;
    case kPmodecfg:
      value = pmodecfg_;
      return true;
    case kMclkcfg:
      value = mclkcfg_;
      return true;
    case kGenclkcfg:
      value = genclkcfg_;
      return true;
    case kResetlevel:
      value = resetLevel_;
      return true;
    case kClkstatus:
      value = hfclkStatus() | (fclMode_ ? kFclMode : 0);
      return true;
    case kRstcause:
      value = machine_.takeResetCause();  // read-to-clear
      return true;
    default:
      break;
  }
  if (!hasHfxt_) return false;
  switch (offset) {
    case kHsclken:
      value = hsclken_;
      return true;
    case kHsclkcfg:
      value = hsclkcfg_;
      return true;
    case kHfclkclkcfg:
      value = hfclkclkcfg_;
      return true;
    default:
      return false;
  }
}

bool Sysctl::write(uint32_t offset, unsigned bytes, uint32_t value) {
  if (bytes != 4) return false;
  if (offset >= kShutdnstore0 && offset < kShutdnstore0 + 4 * kShutdnstoreCount && offset % 4 == 0) {
    shutdnStore_[(offset - kShutdnstore0) / 4] = static_cast<uint8_t>(value);
    return true;
  }
  switch (offset) {
    case kSysosccfg:
      if (value & kSysoscFreqMask) {
        machine_.stop(
            "SYSCTL: SYSOSCCFG.FREQ selects a SYSOSC frequency other than 32 MHz; the twin runs 32 MHz");
      }
      sysosccfg_ = value;
      sysoscFreqWritten_ = true;
      return true;
    case kMclkcfg:
      if (value & (kMclkMdivMask | kMclkUdivMask | kMclkUseHsclk | kMclkUseLfclk)) {
        char buf[128];
        std::snprintf(
            buf, sizeof buf,
            "SYSCTL: MCLKCFG 0x%08X divides or re-sources MCLK/ULPCLK; the twin runs 32 MHz undivided",
            value);
        machine_.stop(buf);
      }
      mclkcfg_ = value;
      return true;
    case kGenclkcfg:
      genclkcfg_ = value;
      return true;
    case kPmodecfg:
      // SHUTDOWN loses the core's state and leaves through a BOOTRST (SLAU847D/SLAU846B 2 PMCU SHUTDOWN):
      // not modelled, and no image uses it.
      if ((value & kDsleepMask) >= kDsleepShutdown)
        machine_.stop(
            "SYSCTL: PMODECFG.DSLEEP selects SHUTDOWN (or a reserved value); the twin has no SHUTDOWN");
      pmodecfg_ = value & kDsleepMask;
      return true;
    case kResetlevel:
      resetLevel_ = value & 7U;
      return true;
    case kSysoscfclctl:
      // Without KEY 0x2A the write is ignored (hw_sysctl SYSOSCFCLCTL.KEY). SETUSEEXRES exists on the MSPM0G
      // only (hw_sysctl_mspm0l11xx_l13xx.h has no such field). The twin's SYSOSC runs at exactly 32 MHz
      // either way; FCL mode shows in CLKSTATUS.FCLMODE.
      if (!machine_.checkKey("SYSCTL SYSOSCFCLCTL", value, kFclKey)) return true;
      if (!hasHfxt_ && (value & kSetUseExRes)) {
        machine_.stop("SYSCTL: SYSOSCFCLCTL.SETUSEEXRES on the MSPM0L1306, which has no such field");
        return true;
      }
      if ((value & kSetUseFcl) && !sysoscFreqWritten_) {
        machine_.stop(
            "SYSCTL: SYSOSCFCLCTL.SETUSEFCL before SYSOSCCFG selected the SYSOSC frequency (TI's order: the "
            "frequency, then the FCL)");
        return true;
      }
      if (value & kSetUseFcl) fclMode_ = true;
      return true;
    case kResetcmd:
      if (!machine_.checkKey("SYSCTL RESETCMD", value, kResetKey) || (value & kResetGo) == 0)
        return true;  // without the key: ignored
      if (resetLevel_ == 0) {
        machine_.requestReset(ResetKind::Sysrst, "software SYSRST (RESETCMD, RESETLEVEL 0)",
                              rstcause::kSysSoftware);
      } else if (resetLevel_ == 1) {
        machine_.requestReset(ResetKind::Bootrst, "software BOOTRST (RESETCMD, RESETLEVEL 1)",
                              rstcause::kBootSoftware);
      } else if (resetLevel_ == 2) {
        bootRequest_ = BootRequest::EnterBootloader;
        machine_.requestReset(ResetKind::Sysrst, "software SYSRST, bootloader entry (RESETCMD, RESETLEVEL 2)",
                              rstcause::kSysBslEntry);
      } else if (resetLevel_ == 3) {
        machine_.requestReset(ResetKind::Por, "software POR (RESETCMD, RESETLEVEL 3)",
                              rstcause::kPorSoftware);
      } else if (resetLevel_ == 4) {
        bootRequest_ = BootRequest::ExitBootloader;
        machine_.requestReset(ResetKind::Sysrst, "software SYSRST, bootloader exit (RESETCMD, RESETLEVEL 4)",
                              rstcause::kSysBslExit);
      } else {
        machine_.stop("SYSCTL: RESETCMD with RESETLEVEL " + std::to_string(resetLevel_) +
                      ", which hw_sysctl does not define");
      }
      return true;
    default:
      break;
  }
  if (!hasHfxt_) return false;
  switch (offset) {
    case kHsclken: {
      const bool start = (value & kHfxtEnable) && !(hsclken_ & kHfxtEnable);
      hsclken_ = value;
      if ((value & kHfxtEnable) == 0) {
        hfxtGoodAt_ = UINT64_MAX;
      } else if (start) {
        const uint32_t range = (hfclkclkcfg_ >> 12) & 3U;
        const uint32_t wanted = crystalHz_ <= 8000000    ? 0
                                : crystalHz_ <= 16000000 ? 1
                                : crystalHz_ <= 32000000 ? 2
                                                         : 3;
        if (crystalHz_ != 0 && range != wanted) {
          static const char* const kRanges[] = {"4..8", "8..16", "16..32", "32..48"};
          char buf[200];
          std::snprintf(
              buf, sizeof buf,
              "SYSCTL: HFXT started with HFCLKCLKCFG.HFXTRSEL %u (%s MHz) for the board's %u Hz crystal "
              "(range %u, %s MHz)",
              range, kRanges[range], crystalHz_, wanted, kRanges[wanted]);
          machine_.violate(Rule::HfxtRange, buf);
        }
        const uint64_t startup = (hfclkclkcfg_ & kHfxtTimeMask) * 64 * machine_.cyclesPerUs();
        hfxtGoodAt_ = (hfclkclkcfg_ & kHfclkFaultCheck) ? machine_.now() + startup : UINT64_MAX;
      }
      return true;
    }
    case kHsclkcfg:
      hsclkcfg_ = value;
      return true;
    case kHfclkclkcfg:
      if ((hsclken_ & kHfxtEnable) && ((value ^ hfclkclkcfg_) & (kHfxtRangeMask | kHfxtTimeMask)) != 0) {
        machine_.stop(
            "SYSCTL: HFCLKCLKCFG.HFXTRSEL or HFXTTIME changed while HSCLKEN.HFXTEN is set (TI's HFXT set-up "
            "turns the HFXT off first)");
      }
      hfclkclkcfg_ = value;
      // The monitor switched on after the crystal: the check runs once the start-up time has passed.
      if ((hsclken_ & kHfxtEnable) && (value & kHfclkFaultCheck) && hfxtGoodAt_ == UINT64_MAX)
        hfxtGoodAt_ = machine_.now() + (value & kHfxtTimeMask) * 64 * machine_.cyclesPerUs();
      return true;
    default:
      return false;
  }
}

}  // namespace twin
