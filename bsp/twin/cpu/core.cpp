#include "cpu/core.hpp"

#include <cstdio>

#include "cpu/timing.hpp"

namespace twin {

namespace {

std::string hex(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

uint32_t bit(uint32_t v, unsigned n) {
  return (v >> n) & 1U;
}

int32_t signExtend(uint32_t v, unsigned bits) {
  const uint32_t m = 1U << (bits - 1);
  return static_cast<int32_t>((v ^ m) - m);
}

// EXC_RETURN values of ARMv6-M (B1.5.8): return to Handler (MSP), Thread (MSP), Thread (PSP).
constexpr uint32_t kReturnHandler = 0xFFFFFFF1;
constexpr uint32_t kReturnThreadMsp = 0xFFFFFFF9;
constexpr uint32_t kReturnThreadPsp = 0xFFFFFFFD;

}  // namespace

std::string Core::where() const {
  return "PC " + hex(pc_);
}

void Core::halt(const std::string& why) {
  if (halted_) return;
  halted_ = true;
  haltReason_ = why;
}

void Core::reset() {
  r_.fill(0);
  lr_ = 0xFFFFFFFF;  // B1.5.5: LR UNKNOWN; all ones makes a return from the reset handler a fault
  n_ = z_ = c_ = v_ = false;
  ipsr_ = 0;
  primask_ = spsel_ = npriv_ = false;
  vtor_ = 0;
  sleeping_ = waitForEvent_ = event_ = faulted_ = false;
  sleepOnExit_ = false;
  nvic_.reset();
  uint32_t sp = 0, entry = 0;
  if (!load(vtor_, 4, sp) || !load(vtor_ + 4, 4, entry)) {
    halt("reset: no vector table at " + hex(vtor_));
    return;
  }
  msp_ = sp & ~3U;
  psp_ = 0;
  thumb_ = true;
  pc_ = next_ = entry & ~1U;
  if ((entry & 1U) == 0) halt("reset: the reset vector " + hex(entry) + " has bit 0 clear (not Thumb)");
}

uint32_t Core::reg(int n) const {
  if (n < 13) return r_[static_cast<size_t>(n)];
  if (n == 13) return (ipsr_ != 0 || !spsel_) ? msp_ : psp_;
  if (n == 14) return lr_;
  return pc_ + 4;  // an instruction reads PC as its own address + 4 (A5.1.2)
}

void Core::setReg(int n, uint32_t value) {
  if (n < 13) {
    r_[static_cast<size_t>(n)] = value;
  } else if (n == 13) {
    sp() = value & ~3U;  // SP[1:0] are zero (B1.4.1)
  } else if (n == 14) {
    lr_ = value;
  } else {
    pc_ = next_ = value & ~1U;
  }
}

uint32_t Core::apsr() const {
  return (n_ ? 1U << 31 : 0) | (z_ ? 1U << 30 : 0) | (c_ ? 1U << 29 : 0) | (v_ ? 1U << 28 : 0);
}

void Core::setApsr(uint32_t value) {
  n_ = bit(value, 31), z_ = bit(value, 30), c_ = bit(value, 29), v_ = bit(value, 28);
}

bool Core::load(uint32_t address, unsigned bytes, uint32_t& value) {
  if ((address & (bytes - 1)) != 0) {
    fault("unaligned " + std::to_string(bytes) + "-byte load from " + hex(address));
    return false;
  }
  const uint8_t* p = nullptr;
  if (address < flashSize_) {
    if (flashBusy_ && !vectorFetch_) {
      // On a part with one bank a program or erase stalls every read request to the flash, data loads as
      // well as fetches, until it completes (SLAU846A NVM chapter, flash banks; SLAAE56A flash memory
      // organization): the load waits, so the instruction runs again once the bank is free.
      waitingForFlash_ = true;
      return false;
    }
    p = flash_ + address;
  } else if (address - sramBase_ < sramSize_) {
    p = sram_ + (address - sramBase_);
  }
  if (p != nullptr) {
    if (watch_ != nullptr && !stacking_ && address >= sramBase_) watch_->onSramLoad(address, bytes);
    value = p[0];
    if (bytes >= 2) value |= static_cast<uint32_t>(p[1]) << 8;
    if (bytes == 4) value |= static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
    return true;
  }
  if (bus_.load(address, bytes, value)) return true;
  halt("load of " + std::to_string(bytes) + " bytes from " + hex(address) + " (" + bus_.describe(address) +
       ") at " + where());
  return false;
}

bool Core::store(uint32_t address, unsigned bytes, uint32_t value) {
  if ((address & (bytes - 1)) != 0) {
    fault("unaligned " + std::to_string(bytes) + "-byte store to " + hex(address));
    return false;
  }
  if (address - sramBase_ < sramSize_) {
    if (watch_ != nullptr && !stacking_) watch_->onSramStore(address, bytes);
    uint8_t* p = sram_ + (address - sramBase_);
    p[0] = static_cast<uint8_t>(value);
    if (bytes >= 2) p[1] = static_cast<uint8_t>(value >> 8);
    if (bytes == 4) p[2] = static_cast<uint8_t>(value >> 16), p[3] = static_cast<uint8_t>(value >> 24);
    return true;
  }
  if (address >= flashSize_ && bus_.store(address, bytes, value)) return true;
  halt("store of " + std::to_string(bytes) + " bytes (" + hex(value) + ") to " + hex(address) + " (" +
       (address < flashSize_ ? std::string("flash is written through FLASHCTL only")
                             : bus_.describe(address)) +
       ") at " + where());
  return false;
}

bool Core::fetch(uint32_t address, uint16_t& op) {
  if (address + 1 < flashSize_) {
    op = static_cast<uint16_t>(flash_[address] | flash_[address + 1] << 8);
    return true;
  }
  uint32_t v = 0;
  if (address - sramBase_ < sramSize_ && load(address, 2, v)) {
    op = static_cast<uint16_t>(v);
    return true;
  }
  halt("instruction fetch from " + hex(address) + ", outside flash and SRAM");
  return false;
}

uint32_t Core::addWithCarry(uint32_t x, uint32_t y, bool carry) {
  const uint64_t sum = static_cast<uint64_t>(x) + y + (carry ? 1 : 0);
  const auto result = static_cast<uint32_t>(sum);
  setNz(result);
  c_ = (sum >> 32) != 0;
  v_ = (((x ^ result) & (y ^ result)) >> 31) != 0;
  return result;
}

bool Core::condition(uint32_t cond) const {
  switch (cond) {
    case 0x0:
      return z_;
    case 0x1:
      return !z_;
    case 0x2:
      return c_;
    case 0x3:
      return !c_;
    case 0x4:
      return n_;
    case 0x5:
      return !n_;
    case 0x6:
      return v_;
    case 0x7:
      return !v_;
    case 0x8:
      return c_ && !z_;
    case 0x9:
      return !c_ || z_;
    case 0xA:
      return n_ == v_;
    case 0xB:
      return n_ != v_;
    case 0xC:
      return !z_ && n_ == v_;
    case 0xD:
      return z_ || n_ != v_;
    default:
      return true;
  }
}

void Core::fault(const std::string& why, bool completed) {
  if (faulted_) return;
  faulted_ = !completed;
  ++hardFaults_;
  const std::string text = why + " at " + where();
  if (observer_ != nullptr) observer_->onHardFault(text);
  // B1.5.13: a fault while NMI or HardFault is active locks the core up.
  if (nvic_.active(Nvic::kHardFault) || nvic_.active(Nvic::kNmi)) {
    halt("lockup: " + text + " inside HardFault/NMI");
    return;
  }
  nvic_.setPending(Nvic::kHardFault);
}

void Core::bxWritePc(uint32_t address) {
  // B1.5.8: EXC_RETURN is recognised when loaded into PC in Handler mode.
  if (ipsr_ != 0 && (address >> 28) == 0xF) {
    exceptionReturn(address);
    return;
  }
  // BXWritePC: EPSR.T = address<0>; the next instruction faults if it is 0 (step()).
  thumb_ = (address & 1U) != 0;
  next_ = address & ~1U;
}

void Core::takeException(int exception, uint32_t returnAddress) {
  // PushStack (B1.5.6): eight words on the stack in use, 8-byte aligned, xPSR bit 9 records the padding.
  if (ipsr_ == 0) handlerStackTop_ = msp_;
  const bool threadPsp = ipsr_ == 0 && spsel_;
  uint32_t& sp = threadPsp ? psp_ : msp_;
  const uint32_t padding = (sp >> 2) & 1U;
  const uint32_t frame = (sp - 0x20) & ~7U;
  const uint32_t xpsr = apsr() | ipsr_ | (padding << 9) | (thumb_ ? 1U << 24 : 0U);
  const uint32_t words[8] = {r_[0], r_[1], r_[2], r_[3], r_[12], lr_, returnAddress, xpsr};
  stacking_ = true;
  for (uint32_t i = 0; i < 8; ++i) {
    if (!store(frame + 4 * i, 4, words[i])) {
      stacking_ = false;
      halt("exception " + std::to_string(exception) + ": stacking to " + hex(frame + 4 * i) + " failed");
      return;
    }
  }
  stacking_ = false;
  sp = frame;
  lr_ = ipsr_ != 0 ? kReturnHandler : threadPsp ? kReturnThreadPsp : kReturnThreadMsp;
  // ExceptionTaken (B1.5.6): Handler mode on the main stack.
  ipsr_ = static_cast<uint32_t>(exception);
  spsel_ = false;
  nvic_.activate(exception);
  event_ = true;
  uint32_t vector = 0;
  vectorFetch_ = true;
  const bool fetched = load(vtor_ + 4U * static_cast<uint32_t>(exception), 4, vector);
  vectorFetch_ = false;
  if (!fetched) {
    halt("exception " + std::to_string(exception) + ": no vector at " + hex(vtor_ + 4U * exception));
    return;
  }
  if (observer_ != nullptr) observer_->onExceptionEntry(exception);
  pc_ = next_ = vector & ~1U;
  thumb_ = true;
  if ((vector & 1U) == 0) {
    // EPSR.T = 0: the first instruction of the handler faults (B1.5.6, B1.4.2).
    faulted_ = false;
    fault("exception " + std::to_string(exception) + " vector " + hex(vector) + " has bit 0 clear");
  }
}

void Core::exceptionReturn(uint32_t excReturn) {
  const int returning = static_cast<int>(ipsr_);
  if (excReturn != kReturnHandler && excReturn != kReturnThreadMsp && excReturn != kReturnThreadPsp) {
    fault("exception return with invalid EXC_RETURN " + hex(excReturn));
    return;
  }
  nvic_.deactivate(returning);
  if (observer_ != nullptr) observer_->onExceptionReturn(returning);
  const bool toThread = excReturn != kReturnHandler;
  if (toThread && nvic_.activeMask() != 0) {
    halt("exception " + std::to_string(returning) + " returns to Thread mode with exceptions still active");
    return;
  }
  uint32_t& sp = excReturn == kReturnThreadPsp ? psp_ : msp_;
  uint32_t words[8];
  stacking_ = true;
  for (uint32_t i = 0; i < 8; ++i) {
    if (!load(sp + 4 * i, 4, words[i])) {
      stacking_ = false;
      halt("exception return: unstacking from " + hex(sp + 4 * i) + " failed");
      return;
    }
  }
  stacking_ = false;
  const uint32_t xpsr = words[7];
  sp = (sp + 0x20) | (bit(xpsr, 9) << 2);
  r_[0] = words[0], r_[1] = words[1], r_[2] = words[2], r_[3] = words[3], r_[12] = words[4];
  lr_ = words[5];
  setApsr(xpsr);
  ipsr_ = xpsr & 0x3FU;
  if (toThread != (ipsr_ == 0)) {
    halt("exception return: stacked IPSR " + std::to_string(ipsr_) + " does not match EXC_RETURN " +
         hex(excReturn));
    return;
  }
  spsel_ = excReturn == kReturnThreadPsp;
  next_ = words[6] & ~1U;
  thumb_ = ((xpsr >> 24) & 1U) != 0;
  event_ = true;
  extraCycles_ = cycles::kExceptionReturn;
  // Sleep-on-exit (B3.2.7 SCR.SLEEPONEXIT: on the return to the base level of execution priority). The
  // Cortex-M0+ may skip the unstacking here and the stacking at the next entry; the twin pays both (its
  // cycle counts err on the busy side) and resumes the Thread at the stacked address when woken.
  if (toThread && sleepOnExit_) sleeping_ = true;
}

uint32_t Core::step() {
  if (halted_) return 0;
  if (sleeping_) {
    // WFI wakes on an exception that would preempt if PRIMASK were 0 (B1.5.19); WFE also on an event.
    const bool wake = nvic_.pendingToTake(nvic_.executionPriority(false)) != 0 || (waitForEvent_ && event_);
    if (!wake) return 0;
    sleeping_ = false;
    if (waitForEvent_) event_ = false;
    waitForEvent_ = false;
  }
  if (nvic_.anyPending()) {
    const int e = nvic_.pendingToTake(nvic_.executionPriority(primask_));
    if (e != 0) {
      takeException(e, pc_);
      return cycles::kExceptionEntry;
    }
  }
  if (!thumb_) {  // EPSR.T = 0: the instruction here cannot execute (INVSTATE, B1.4.2)
    faulted_ = false;
    fault("instruction at " + hex(pc_) +
          " with EPSR.T = 0 (INVSTATE: a branch to an address with bit 0 clear)");
    return cycles::kAlu;
  }
  uint16_t op = 0;
  if (!fetch(pc_, op)) return 0;
  waitingForFlash_ = false;
  faulted_ = false;
  extraCycles_ = 0;
  next_ = pc_ + 2;
  ++instructions_;
  uint32_t spent;
  if ((op >> 11) >= 0x1D) {
    uint16_t hw2 = 0;
    if (!fetch(pc_ + 2, hw2)) return 0;
    next_ = pc_ + 4;
    spent = execute32(op, hw2);
  } else {
    spent = execute(op);
  }
  if (waitingForFlash_) {  // a load from the busy bank: nothing done (loads write no register before the
    --instructions_;       // last one is in), the same instruction runs again
    return 0;
  }
  if (!faulted_) pc_ = next_;  // a faulting instruction returns to itself (HardFault's ReturnAddress)
  return spent + extraCycles_;
}

uint32_t Core::execute(uint16_t op) {
  using namespace cycles;
  const uint32_t rd = op & 7U, rn = (op >> 3) & 7U, rm = (op >> 6) & 7U;
  switch (op >> 11) {
    case 0x00: {  // LSLS Rd, Rm, #imm5 (imm5 = 0: MOVS Rd, Rm)
      const uint32_t sh = (op >> 6) & 31U, v = r_[rn];
      if (sh != 0) c_ = bit(v, 32 - sh);
      r_[rd] = sh != 0 ? v << sh : v;
      setNz(r_[rd]);
      return kAlu;
    }
    case 0x01: {  // LSRS Rd, Rm, #imm5 (0 means 32)
      const uint32_t sh = (op >> 6) & 31U, v = r_[rn];
      c_ = sh != 0 ? bit(v, sh - 1) : bit(v, 31);
      r_[rd] = sh != 0 ? v >> sh : 0;
      setNz(r_[rd]);
      return kAlu;
    }
    case 0x02: {  // ASRS Rd, Rm, #imm5 (0 means 32)
      const uint32_t sh = (op >> 6) & 31U, v = r_[rn];
      c_ = sh != 0 ? bit(v, sh - 1) : bit(v, 31);
      r_[rd] = static_cast<uint32_t>(static_cast<int32_t>(v) >> (sh != 0 ? sh : 31));
      setNz(r_[rd]);
      return kAlu;
    }
    case 0x03: {  // ADDS/SUBS Rd, Rn, Rm | #imm3
      const uint32_t operand = bit(op, 10) ? rm : r_[rm];
      r_[rd] = bit(op, 9) ? addWithCarry(r_[rn], ~operand, true) : addWithCarry(r_[rn], operand, false);
      return kAlu;
    }
    case 0x04:  // MOVS Rd, #imm8
      r_[(op >> 8) & 7U] = op & 0xFFU;
      setNz(op & 0xFFU);
      return kAlu;
    case 0x05:  // CMP Rn, #imm8
      addWithCarry(r_[(op >> 8) & 7U], ~(op & 0xFFU), true);
      return kAlu;
    case 0x06: {  // ADDS Rdn, #imm8
      uint32_t& r = r_[(op >> 8) & 7U];
      r = addWithCarry(r, op & 0xFFU, false);
      return kAlu;
    }
    case 0x07: {  // SUBS Rdn, #imm8
      uint32_t& r = r_[(op >> 8) & 7U];
      r = addWithCarry(r, ~(op & 0xFFU), true);
      return kAlu;
    }
    case 0x08:
      if ((op & 0x0400) == 0) {  // data processing (A5.2.2)
        uint32_t& d = r_[rd];
        const uint32_t m = r_[rn];
        switch ((op >> 6) & 0xF) {
          case 0x0:
            setNz(d &= m);
            break;
          case 0x1:
            setNz(d ^= m);
            break;
          case 0x2: {  // LSLS Rdn, Rm
            const uint32_t sh = m & 0xFF;
            if (sh != 0) c_ = sh <= 32 ? bit(d, 32 - sh) : false, d = sh < 32 ? d << sh : 0;
            setNz(d);
            break;
          }
          case 0x3: {  // LSRS Rdn, Rm
            const uint32_t sh = m & 0xFF;
            if (sh != 0) c_ = sh <= 32 ? bit(d, sh - 1) : false, d = sh < 32 ? d >> sh : 0;
            setNz(d);
            break;
          }
          case 0x4: {  // ASRS Rdn, Rm
            const uint32_t sh = m & 0xFF;
            if (sh != 0) {
              c_ = bit(d, sh < 32 ? sh - 1 : 31);
              d = static_cast<uint32_t>(static_cast<int32_t>(d) >> (sh < 32 ? sh : 31));
            }
            setNz(d);
            break;
          }
          case 0x5:
            d = addWithCarry(d, m, c_);
            break;  // ADCS
          case 0x6:
            d = addWithCarry(d, ~m, c_);
            break;     // SBCS
          case 0x7: {  // RORS Rdn, Rm
            const uint32_t sh = m & 0xFF;
            if (sh != 0) {
              const uint32_t r = sh & 31U;
              if (r != 0) d = (d >> r) | (d << (32 - r));
              c_ = bit(d, 31);
            }
            setNz(d);
            break;
          }
          case 0x8:
            setNz(d & m);
            break;  // TST
          case 0x9:
            d = addWithCarry(~m, 0, true);
            break;  // RSBS Rd, Rn, #0
          case 0xA:
            addWithCarry(d, ~m, true);
            break;  // CMP
          case 0xB:
            addWithCarry(d, m, false);
            break;  // CMN
          case 0xC:
            setNz(d |= m);
            break;   // ORRS
          case 0xD:  // MULS Rdm, Rn, Rdm: N, Z only (A6.7.44)
            setNz(d *= m);
            return kMultiply;
          case 0xE:
            setNz(d &= ~m);
            break;  // BICS
          default:
            setNz(d = ~m);
            break;  // MVNS
        }
        return kAlu;
      } else {  // special data processing and branch/exchange (A5.2.3)
        const uint32_t d = ((op >> 4) & 8U) | rd, m = (op >> 3) & 0xFU;
        switch ((op >> 8) & 3U) {
          case 0: {  // ADD Rdn, Rm (no flags)
            const uint32_t v = reg(static_cast<int>(d)) + reg(static_cast<int>(m));
            if (d == 15) {
              branchWritePc(v);
              return kWritePc;
            }
            setReg(static_cast<int>(d), v);
            return kAlu;
          }
          case 1:  // CMP Rn, Rm
            addWithCarry(reg(static_cast<int>(d)), ~reg(static_cast<int>(m)), true);
            return kAlu;
          case 2:  // MOV Rd, Rm
            if (d == 15) {
              branchWritePc(reg(static_cast<int>(m)));
              return kWritePc;
            }
            setReg(static_cast<int>(d), reg(static_cast<int>(m)));
            return kAlu;
          default: {  // BX / BLX Rm
            const uint32_t target = reg(static_cast<int>(m));
            if (bit(op, 7)) lr_ = (pc_ + 2) | 1U;
            bxWritePc(target);
            return kBranchExchange;
          }
        }
      }
    case 0x09: {  // LDR Rt, [PC, #imm8*4]
      uint32_t v = 0;
      if (load(((pc_ + 4) & ~3U) + (op & 0xFFU) * 4, 4, v)) r_[(op >> 8) & 7U] = v;
      return kLoadStore;
    }
    case 0x0A:
    case 0x0B: {  // load/store register offset (A5.2.4)
      const uint32_t address = r_[rn] + r_[rm];
      uint32_t v = 0;
      switch ((op >> 9) & 7U) {
        case 0:
          store(address, 4, r_[rd]);
          break;
        case 1:
          store(address, 2, r_[rd] & 0xFFFF);
          break;
        case 2:
          store(address, 1, r_[rd] & 0xFF);
          break;
        case 3:
          if (load(address, 1, v)) r_[rd] = static_cast<uint32_t>(signExtend(v, 8));
          break;
        case 4:
          if (load(address, 4, v)) r_[rd] = v;
          break;
        case 5:
          if (load(address, 2, v)) r_[rd] = v;
          break;
        case 6:
          if (load(address, 1, v)) r_[rd] = v;
          break;
        default:
          if (load(address, 2, v)) r_[rd] = static_cast<uint32_t>(signExtend(v, 16));
          break;
      }
      return kLoadStore;
    }
    case 0x0C:
    case 0x0D:
    case 0x0E:
    case 0x0F:
    case 0x10:
    case 0x11: {  // STR/LDR word (imm5*4), byte (imm5), halfword (imm5*2)
      const uint32_t kind = op >> 11;
      const unsigned bytes = kind <= 0x0D ? 4 : kind <= 0x0F ? 1 : 2;
      const uint32_t address = r_[rn] + ((op >> 6) & 31U) * bytes;
      if (bit(op, 11)) {
        uint32_t v = 0;
        if (load(address, bytes, v)) r_[rd] = v;
      } else {
        store(address, bytes, bytes == 4 ? r_[rd] : r_[rd] & ((1U << (8 * bytes)) - 1));
      }
      return kLoadStore;
    }
    case 0x12:
    case 0x13: {  // STR/LDR Rt, [SP, #imm8*4]
      const uint32_t t = (op >> 8) & 7U, address = sp() + (op & 0xFFU) * 4;
      if (bit(op, 11)) {
        uint32_t v = 0;
        if (load(address, 4, v)) r_[t] = v;
      } else {
        store(address, 4, r_[t]);
      }
      return kLoadStore;
    }
    case 0x14:  // ADR Rd, label
      r_[(op >> 8) & 7U] = ((pc_ + 4) & ~3U) + (op & 0xFFU) * 4;
      return kAlu;
    case 0x15:  // ADD Rd, SP, #imm8*4
      r_[(op >> 8) & 7U] = sp() + (op & 0xFFU) * 4;
      return kAlu;
    case 0x16:
    case 0x17:  // miscellaneous (A5.2.5)
      switch ((op >> 8) & 0xF) {
        case 0x0:  // ADD/SUB SP, SP, #imm7*4
          sp() = bit(op, 7) ? sp() - (op & 0x7FU) * 4 : sp() + (op & 0x7FU) * 4;
          return kAlu;
        case 0x2:
          switch ((op >> 6) & 3U) {
            case 0:
              r_[rd] = static_cast<uint32_t>(signExtend(r_[rn] & 0xFFFF, 16));
              break;  // SXTH
            case 1:
              r_[rd] = static_cast<uint32_t>(signExtend(r_[rn] & 0xFF, 8));
              break;  // SXTB
            case 2:
              r_[rd] = r_[rn] & 0xFFFF;
              break;  // UXTH
            default:
              r_[rd] = r_[rn] & 0xFF;
              break;  // UXTB
          }
          return kAlu;
        case 0x4:
        case 0x5: {  // PUSH {list, LR}
          const uint32_t list = (op & 0xFFU) | (bit(op, 8) << 14);
          const auto count = static_cast<uint32_t>(__builtin_popcount(list));
          uint32_t address = sp() - 4 * count;
          const uint32_t base = address;
          for (int i = 0; i < 15; ++i) {
            if (((list >> i) & 1U) == 0) continue;
            if (!store(address, 4, reg(i))) return kMultipleBase + count;
            address += 4;
          }
          sp() = base;
          return kMultipleBase + count;
        }
        case 0x6:
          if ((op & 0xFFEF) == 0xB662) {  // CPSIE i / CPSID i: bit 4 (im) set disables
            setPrimask(bit(op, 4) != 0);
            return kCps;
          }
          break;
        case 0xA:
          switch ((op >> 6) & 3U) {
            case 0:
              r_[rd] = __builtin_bswap32(r_[rn]);
              return kAlu;  // REV
            case 1: {       // REV16
              const uint32_t v = r_[rn];
              r_[rd] = ((v & 0x00FF00FFU) << 8) | ((v >> 8) & 0x00FF00FFU);
              return kAlu;
            }
            case 3: {  // REVSH
              const uint32_t v = r_[rn];
              r_[rd] = static_cast<uint32_t>(signExtend(((v & 0xFF) << 8) | ((v >> 8) & 0xFF), 16));
              return kAlu;
            }
            default:
              break;
          }
          break;
        case 0xC:
        case 0xD: {  // POP {list, PC}
          const uint32_t list = (op & 0xFFU) | (bit(op, 8) << 15);
          const auto count = static_cast<uint32_t>(__builtin_popcount(list));
          uint32_t address = sp();
          uint32_t values[16];
          for (int i = 0; i < 16; ++i) {
            if (((list >> i) & 1U) == 0) continue;
            if (!load(address, 4, values[i])) return kMultipleBase + count;
            address += 4;
          }
          sp() = address;
          for (int i = 0; i < 15; ++i) {
            if ((list >> i) & 1U) setReg(i, values[i]);
          }
          if (bit(list, 15)) {
            bxWritePc(values[15]);
            return kMultipleBase + count + kPopPcExtra;
          }
          return kMultipleBase + count;
        }
        case 0xE:  // BKPT: without a debugger it escalates to HardFault (C1.7)
          fault("BKPT");
          return kHint;
        case 0xF:
          if ((op & 0xF) != 0) break;  // IT does not exist on ARMv6-M
          switch ((op >> 4) & 0xF) {
            case 0:
              return kHint;  // NOP
            case 1:
              return kHint;  // YIELD
            case 2:          // WFE (B1.5.18)
              if (event_) {
                event_ = false;
              } else {
                sleeping_ = waitForEvent_ = true;
              }
              return kWait;
            case 3:  // WFI (B1.5.19)
              if (observer_ != nullptr) observer_->onWfi();
              if (nvic_.pendingToTake(nvic_.executionPriority(false)) == 0) sleeping_ = true;
              return kWait;
            case 4:  // SEV
              event_ = true;
              return kHint;
            default:
              return kHint;  // other hints execute as NOP (A5.2.5)
          }
        default:
          break;
      }
      fault("undefined instruction " + hex(op));
      return kAlu;
    case 0x18: {  // STM Rn!, {list}
      const uint32_t n = (op >> 8) & 7U, list = op & 0xFFU;
      const auto count = static_cast<uint32_t>(__builtin_popcount(list));
      uint32_t address = r_[n];
      for (uint32_t i = 0; i < 8; ++i) {
        if (((list >> i) & 1U) == 0) continue;
        if (!store(address, 4, r_[i])) return kMultipleBase + count;
        address += 4;
      }
      r_[n] = address;
      return kMultipleBase + count;
    }
    case 0x19: {  // LDM Rn{!}, {list}: no writeback when Rn is in the list
      const uint32_t n = (op >> 8) & 7U, list = op & 0xFFU;
      const auto count = static_cast<uint32_t>(__builtin_popcount(list));
      uint32_t address = r_[n];
      uint32_t values[8];
      for (uint32_t i = 0; i < 8; ++i) {
        if (((list >> i) & 1U) == 0) continue;
        if (!load(address, 4, values[i])) return kMultipleBase + count;
        address += 4;
      }
      if (((list >> n) & 1U) == 0) r_[n] = address;
      for (uint32_t i = 0; i < 8; ++i) {
        if ((list >> i) & 1U) r_[i] = values[i];
      }
      return kMultipleBase + count;
    }
    case 0x1A:
    case 0x1B: {  // B<cond>, UDF, SVC (A5.2.6)
      const uint32_t cond = (op >> 8) & 0xF;
      if (cond == 0xE) {
        fault("UDF " + hex(op));
        return kAlu;
      }
      if (cond == 0xF) {  // SVC: taken at once, or HardFault if its priority cannot preempt (B1.5.6)
        if (nvic_.priority(Nvic::kSvcall) >= nvic_.executionPriority(primask_)) {
          // Escalated to HardFault. The SVC has completed (A6.7 SVC: its operation is CallSupervisor()), so
          // the return address stays SVCall's, the next instruction (B1.5.6 ReturnAddress); DDI 0419E does
          // not name the escalated case, QEMU's Cortex-M0 does the same (core_qemu_test.cpp; README open
          // questions).
          fault("SVC at a priority that cannot take SVCall", true);
        } else {
          nvic_.setPending(Nvic::kSvcall);
        }
        return kAlu;
      }
      if (!condition(cond)) return kBranchNotTaken;
      branchWritePc(pc_ + 4 + static_cast<uint32_t>(signExtend(op & 0xFFU, 8) * 2));
      return kBranchTaken;
    }
    case 0x1C:  // B label
      branchWritePc(pc_ + 4 + static_cast<uint32_t>(signExtend(op & 0x7FFU, 11) * 2));
      return kBranchTaken;
    default:
      break;
  }
  fault("undefined instruction " + hex(op));
  return kAlu;
}

uint32_t Core::execute32(uint16_t hw1, uint16_t hw2) {
  using namespace cycles;
  if ((hw1 & 0xF800) == 0xF000 && (hw2 & 0xD000) == 0xD000) {  // BL (A6.7.13)
    const uint32_t s = bit(hw1, 10), j1 = bit(hw2, 13), j2 = bit(hw2, 11);
    const uint32_t i1 = (j1 ^ s) ^ 1U, i2 = (j2 ^ s) ^ 1U;
    const uint32_t imm = (s << 24) | (i1 << 23) | (i2 << 22) | ((hw1 & 0x3FFU) << 12) | ((hw2 & 0x7FFU) << 1);
    lr_ = (pc_ + 4) | 1U;
    branchWritePc(pc_ + 4 + static_cast<uint32_t>(signExtend(imm, 25)));
    return kBranchLink;
  }
  if ((hw1 & 0xFFF0) == 0xF380 && (hw2 & 0xFF00) == 0x8800) {  // MSR spec_reg, Rn (A6.7.42, B5.2.3)
    const uint32_t v = reg(hw1 & 0xF), sysm = hw2 & 0xFF;
    if (sysm <= 3) {
      setApsr(v);
    } else if (sysm == 8) {
      msp_ = v & ~3U;
    } else if (sysm == 9) {
      psp_ = v & ~3U;
    } else if (sysm == 16) {
      setPrimask((v & 1U) != 0);
    } else if (sysm == 20) {
      npriv_ = (v & 1U) != 0;
      if (ipsr_ == 0) spsel_ = (v & 2U) != 0;  // SPSEL is writable in Thread mode only
    }
    return kSpecialRegister;
  }
  if (hw1 == 0xF3EF && (hw2 & 0xF000) == 0x8000) {  // MRS Rd, spec_reg (A6.7.41, B5.2.2)
    const uint32_t sysm = hw2 & 0xFF;
    uint32_t v = 0;
    if (sysm <= 7) {
      if ((sysm & 1U) != 0) v |= ipsr_;   // IPSR, IAPSR, XPSR, IEPSR
      if ((sysm & 4U) == 0) v |= apsr();  // APSR, IAPSR, EAPSR, XPSR; EPSR reads as zero
    } else if (sysm == 8) {
      v = msp_;
    } else if (sysm == 9) {
      v = psp_;
    } else if (sysm == 16) {
      v = primask_ ? 1U : 0U;
    } else if (sysm == 20) {
      v = control();
    }
    setReg(static_cast<int>((hw2 >> 8) & 0xF), v);
    return kSpecialRegister;
  }
  if (hw1 == 0xF3BF && (hw2 & 0xFF00) == 0x8F00) {  // DSB, DMB, ISB (A6.7.21, A6.7.20, A6.7.34)
    const uint32_t opc = (hw2 >> 4) & 0xF;
    if (opc >= 4 && opc <= 6) return kBarrier;
  }
  fault("undefined 32-bit instruction " + hex(static_cast<uint32_t>(hw1) << 16 | hw2));
  return kAlu;
}

}  // namespace twin
