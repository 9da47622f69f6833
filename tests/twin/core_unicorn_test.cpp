// The twin's ARMv6-M interpreter against an independent implementation: Unicorn 2 (QEMU's TCG ARM front
// end, Cortex-M0 model). Random instructions of every 16-bit Thumb class and the 32-bit BL/MRS/MSR run once
// on each from the same random register state; registers, flags and the RAM they wrote must agree.
// Encodings the architecture calls UNPREDICTABLE (DDI 0419E, per instruction) are skipped, as are those
// that fault (undefined, unaligned), which the exception tests cover.
#include <unicorn/unicorn.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "cpu/core.hpp"
#include "cpu/nvic.hpp"
#include "gtest/gtest.h"

namespace {

constexpr uint32_t kCode = 0x1000;
constexpr uint32_t kCodeSize = 0x10000;
constexpr uint32_t kRam = 0x20000000;
constexpr uint32_t kRamSize = 0x1000;  // one page: every load/store base points into it

class NoBus final : public twin::CoreBus {
 public:
  bool load(uint32_t, unsigned, uint32_t&) override { return false; }
  bool store(uint32_t, unsigned, uint32_t) override { return false; }
  std::string describe(uint32_t) const override { return "nothing"; }
};

struct State {
  std::array<uint32_t, 16> r{};  // r13 = SP, r15 = PC
  uint32_t flags = 0;            // NZCV in 31:28
  std::vector<uint8_t> ram = std::vector<uint8_t>(kRamSize);
};

class Differential : public ::testing::Test {
 protected:
  void SetUp() override {
    code_.assign(kCodeSize + kCode, 0);
    ASSERT_EQ(uc_open(UC_ARCH_ARM, static_cast<uc_mode>(UC_MODE_THUMB | UC_MODE_MCLASS), &uc_), UC_ERR_OK);
    uc_ctl_set_cpu_model(uc_, UC_CPU_ARM_CORTEX_M0);
    ASSERT_EQ(uc_mem_map(uc_, 0, kCodeSize + kCode, UC_PROT_ALL), UC_ERR_OK);
    // The vector table the twin resets from, at 0 in both memories.
    const uint32_t sp = kRam + 0x100, entry = kCode | 1U;
    std::memcpy(code_.data(), &sp, 4);
    std::memcpy(code_.data() + 4, &entry, 4);
    uc_mem_write(uc_, 0, code_.data(), code_.size());
    ASSERT_EQ(uc_mem_map(uc_, kRam, kRamSize, UC_PROT_ALL), UC_ERR_OK);
  }
  void TearDown() override { uc_close(uc_); }

  // Runs `words` (one instruction) at kCode from `in` on both; false (skipped) if Unicorn faults.
  bool run(const std::vector<uint16_t>& words, const State& in, State& onTwin, State& onUnicorn,
           std::string& twinHalt) {
    std::memset(code_.data() + kCode, 0, 8);
    for (size_t i = 0; i < words.size(); ++i) {
      code_[kCode + 2 * i] = static_cast<uint8_t>(words[i]);
      code_[kCode + 2 * i + 1] = static_cast<uint8_t>(words[i] >> 8);
    }
    // Unicorn
    uc_mem_write(uc_, kCode, code_.data() + kCode, 8);
    uc_ctl_remove_cache(uc_, kCode, kCode + 8);  // Unicorn keeps translated blocks of the previous case
    uc_mem_write(uc_, kRam, in.ram.data(), kRamSize);
    for (int i = 0; i < 13; ++i)
      uc_reg_write(uc_, UC_ARM_REG_R0 + i, &in.r[static_cast<size_t>(i)]);
    uc_reg_write(uc_, UC_ARM_REG_SP, &in.r[13]);
    uc_reg_write(uc_, UC_ARM_REG_LR, &in.r[14]);
    uint32_t xpsr = in.flags | (1U << 24);
    uc_reg_write(uc_, UC_ARM_REG_XPSR, &xpsr);
    if (uc_emu_start(uc_, kCode | 1U, 0xFFFFFFFF, 0, 1) != UC_ERR_OK) return false;
    onUnicorn = in;
    for (int i = 0; i < 13; ++i)
      uc_reg_read(uc_, UC_ARM_REG_R0 + i, &onUnicorn.r[static_cast<size_t>(i)]);
    uc_reg_read(uc_, UC_ARM_REG_SP, &onUnicorn.r[13]);
    uc_reg_read(uc_, UC_ARM_REG_LR, &onUnicorn.r[14]);
    uc_reg_read(uc_, UC_ARM_REG_PC, &onUnicorn.r[15]);
    uc_reg_read(uc_, UC_ARM_REG_XPSR, &xpsr);
    onUnicorn.flags = xpsr & 0xF0000000U;
    onUnicorn.r[15] &= ~1U;
    uc_mem_read(uc_, kRam, onUnicorn.ram.data(), kRamSize);

    // Twin: the reset vector points at the instruction; then registers as Unicorn had them.
    onTwin = in;
    twin::Nvic nvic;
    NoBus bus;
    twin::Core core(bus, nvic);
    core.setFlash(code_.data(), static_cast<uint32_t>(code_.size()));
    core.setSram(onTwin.ram.data(), kRam, kRamSize);
    core.reset();
    for (int i = 0; i < 15; ++i)
      core.setReg(i, in.r[static_cast<size_t>(i)]);
    core.setApsr(in.flags);
    core.step();
    twinHalt = core.halted() ? core.haltReason() : (nvic.pending(twin::Nvic::kHardFault) ? "HardFault" : "");
    for (int i = 0; i < 15; ++i)
      onTwin.r[static_cast<size_t>(i)] = core.reg(i);
    onTwin.r[15] = core.pc();
    onTwin.flags = core.apsr();
    return true;
  }

