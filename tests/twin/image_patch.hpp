// Patches that break an image in a chosen way (tests/twin/images_test.cpp BrokenImage.*): a register write
// given another value, an instruction taken out. The patches work on the flash image the ELF holds, found by
// running the image on the twin (the PCs that store to an address) and by reading the Thumb code backwards
// from there (which instruction last set the stored register).
//
// valueDef(): from `pc` backwards through straight-line code (at most 24 halfwords, never past a branch, a
// call, a POP or a function's first instruction) to the instruction that last wrote register `reg`.
// setValue(): makes that instruction produce `value`: a PC-relative LDR gets its literal word replaced; any
// other single instruction becomes MOVS reg, #value (value 0..255); an LSLS reg, reg, #k after a MOVS reg,
// #imm gets imm = value >> k (value a multiple of 1 << k, the quotient 0..255); a load from [Rn, #imm] gets
// the data it loads replaced (in flash, or .data's initial values in flash).
// setStoredValue(): all of it for one store, following a value ORed in from an argument to the caller.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "elf_file.hpp"

namespace twinpatch {

inline uint16_t half(const twin::ElfFile& elf, uint32_t at) {
  const auto& f = elf.flashImage();
  return static_cast<uint16_t>(f[at] | f[at + 1] << 8);
}

// Destination register of a 16-bit Thumb instruction, -1 if it writes none of r0..r7 (or is not
// straight-line code: then `stop` is set).
inline int destination(uint16_t op, bool& stop) {
  stop = false;
  if (op < 0x2000) return op & 7;                                        // shifts, ADD/SUB 3-bit
  if (op < 0x4000) return (op & 0x1800) == 0x0800 ? -1 : (op >> 8) & 7;  // MOV/CMP/ADD/SUB imm8
  if (op < 0x4400) {                                                     // data processing
    const int opc = (op >> 6) & 0xF;
    return (opc == 8 || opc == 10 || opc == 11) ? -1 : op & 7;  // TST, CMP, CMN
  }
  if (op < 0x4800) {  // hi-register, BX
    if ((op & 0x0300) == 0x0300 || (op & 0x0300) == 0x0100) {
      stop = (op & 0x0300) == 0x0300;
      return -1;
    }
    const int d = ((op >> 4) & 8) | (op & 7);
    if (d == 15) stop = true;
    return d < 8 ? d : -1;
  }
  if (op < 0x5000) return (op >> 8) & 7;                                  // LDR literal
  if (op < 0x6000) return ((op >> 9) & 7) >= 3 ? op & 7 : -1;             // register offset
  if (op < 0x9000) return (op & 0x0800) ? op & 7 : -1;                    // immediate offset
  if (op < 0xA000) return (op & 0x0800) ? (op >> 8) & 7 : -1;             // SP-relative
  if (op < 0xB000) return (op >> 8) & 7;                                  // ADR, ADD Rd, SP
  if ((op & 0xFF00) == 0xB200 || (op & 0xFF00) == 0xBA00) return op & 7;  // extend, reverse
  if ((op & 0xFF00) == 0xB000 || (op & 0xFFEF) == 0xB662 || (op & 0xFF00) == 0xBF00) return -1;
  stop = true;  // PUSH/POP, LDM/STM, branches, BL halves, SVC
  return -1;
}

struct Def {
  uint32_t at;
  uint16_t op;
};

inline std::optional<Def> valueDef(const twin::ElfFile& elf, uint32_t pc, int reg, std::string& why) {
  for (uint32_t at = pc - 2, n = 0; n < 24 && at < pc; at -= 2, ++n) {
    // A function's first instruction ends the search (the value came from the caller).
    for (const auto& s : elf.symbols()) {
      if (s.function && (s.value & ~1U) == at + 2 && at + 2 != pc) {
        why = "register r" + std::to_string(reg) + " is set before the function starts";
        return std::nullopt;
      }
    }
    const uint16_t op = half(elf, at);
    if (at >= 2 && (half(elf, at - 2) & 0xF800) == 0xF000 && (op & 0xD000) == 0xD000) {
      why = "a call lies between";  // BL: r0..r3 are the callee's
      return std::nullopt;
    }
    bool stop = false;
    const int d = destination(op, stop);
    if (d == reg) return Def{at, op};
    if (stop) {
      why = "a branch lies between";
      return std::nullopt;
    }
  }
  why = "no instruction sets r" + std::to_string(reg) + " within 24 halfwords";
  return std::nullopt;
}

inline bool patchData(twin::ElfFile& elf, uint32_t address, unsigned bytes, uint32_t value) {
  // Flash, or the .data initial values the reset handler copies from flash.
  const auto dataStart = elf.symbol("__data_start__"), dataEnd = elf.symbol("__data_end__");
  const auto dataLoad = elf.symbol("__data_load__");
  uint32_t at = address;
  if (dataStart && dataEnd && dataLoad && address >= dataStart->value && address < dataEnd->value)
    at = dataLoad->value + (address - dataStart->value);
  if (at + bytes > elf.flashImage().size()) return false;
  if (bytes == 4) return elf.patch32(at, value);
  if (bytes == 2) return elf.patch16(at & ~1U, static_cast<uint16_t>(value));
  const uint32_t even = at & ~1U;
  uint16_t h = half(elf, even);
  h = (at & 1U) ? static_cast<uint16_t>((h & 0x00FF) | (value & 0xFF) << 8)
                : static_cast<uint16_t>((h & 0xFF00) | (value & 0xFF));
  return elf.patch16(even, h);
}

// Registers r0..r7 at the store, the caller's return address (LR) and the value stored, as the twin saw them.
struct Store {
  uint32_t pc = 0, lr = 0;
  uint32_t regs[8] = {};
  uint32_t value = 0;
};

// Makes the instruction `def` (which sets `reg`, used by the store at `pc`) produce `value`. `regs` are
// r0..r7 at the store; `old` the value the store wrote.
inline bool setValue(twin::ElfFile& elf, const Def& def, int reg, uint32_t pc, const Store& at,
                     uint32_t value, std::string& why) {
  if ((def.op & 0xF800) == 0x4800) {  // LDR reg, [PC, #imm8 * 4]
    const uint32_t literal = ((def.at + 4) & ~3U) + (def.op & 0xFFU) * 4;
    return elf.patch32(literal, value);
  }
  const uint16_t movs = static_cast<uint16_t>(0x2000 | (reg << 8));
  if (value <= 0xFF) return elf.patch16(def.at, static_cast<uint16_t>(movs | value));
  // LSLS reg, reg, #k after MOVS reg, #imm: change imm.
  const uint32_t k = (def.op >> 6) & 31U;
  if ((def.op & 0xF800) == 0x0000 && (def.op & 7) == reg && ((def.op >> 3) & 7) == reg && k != 0 &&
      (value & ((1U << k) - 1)) == 0 && (value >> k) <= 0xFF) {
    std::string inner;
    const auto mov = valueDef(elf, def.at, reg, inner);
    if (mov && (mov->op & 0xFF00) == movs)
      return elf.patch16(mov->at, static_cast<uint16_t>(movs | (value >> k)));
  }
  // LDR/LDRH/LDRB reg, [Rn, #imm] with Rn untouched up to the store: the data it loads.
  const uint32_t kind = def.op >> 11;
  if (kind == 0x0D || kind == 0x0F || kind == 0x11) {
    const int rn = (def.op >> 3) & 7;
    const unsigned bytes = kind == 0x0D ? 4 : kind == 0x0F ? 1 : 2;
    bool touched = rn == reg;
    for (uint32_t a = def.at + 2; a < pc && !touched; a += 2) {
      bool stop = false;
      touched = destination(half(elf, a), stop) == rn || stop;
    }
    if (!touched) {
      const uint32_t address = at.regs[rn] + ((def.op >> 6) & 31U) * bytes;
      if (patchData(elf, address, bytes, value)) return true;
      why = "the loaded data is neither in flash nor in .data";
      return false;
    }
  }
  why = "the value cannot be put in place of that instruction";
  return false;
}

// The store at `at` writing `value` instead: the instruction that set the stored register is changed, in
// the function or, where the stored value is an argument ORed in (ORRS rd, rm with rm = r0..r3 set by the
// caller), at the caller's call (the BL before LR).
inline bool setStoredValue(twin::ElfFile& elf, const Store& at, uint32_t value, std::string& why);

// Rt of a 16-bit STR (immediate or register offset), -1 if `op` is none.
inline int storedRegister(uint16_t op) {
  if ((op >> 11) == 0x0C || (op & 0xFE00) == 0x5000) return op & 7;
  return -1;
}

inline bool setStoredValue(twin::ElfFile& elf, const Store& at, uint32_t value, std::string& why) {
  const int rt = storedRegister(half(elf, at.pc));
  if (rt < 0) {
    why = "not a 16-bit STR";
    return false;
  }
  const auto def = valueDef(elf, at.pc, rt, why);
  if (!def) return false;
  if ((def->op & 0xFFC0) == 0x4300 && (def->op & 7) == rt) {  // ORRS rt, rm
    const int rm = (def->op >> 3) & 7;
    std::string inner;
    if (rm <= 3 && !valueDef(elf, def->at, rm, inner)) {
      const uint32_t newArg = at.regs[rm] ^ (at.value ^ value);
      const uint32_t call = (at.lr & ~1U) - 4;
      const auto argDef = valueDef(elf, call, rm, why);
      if (!argDef) return false;
      Store caller = at;
      caller.pc = call;
      return setValue(elf, *argDef, rm, call, caller, newArg, why);
    }
  }
  return setValue(elf, *def, rt, at.pc, at, value, why);
}

}  // namespace twinpatch
