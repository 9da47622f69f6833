#include "bsl/boot_code.hpp"

#include <algorithm>

namespace twin {

BootCode::BootCode(Machine& machine, Sysctl& sysctl, Pins& pins, RomBsl& bsl, int invokePincm)
    : machine_(machine), sysctl_(sysctl), pins_(pins), bsl_(bsl), invokePincm_(invokePincm) {
  machine.onReset([this](ResetKind kind) { afterReset(kind); });
}

bool BootCode::flashBlank() const {
  const auto& flash = machine_.flash();
  return std::all_of(flash.begin(), flash.begin() + 8, [](uint8_t b) { return b == 0xFF; });
}

void BootCode::afterReset(ResetKind kind) {
  const Sysctl::BootRequest request = sysctl_.takeBootRequest();
  reason_.clear();
  if (request == Sysctl::BootRequest::EnterBootloader) {
    reason_ = "software invoke (RESETLEVEL BOOTLOADERENTRY)";
  } else if (request == Sysctl::BootRequest::ExitBootloader || kind != ResetKind::Sysrst) {
    if (request != Sysctl::BootRequest::ExitBootloader && pins_.level(invokePincm_)) {
      reason_ = "invoke pin PA18 high at reset";
    } else if (flashBlank()) {
      reason_ = "MAIN flash blank (initial SP and reset vector erased)";
    }
  }
  machine_.holdCore(!reason_.empty());
  if (reason_.empty()) {
    bsl_.stop();
  } else {
    bsl_.start(reason_);
  }
}

}  // namespace twin
