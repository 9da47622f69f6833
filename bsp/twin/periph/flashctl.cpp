#include "flashctl.hpp"

#include <algorithm>
#include <cstdio>

#include "machine.hpp"

namespace twin {

namespace {

// hw_flashctl.h offsets and fields (see flashctl.hpp).
constexpr uint32_t kCmdexec = 0x1100, kCmdtype = 0x1104, kCmdctl = 0x1108, kCmdaddr = 0x1120;
constexpr uint32_t kCmdbyten = 0x1124, kCmddata0 = 0x1130, kCmddata1 = 0x1134;
constexpr uint32_t kWeprotA = 0x11D0, kWeprotB = 0x11D4, kWeprotNm = 0x1210, kStatcmd = 0x13D0;
constexpr uint32_t kProgramOneWord = 0x01, kEraseSector = 0x42;  // CMDTYPE COMMAND | SIZE
constexpr uint32_t kDone = 1U << 0, kPass = 1U << 1, kInProgress = 1U << 2, kFailWeProt = 1U << 4;
constexpr uint32_t kFailIllAddr = 1U << 6;
constexpr uint32_t kEccGenOverride = 1U << 17;
constexpr uint32_t kNonmainBase = 0x41C00000, kNonmainEnd = 0x41C00400;  // NONMAIN 1 KB (bsl.md)

std::string hex(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

}  // namespace

Flashctl::Flashctl(Machine& machine, bool ecc)
    : machine_(machine), ecc_(ecc), done_(machine.timeline(), [this] { finish(); }) {}

void Flashctl::systemReset() {
  // A reset while the controller programs or erases ends the operation as a power cut would: TI documents
  // no completion across a reset, so the twin takes the side that leaves the word or sector torn.
  cutPower();
  cmdtype_ = cmdctl_ = cmdaddr_ = cmdbyten_ = data0_ = data1_ = 0;
  weprotA_ = weprotB_ = weprotNm_ = ~0U;
  statcmd_ = 0;
}

bool Flashctl::read(uint32_t offset, unsigned bytes, uint32_t& value) {
  if (bytes != 4) return false;
  switch (offset) {
    case kCmdtype:
      value = cmdtype_;
      return true;
    case kCmdctl:
      value = cmdctl_;
      return true;
    case kCmdaddr:
      value = cmdaddr_;
      return true;
    case kCmdbyten:
      value = cmdbyten_;
      return true;
    case kCmddata0:
      value = data0_;
      return true;
    case kCmddata1:
      value = data1_;
      return true;
    case kWeprotA:
      value = weprotA_;
      return true;
    case kWeprotB:
      value = weprotB_;
      return true;
    case kWeprotNm:
      value = weprotNm_;
      return true;
    case kStatcmd:
      value = statcmd_;
      return true;
    default:
      return false;
  }
}

bool Flashctl::write(uint32_t offset, unsigned bytes, uint32_t value) {
  if (bytes != 4) return false;
  if (op_ != Op::None && offset != kStatcmd) {
    // The TRM gives no meaning to a register write while a command runs; the firmware waits for CMDDONE.
    machine_.stop("FLASHCTL: register write at +" + hex(offset) + " while a command is in progress");
    return true;
  }
  switch (offset) {
    case kCmdexec:
      if ((value & 1U) != 0) execute();
      return true;
    case kCmdtype:
      cmdtype_ = value;
      return true;
    case kCmdctl:
      cmdctl_ = value;
      return true;
    case kCmdaddr:
      cmdaddr_ = value;
      return true;
    case kCmdbyten:
      cmdbyten_ = value;
      return true;
    case kCmddata0:
      data0_ = value;
      return true;
    case kCmddata1:
      data1_ = value;
      return true;
    case kWeprotA:
      weprotA_ = value;
      return true;
    case kWeprotB:
      weprotB_ = value;
      return true;
    case kWeprotNm:
      if (value != ~0U) {
        machine_.violate(Rule::FlashRegion, "FLASHCTL: CMDWEPROTNM written with " + hex(value) +
                                                ": NONMAIN (the boot configuration) unprotected");
      }
      weprotNm_ = value;
      return true;
    default:
      return false;
  }
}

bool Flashctl::sectorProtected(uint32_t sector) const {
  if (sector < 32) return ((weprotA_ >> sector) & 1U) != 0;
  return ((weprotB_ >> ((sector - 32) / 8)) & 1U) != 0;
}

void Flashctl::fail(uint32_t why) {
  statcmd_ = kDone | why;  // CMDPASS clear: failed
  weprotA_ = weprotB_ = ~0U;
}

void Flashctl::execute() {
  const uint32_t flashSize = machine_.layout().flashSize;
  if (cmdaddr_ - kNonmainBase < kNonmainEnd - kNonmainBase) {
    machine_.violate(Rule::FlashRegion, "FLASHCTL: command at " + hex(cmdaddr_) + " in NONMAIN");
    return;
  }
  if (cmdtype_ != kProgramOneWord && cmdtype_ != kEraseSector) {
    machine_.stop("FLASHCTL: CMDTYPE " + hex(cmdtype_) +
                  " not modelled (PROGRAM ONEWORD and ERASE SECTOR only)");
    return;
  }
  if (cmdaddr_ >= flashSize) {
    fail(kFailIllAddr);  // hw_flashctl.h STATCMD.FAILILLADDR
    return;
  }
  const uint32_t sector = cmdaddr_ / kSectorBytes;
  if (sector * kSectorBytes < imageEnd_) {
    machine_.violate(Rule::FlashRegion, "FLASHCTL: command at " + hex(cmdaddr_) + " in sector " +
                                            std::to_string(sector) + ", which holds the image (image end " +
                                            hex(imageEnd_) + ")");
    return;
  }
  if (sectorProtected(sector)) {
    fail(kFailWeProt);
    machine_.violate(Rule::FlashProtected,
                     "FLASHCTL: command at " + hex(cmdaddr_) + " with sector " + std::to_string(sector) +
                         " still protected (CMDWEPROTA/B): STATCMD FAILWEPROT, nothing written");
    return;
  }
  const bool program = cmdtype_ == kProgramOneWord;
  if (program) {
    const uint32_t wantByten = ecc_ ? 0x1FFU : 0xFFU;
    if ((cmdaddr_ & 7U) != 0 || cmdbyten_ != wantByten || (cmdctl_ & kEccGenOverride) != 0) {
      machine_.stop("FLASHCTL: program at " + hex(cmdaddr_) + " with CMDBYTEN " + hex(cmdbyten_) +
                    ", CMDCTL " + hex(cmdctl_) + ": only a whole aligned 64-bit word" +
                    (ecc_ ? " with hardware ECC (CMDBYTEN 0x1FF, ECCGENOVR clear)" : " (CMDBYTEN 0xFF)") +
                    " is modelled");
      return;
    }
    const auto& flash = machine_.flash();
    if (!std::all_of(flash.begin() + cmdaddr_, flash.begin() + cmdaddr_ + 8,
                     [](uint8_t b) { return b == 0xFF; })) {
      machine_.violate(Rule::FlashUnerased, "FLASHCTL: program at " + hex(cmdaddr_) +
                                                " into a word that is not erased" +
                                                (ecc_ ? ": its ECC no longer matches, reads fault" : ""));
      return;
    }
  }
  op_ = program ? Op::Program : Op::Erase;
  ++started_;
  opStart_ = machine_.now();
  statcmd_ = kInProgress;
  const uint64_t end = opStart_ + (program ? kProgramUs : kEraseUs) * machine_.cyclesPerUs();
  done_.at(end);
  machine_.stallFlashUntil(end);
}

void Flashctl::finish() {
  auto& flash = machine_.flash();
  if (op_ == Op::Program) {
    for (unsigned i = 0; i < 8; ++i)
      flash[cmdaddr_ + i] = static_cast<uint8_t>((i < 4 ? data0_ >> (8 * i) : data1_ >> (8 * (i - 4))));
  } else if (op_ == Op::Erase) {
    const uint32_t first = cmdaddr_ / kSectorBytes * kSectorBytes;
    std::fill(flash.begin() + first, flash.begin() + first + kSectorBytes, 0xFF);
  }
  op_ = Op::None;
  machine_.stallFlashUntil(0);  // the bank answers reads again
  statcmd_ = kDone | kPass;
  weprotA_ = weprotB_ = ~0U;  // re-protected after every command
}

void Flashctl::cutPower() {
  if (op_ == Op::None) return;
  leaveCut(machine_.flash());
  done_.cancel();
  machine_.stallFlashUntil(0);
  op_ = Op::None;
  statcmd_ = 0;
}

void Flashctl::leaveCut(std::vector<uint8_t>& flash) const {
  if (op_ == Op::None) return;
  const uint64_t total = done_.when() - opStart_;
  const uint64_t elapsed = std::min(machine_.now() - opStart_, total);
  if (op_ == Op::Program) {
    const unsigned bytes = static_cast<unsigned>(8 * elapsed / total);
    for (unsigned i = 0; i < bytes; ++i)
      flash[cmdaddr_ + i] = static_cast<uint8_t>((i < 4 ? data0_ >> (8 * i) : data1_ >> (8 * (i - 4))));
    // The next byte half-programmed: its 1 -> 0 bits of the low nibble only.
    if (bytes < 8) {
      const uint8_t want =
          static_cast<uint8_t>(bytes < 4 ? data0_ >> (8 * bytes) : data1_ >> (8 * (bytes - 4)));
      flash[cmdaddr_ + bytes] = static_cast<uint8_t>(want | 0xF0);
    }
  } else {
    const uint32_t first = cmdaddr_ / kSectorBytes * kSectorBytes;
    const uint32_t bytes = static_cast<uint32_t>(kSectorBytes * elapsed / total);
    std::fill(flash.begin() + first, flash.begin() + first + bytes, 0xFF);
  }
}

}  // namespace twin