  uc_engine* uc_ = nullptr;
  std::vector<uint8_t> code_;
};

std::string diff(const State& a, const State& b) {
  std::string out;
  char buf[96];
  for (size_t i = 0; i < 16; ++i) {
    if (a.r[i] != b.r[i]) {
      std::snprintf(buf, sizeof buf, " r%zu twin=0x%08X unicorn=0x%08X", i, a.r[i], b.r[i]);
      out += buf;
    }
  }
  if (a.flags != b.flags) {
    std::snprintf(buf, sizeof buf, " NZCV twin=%X unicorn=%X", a.flags >> 28, b.flags >> 28);
    out += buf;
  }
  for (size_t i = 0; i < a.ram.size(); ++i) {
    if (a.ram[i] != b.ram[i]) {
      std::snprintf(buf, sizeof buf, " ram[0x%zX] twin=%02X unicorn=%02X", i, a.ram[i], b.ram[i]);
      out += buf;
      break;
    }
  }
  return out;
}

// A register state whose low registers and SP point into RAM often enough for loads and stores to land there.
State randomState(std::mt19937& rng, bool pointers) {
  State s;
  std::uniform_int_distribution<uint32_t> any;
  for (auto& b : s.ram)
    b = static_cast<uint8_t>(any(rng));
  for (size_t i = 0; i < 15; ++i) {
    const uint32_t v = any(rng);
    // Interesting values: zero, all ones, sign boundaries, small shifts.
    switch (v % 8) {
      case 0:
        s.r[i] = 0;
        break;
      case 1:
        s.r[i] = 0xFFFFFFFF;
        break;
      case 2:
        s.r[i] = 0x80000000U + (v >> 28) - 8;
        break;
      case 3:
        s.r[i] = v % 40;
        break;
      default:
        s.r[i] = any(rng);
        break;
    }
    if (pointers && i < 8) s.r[i] = kRam + 0x200 + (any(rng) % 0x100) * 4;
  }
  s.r[13] = kRam + 0xA00 + (any(rng) % 0x40) * 4;
  s.r[14] = any(rng);
  s.flags = any(rng) & 0xF0000000U;
  return s;
}

// DDI 0419E A5.2: which 16-bit encodings may be compared (not UNPREDICTABLE, no PC write through a path
// Unicorn single-steps differently, no exception).
bool comparable(uint16_t op) {
  const uint32_t top6 = op >> 10;
  if (top6 == 0x11) {  // special data processing / branch and exchange
    const uint32_t opc = (op >> 8) & 3U, d = ((op >> 4) & 8U) | (op & 7U), m = (op >> 3) & 0xFU;
    if (opc == 3) return false;                         // BX/BLX: covered by the exception tests
    if (opc == 0 && (d == 15 || (d == 13 && m == 15)))  // ADD to PC; ADD SP,PC
      return false;
    if (opc == 1 && ((d < 8 && m < 8) || d == 15 || m == 15)) return false;  // CMP T2 UNPREDICTABLE
    if (opc == 2 && d == 15) return false;
    // SP[1:0] are RAZ/WI (B1.4.1): QEMU keeps them, so an unaligned value written to SP is not compared.
    if ((opc == 0 || opc == 2) && d == 13) return false;
    return true;
  }
  if ((op >> 12) == 0xB) {  // miscellaneous
    const uint32_t sub = (op >> 8) & 0xF;
    if (sub == 0x0 || sub == 0x2 || sub == 0xA) return sub != 0xA || ((op >> 6) & 3U) != 2;
    if (sub == 0x4 || sub == 0x5) return (op & 0x1FF) != 0;  // PUSH, non-empty
    if (sub == 0xC) return (op & 0xFF) != 0;                 // POP without PC, non-empty
    return false;                                            // CPS, POP PC, BKPT, hints, CB{N}Z
  }
  if ((op >> 11) == 0x18 || (op >> 11) == 0x19) {  // STM/LDM
    const uint32_t n = (op >> 8) & 7U, list = op & 0xFFU;
    if (list == 0) return false;
    if ((op >> 11) == 0x18 && ((list >> n) & 1U) && (list & ((1U << n) - 1)) != 0) return false;
    return true;
  }
  if ((op >> 12) == 0xD) return ((op >> 8) & 0xF) < 0xE;  // B<cond>; UDF and SVC fault
  if ((op >> 11) == 0x1C) return true;                    // B
  return op < 0xB000 && (op >> 11) != 0x1D;
}

TEST_F(Differential, Random16BitInstructionsAgreeWithUnicorn) {
  std::mt19937 rng(20240611);
  std::uniform_int_distribution<uint32_t> any;
  int compared = 0, mismatches = 0;
  // Each case costs a Unicorn start (about a millisecond under the sanitizers): 5 000 cover every class
  // many times over (REPORT line below).
  while (compared < 5000 && mismatches < 10) {
    const auto op = static_cast<uint16_t>(any(rng));
    if (!comparable(op)) continue;
    // Register offset with Rn = Rm would address the code page; the generator keeps offsets in RAM.
    if ((op >> 12) == 5 && ((op >> 3) & 7U) == ((op >> 6) & 7U)) continue;
    const bool memory = (op >> 12) == 5 || (op >> 12) == 6 || (op >> 12) == 7 || (op >> 12) == 8 ||
                        (op >> 11) == 0x18 || (op >> 11) == 0x19;
    State in = randomState(rng, memory);
    if ((op >> 12) == 5) in.r[(op >> 6) & 7U] = (any(rng) % 0x40) * 4;  // register offset: small, aligned
    State twinOut, ucOut;
    std::string halt;
    if (!run({op, 0xBF00}, in, twinOut, ucOut, halt)) continue;  // Unicorn faulted (unaligned, ...)
    if (!halt.empty()) continue;                                 // the twin faulted likewise
    ++compared;
    const std::string d = diff(twinOut, ucOut);
    if (!d.empty()) {
      ++mismatches;
      ADD_FAILURE() << "instruction 0x" << std::hex << op << ":" << d;
    }
  }
  std::printf("REPORT twin core: %d random 16-bit instructions agree with Unicorn\n", compared);
}

TEST_F(Differential, BranchWithLinkAndSpecialRegistersAgreeWithUnicorn) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<uint32_t> any;
  int compared = 0;
  for (int n = 0; n < 1500; ++n) {
    std::vector<uint16_t> words;
    const uint32_t kind = n % 3;
    if (kind == 0) {  // BL within +-0x800 bytes (inside the mapped code)
      const uint32_t imm = any(rng) % 0x400;
      const bool back = any(rng) & 1U;
      const uint32_t off = back ? (0x1000000U - imm) & 0xFFFFFF : imm;
      const uint32_t s = (off >> 23) & 1U, i1 = (off >> 22) & 1U, i2 = (off >> 21) & 1U;
      const uint32_t j1 = (~(i1 ^ s)) & 1U, j2 = (~(i2 ^ s)) & 1U;
      words = {static_cast<uint16_t>(0xF000 | (s << 10) | ((off >> 11) & 0x3FF)),
               static_cast<uint16_t>(0xD000 | (j1 << 13) | (j2 << 11) | (off & 0x7FF))};
    } else if (kind == 1) {  // MRS Rd, APSR | IPSR | XPSR | PRIMASK | CONTROL
      const uint32_t sysm[] = {0, 1, 3, 5, 16, 20};
      words = {0xF3EF, static_cast<uint16_t>(0x8000 | ((any(rng) % 13) << 8) | sysm[any(rng) % 6])};
    } else {  // MSR APSR, Rn
      words = {static_cast<uint16_t>(0xF380 | (any(rng) % 13)), 0x8800};
    }
    State in = randomState(rng, false);
    State twinOut, ucOut;
    std::string halt;
    if (!run(words, in, twinOut, ucOut, halt) || !halt.empty()) continue;
    ++compared;
    const std::string d = diff(twinOut, ucOut);
    EXPECT_TRUE(d.empty()) << std::hex << words[0] << " " << words[1] << ":" << d;
  }
  EXPECT_GT(compared, 1400);
}

}  // namespace
