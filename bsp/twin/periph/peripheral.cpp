#include "periph/peripheral.hpp"

#include <cstdio>

#include "machine.hpp"

namespace twin {

namespace {
constexpr uint32_t kEventBlockSize = 0x30;
constexpr uint32_t kPwrenKey = 0x26, kRstctlKey = 0xB1;
}  // namespace

bool EventRegs::read(uint32_t offset, uint32_t& value) {
  switch (offset) {
    case 0x00: {  // IIDX: lowest pending MIS bit + 1; the read clears that RIS bit
      const uint32_t m = mis();
      if (m == 0) {
        value = 0;
      } else {
        const int bitIndex = __builtin_ctz(m);
        value = static_cast<uint32_t>(bitIndex) + 1;
        ris &= ~(1U << bitIndex);
      }
      return true;
    }
    case 0x08:
      value = imask;
      return true;
    case 0x10:
      value = ris;
      return true;
    case 0x18:
      value = mis();
      return true;
    case 0x20:
    case 0x28:
      value = 0;
      return true;  // write-only
    default:
      return false;
  }
}

bool EventRegs::write(uint32_t offset, uint32_t value) {
  switch (offset) {
    case 0x00:
    case 0x10:
    case 0x18:
      return true;  // read-only
    case 0x08:
      imask = value;
      return true;
    case 0x20:
      ris |= value;
      return true;
    case 0x28:
      ris &= ~value;
      return true;
    default:
      return false;
  }
}

bool ClockRegs::read(uint32_t offset, uint32_t& value) const {
  if (offset != 0x1000 && offset != selOffset) return false;
  value = offset == 0x1000 ? div : sel;
  return true;
}

bool ClockRegs::write(uint32_t offset, uint32_t value) {
  if (offset != 0x1000 && offset != selOffset) return false;
  (offset == 0x1000 ? div : sel) = value;
  return true;
}

Peripheral::Peripheral(Machine& machine, std::string name, uint32_t gprcmOffset, uint32_t cpuIntOffset)
    : machine_(machine), name_(std::move(name)), gprcmOffset_(gprcmOffset), cpuIntOffset_(cpuIntOffset) {}

void Peripheral::stop(const std::string& why) {
  machine_.stop(name_ + ": " + why);
}

void Peripheral::systemReset() {
  powered_ = false;
  resetSticky_ = true;
  cpuInt_ = {};
  resetRegisters();
  updateInterrupt();
}

void Peripheral::updateInterrupt() {
  const bool level = cpuInt_.mis() != 0;
  if (level == lineLevel_) return;
  lineLevel_ = level;
  if (line_) line_(level);
}

bool Peripheral::read(uint32_t offset, unsigned bytes, uint32_t& value) {
  if ((offset & 3U) != 0) return false;
  if (bytes != 4) {
    // A narrower access to a register's lowest byte lanes (the DMA moving bytes to and from TXDATA/RXDATA
    // with DMASRCWDTH/DMADSTWDTH = byte, as TI's UART DMA examples do) reads the register's low bits.
    uint32_t word = 0;
    const bool ok = read(offset, 4, word);
    value = word & ((1U << (8 * bytes)) - 1);
    return ok;
  }
  if (offset == gprcmOffset_) {
    value = powered_ ? 1U : 0U;
    return true;
  }
  if (offset == gprcmOffset_ + 0x14) {
    value = resetSticky_ ? 1U << 16 : 0U;
    return true;
  }
  if (offset == gprcmOffset_ + 4) {
    value = 0;  // RSTCTL is write-only
    return true;
  }
  if (!powered_) {
    char buf[80];
    std::snprintf(buf, sizeof buf, "read of +0x%X while the peripheral is not powered (GPRCM.PWREN)", offset);
    stop(buf);
    value = 0;
    return true;
  }
  if (offset - cpuIntOffset_ < kEventBlockSize) {
    const bool ok = cpuInt_.read(offset - cpuIntOffset_, value);
    updateInterrupt();  // an IIDX read clears a flag
    return ok;
  }
  return readRegister(offset, value);
}

bool Peripheral::write(uint32_t offset, unsigned bytes, uint32_t value) {
  if ((offset & 3U) != 0) return false;
  if (bytes != 4) return write(offset, 4, value & ((1U << (8 * bytes)) - 1));  // low byte lanes (DMA)
  if (offset == gprcmOffset_) {
    if (machine_.checkKey(name_ + " GPRCM.PWREN", value, kPwrenKey))
      powered_ = (value & 1U) != 0;  // without the key: ignored
    return true;
  }
  if (offset == gprcmOffset_ + 4) {
    if (!machine_.checkKey(name_ + " GPRCM.RSTCTL", value, kRstctlKey)) return true;
    if (value & 2U) resetSticky_ = false;
    if (value & 1U) {
      resetSticky_ = true;
      cpuInt_ = {};
      resetRegisters();
      updateInterrupt();
    }
    return true;
  }
  if (offset == gprcmOffset_ + 0x14) return true;  // STAT is read-only
  if (!powered_) {
    char buf[96];
    std::snprintf(buf, sizeof buf,
                  "write of 0x%08X to +0x%X while the peripheral is not powered (GPRCM.PWREN)", value,
                  offset);
    stop(buf);
    return true;
  }
  if (offset - cpuIntOffset_ < kEventBlockSize) {
    const bool ok = cpuInt_.write(offset - cpuIntOffset_, value);
    updateInterrupt();
    if (ok) onCpuIntWrite(offset - cpuIntOffset_, value);
    return ok;
  }
  return writeRegister(offset, value);
}

}  // namespace twin
