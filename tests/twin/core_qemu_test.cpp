// The twin's core against a second reference: QEMU's Cortex-M0 machine (qemu-system-arm -M microbit, the
// nRF51's Cortex-M0: the ARMv6-M architecture, ARM DDI 0419E, that the MSPM0's Cortex-M0+ implements) running
// the same programs with -icount shift=0 (deterministic: one instruction, one virtual nanosecond). Each
// program ends at `done` by writing a RAM region to QEMU's semihosting console (SYS_OPEN ":tt", SYS_WRITE,
// SYS_EXIT); the twin stops when its PC reaches `done` and reads the same region from SRAM. The regions must
// agree word for word: registers and memory at one defined exit point, never a value the test computed
// itself.
// - Sequences: programs generated here, each 96 random straight-line sequences of 4..12 16-bit instructions
//   (every data-processing, shift, load/store, SP-relative, extend/reverse and hi-register class of A5.2, and
//   forward conditional branches) from random registers and flags; after each sequence r0..r12 and APSR go
//   to a result slot, and the scratch RAM the loads and stores used is compared at the end too. Loads and
//   stores use r6/r7 as bases and r5 as the offset register, which no instruction of a sequence writes, so
//   every access lands in the scratch RAM, aligned. SP and LR are not written by a sequence (usable()).
// - Exceptions: programs/qemu_exceptions.S (SVC, PendSV and SysTick pended through ICSR, NVIC priorities and
//   nesting, order at equal priority, PRIMASK and WFI, Thread on PSP, frame alignment, BLX/BX/MOV PC, the
//   faults: unaligned, UDF, INVSTATE, BKPT, SVC escalation; priority registers; the registers at the exit),
//   its log compared word by word. Each step cites the DDI 0419E section it relies on.
// Left out, because QEMU does not model them as the Cortex-M0+ does (bsp/twin/README.md says the same):
// - cycle counts: -icount counts instructions, not M0+ cycles (the cycle table is CorePrograms.Cycles*);
//   SysTick counting, WFI sleep time and interrupt latency are timing too: SysTick is pended through ICSR;
// - ICSR bit 11 (RETTOBASE, ARMv7-M): reserved on ARMv6-M (B3.2.4), QEMU sets it; the program masks it out;
// - UNPREDICTABLE encodings (CMP T2 with two low registers, A6.7 CMP (register); hi-register forms with SP or
// PC) and
//   unaligned or out-of-RAM accesses in the sequences: the architecture allows either result;
// - BKPT 0xAB is QEMU's semihosting call: it appears only in the epilogue, which the twin never runs (other
//   BKPTs are HardFault on both, C1.7);
// - the MSPM0's memory map and peripherals: the programs touch flash, the first 16 KiB of RAM and the SCS.
// Skipped (GTEST_SKIP) when qemu-system-arm is not installed (ci/setup installs it).
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "gtest/gtest.h"
#include "machine.hpp"

namespace {

constexpr uint32_t kRam = 0x20000000, kRamSize = 0x4000, kFlashSize = 0x40000;

// The qemu-system-arm the build found, if it is still there; empty when the tests must skip.
std::string qemuBinary() {
  const std::string path = QEMU_SYSTEM_ARM;
  return (!path.empty() && ::access(path.c_str(), X_OK) == 0) ? path : std::string();
}

constexpr const char* kNoQemu = "qemu-system-arm not installed (ci/setup installs it)";

// Runs a flash image on QEMU's microbit; returns what the program wrote to the semihosting console.
bool runOnQemu(const std::vector<uint8_t>& flash, std::vector<uint8_t>& out, std::string& error) {
  const auto dir = std::filesystem::temp_directory_path() / ("twin-qemu-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto bin = dir / "program.bin", result = dir / "out.bin";
  std::ofstream(bin, std::ios::binary)
      .write(reinterpret_cast<const char*>(flash.data()), static_cast<std::streamsize>(flash.size()));
  const std::string cmd = qemuBinary() +
                          " -M microbit -nographic -monitor none -serial none -icount shift=0"
                          " -semihosting-config enable=on,target=native -kernel " +
                          bin.string() + " > " + result.string() + " 2> " + (dir / "err.txt").string();
  const int rc = std::system(("timeout 20 " + cmd).c_str());
  std::ifstream in(result, std::ios::binary);
  out.assign(std::istreambuf_iterator<char>(in), {});
  std::filesystem::remove_all(dir);
  if (rc != 0) error = "qemu-system-arm exited " + std::to_string(rc);
  return rc == 0;
}

// Runs the same image on the twin's core until PC reaches `done`; returns `bytes` of SRAM from its start.
bool runOnTwin(const std::vector<uint8_t>& flash, uint32_t done, uint32_t bytes, std::vector<uint8_t>& out,
               std::string& error, uint32_t* hardFaults = nullptr) {
  twin::Machine m({kFlashSize, kRam, kRamSize, 32000000});
  m.loadFlash(flash);
  m.powerOn();
  for (uint32_t a = kRam; a < kRam + kRamSize; a += 4)
    m.busWrite(a, 4, 0);  // QEMU starts with zeroed RAM
  m.core().reset();
  uint64_t steps = 0;
  while (m.core().pc() != done && !m.core().halted() && steps < 5000000) {
    m.core().step();
    ++steps;
  }
  if (m.core().pc() != done) {
    error = m.core().halted() ? m.core().haltReason() : "did not reach done";
    return false;
  }
  if (hardFaults != nullptr) *hardFaults = m.core().hardFaults();
  out.clear();
  for (uint32_t a = kRam; a < kRam + bytes; a += 4) {
    const uint32_t w = m.readSram32(a);
    for (int i = 0; i < 4; ++i)
      out.push_back(static_cast<uint8_t>(w >> (8 * i)));
  }
  return true;
}

// --- a small Thumb assembler for the generated programs --------------------------------------------------

class Assembler {
 public:
  Assembler() : mem_(kFlashSize, 0xFF) {}
  uint32_t here() const { return pc_; }
  void at(uint32_t address) { pc_ = address; }
  void half(uint16_t v) {
    mem_[pc_] = static_cast<uint8_t>(v);
    mem_[pc_ + 1] = static_cast<uint8_t>(v >> 8);
    pc_ += 2;
  }
  void word(uint32_t address, uint32_t v) {
    for (int i = 0; i < 4; ++i)
      mem_[address + static_cast<uint32_t>(i)] = static_cast<uint8_t>(v >> (8 * i));
  }
  // LDR rt, =value (the literal goes to the next pool).
  void load(int rt, uint32_t value) {
    literals_.push_back({pc_, value});
    half(static_cast<uint16_t>(0x4800 | rt << 8));
  }
  // B over the pool, then the pool.
  void pool() {
    if (literals_.empty()) return;
    const uint32_t branch = pc_;
    half(0xE000);
    if (pc_ & 2U) half(0xBF00);
    for (const auto& [ldr, value] : literals_) {
      word(pc_, value);
      const uint32_t imm = (pc_ - ((ldr + 4) & ~3U)) / 4;
      mem_[ldr] = static_cast<uint8_t>(imm);
      pc_ += 4;
    }
    literals_.clear();
    const uint32_t offset = (pc_ - (branch + 4)) / 2;
    mem_[branch] = static_cast<uint8_t>(offset);
    mem_[branch + 1] = static_cast<uint8_t>(0xE0 | (offset >> 8));
  }
  void bkptSemihost() { half(0xBEAB); }
  std::vector<uint8_t>& mem() { return mem_; }

 private:
  std::vector<uint8_t> mem_;
  uint32_t pc_ = 0;
  std::vector<std::pair<uint32_t, uint32_t>> literals_;
};

// The epilogue both machines reach: SYS_OPEN(":tt", "wb"), SYS_WRITE of RAM [kRam, kRam + bytes), SYS_EXIT.
void emitDone(Assembler& a, uint32_t bytes) {
  const uint32_t block = 0x3F000, tty = 0x3F010;
  a.word(block, tty);
  a.word(block + 4, 5);
  a.word(block + 8, 3);
  a.word(tty, 0x0074743A);  // ":tt\0"
  a.half(0x2001);           // MOVS r0, #1
  a.load(1, block);
  a.bkptSemihost();
  a.load(2, kRam + kRamSize - 0x100);
  a.half(0x6010);  // STR r0, [r2]
  a.load(1, kRam);
  a.half(0x6051);  // STR r1, [r2, #4]
  a.load(1, bytes);
  a.half(0x6091);  // STR r1, [r2, #8]
  a.half(0x2005);  // MOVS r0, #5
  a.half(0x4611);  // MOV r1, r2
  a.bkptSemihost();
  a.half(0x2018);  // MOVS r0, #0x18
  a.load(1, 0x20026);
  a.bkptSemihost();
  a.half(0xE7FE);  // B .
  a.pool();
}

// Destination among r0..r15 of a 16-bit instruction of the classes the generator uses, or -1.
int writes(uint16_t op) {
  if (op < 0x2000) return op & 7;
  if (op < 0x4000) return (op & 0x1800) == 0x0800 ? -1 : (op >> 8) & 7;
  if (op < 0x4400) {
    const int opc = (op >> 6) & 0xF;
    return (opc == 8 || opc == 10 || opc == 11) ? -1 : op & 7;
  }
  if (op < 0x4800) return (op & 0x0300) == 0x0100 ? -1 : (((op >> 4) & 8) | (op & 7));
  if (op < 0x5000) return (op >> 8) & 7;
  if (op < 0x6000) return ((op >> 9) & 7) >= 3 ? op & 7 : -1;
  if (op < 0x9000) return (op & 0x0800) ? op & 7 : -1;
  if (op < 0xA000) return (op & 0x0800) ? (op >> 8) & 7 : -1;
  if (op < 0xB000) return (op >> 8) & 7;
  return op & 7;  // extend, reverse
}

// Whether a random encoding may go into a sequence (see the file comment); LDR literal and ADR read the PC,
// which is the same on both machines.
bool usable(uint16_t op) {
  if (op >= 0xB000) {
    const uint32_t sub = (op >> 8) & 0xF;
    if (op >= 0xC000) return false;
    if (sub == 0x2) return writes(op) < 5;
    if (sub == 0xA) return ((op >> 6) & 3U) != 2 && writes(op) < 5;
    return false;
  }
  if (op >= 0x4400 && op < 0x4800) {  // hi-register ADD, CMP, MOV
    const uint32_t opc = (op >> 8) & 3U, d = ((op >> 4) & 8U) | (op & 7U), m = (op >> 3) & 0xFU;
    if (opc == 3 || d == 13 || d == 15 || m == 13 || m == 15) return false;
    if (opc == 1 && d < 8 && m < 8)
      return false;  // CMP T2 with two low registers: UNPREDICTABLE (A6.7 CMP (register))
    if (opc != 1 && d >= 5 && d <= 7) return false;
    return true;
  }
  if (op >= 0x5000 && op < 0x9000) {  // loads and stores: base r6/r7, register offset r5
    const uint32_t n = (op >> 3) & 7U;
    if (n != 6 && n != 7) return false;
    if (op < 0x6000 && ((op >> 6) & 7U) != 5) return false;
  }
  const int d = writes(op);
  return !(d >= 5 && d <= 7) && d != 13 && d != 15;
}

uint32_t interesting(std::mt19937& rng) {
  const uint32_t v = rng();
  switch (v % 6) {
    case 0:
      return 0;
    case 1:
      return 0xFFFFFFFF;
    case 2:
      return 0x80000000U + (v >> 28) - 8;
    case 3:
      return v % 40;
    default:
      return rng();
  }
}

constexpr uint32_t kScratch = kRam, kScratchBytes = 0x400, kSlots = kRam + 0x400, kSlotBytes = 56;
constexpr uint32_t kSequences = 96, kDumpBytes = 0x2400;

// One generated program: kSequences sequences; `done` is where the epilogue starts.
std::vector<uint8_t> sequenceProgram(uint32_t seed, uint32_t& done) {
  std::mt19937 rng(seed);
  Assembler a;
  a.word(0, kRam + kRamSize);
  a.word(4, 0x101);
  a.word(12, 0);  // HardFault: set to the epilogue below, so a fault ends the program on both
  a.at(0x100);
  // Scratch RAM from a flash table (random bytes): both machines start equal.
  const uint32_t table = 0x30000;
  for (uint32_t i = 0; i < kScratchBytes; i += 4)
    a.word(table + i, rng());
  a.load(0, table);
  a.load(1, kScratch);
  a.load(2, kScratchBytes / 4);
  const uint32_t loop = a.here();
  a.half(0x6803);                                                                // LDR r3, [r0]
  a.half(0x600B);                                                                // STR r3, [r1]
  a.half(0x3004);                                                                // ADDS r0, #4
  a.half(0x3104);                                                                // ADDS r1, #4
  a.half(0x3A01);                                                                // SUBS r2, #1
  a.half(static_cast<uint16_t>(0xD100 | ((loop - (a.here() + 4)) / 2 & 0xFF)));  // BNE loop
  a.pool();
  for (uint32_t s = 0; s < kSequences; ++s) {
    // Registers: r0..r4, r8..r12 interesting; r5 a small aligned offset; r6, r7 pointers into scratch; APSR
    // random NZCV; SP the end of this sequence's result slot.
    const uint32_t slotEnd = kSlots + (s + 1) * kSlotBytes;
    for (int hi = 8; hi <= 12; ++hi) {
      a.load(0, interesting(rng));
      a.half(static_cast<uint16_t>(0x4600 | ((hi & 8) << 4) | (hi & 7)));  // MOV r<hi>, r0
    }
    a.load(0, rng() & 0xF0000000U);
    a.half(0xF380), a.half(0x8800);  // MSR APSR_nzcv, r0
    a.load(0, slotEnd);
    a.half(0x4685);  // MOV SP, r0
    for (int r = 0; r <= 4; ++r)
      a.load(r, interesting(rng));
    a.load(5, (rng() % 32) * 4);
    a.load(6, kScratch + (rng() % 200) * 4);
    a.load(7, kScratch + (rng() % 200) * 4);
    const uint32_t n = 4 + rng() % 9;
    for (uint32_t i = 0; i < n; ++i) {
      uint16_t op;
      if (rng() % 6 == 0 && i + 2 <= n) {  // a forward conditional branch inside the sequence
        const uint32_t k = rng() % (n - i - 1);
        op = static_cast<uint16_t>(0xD000 | (rng() % 14) << 8 | k);
      } else {
        do {
          op = static_cast<uint16_t>(rng());
        } while (!usable(op));
      }
      a.half(op);
    }
    a.half(0xB4FF);  // PUSH {r0-r7}
    for (int hi = 8; hi <= 12; ++hi)
      a.half(static_cast<uint16_t>(0x4600 | (hi << 3) | (hi - 8)));  // MOV r<hi-8>, r<hi>
    a.half(0xF3EF), a.half(0x8500);                                  // MRS r5, APSR
    a.half(0xB43F);                                                  // PUSH {r0-r5}
    a.pool();
  }
  done = a.here();
  a.word(12, done | 1U);
  emitDone(a, kDumpBytes);
  auto& mem = a.mem();
  mem.resize(0x40000);
  return mem;
}

std::string firstDifference(const std::vector<uint8_t>& twin, const std::vector<uint8_t>& qemu) {
  if (twin.size() != qemu.size())
    return "sizes differ: twin " + std::to_string(twin.size()) + ", QEMU " + std::to_string(qemu.size());
  for (size_t i = 0; i + 4 <= twin.size(); i += 4) {
    uint32_t t = 0, q = 0;
    std::memcpy(&t, &twin[i], 4);
    std::memcpy(&q, &qemu[i], 4);
    if (t != q) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "word at 0x%08zX: twin 0x%08X, QEMU 0x%08X", kRam + i, t, q);
      return buf;
    }
  }
  return "";
}

TEST(QemuDifferential, RandomSequencesAgreeWithQemusCortexM0) {
  if (qemuBinary().empty()) GTEST_SKIP() << kNoQemu;
  int programs = 0;
  for (uint32_t seed = 1; seed <= 8; ++seed) {
    uint32_t done = 0;
    const auto image = sequenceProgram(seed, done);
    std::vector<uint8_t> onQemu, onTwin;
    std::string error;
    ASSERT_TRUE(runOnQemu(image, onQemu, error)) << error;
    uint32_t faults = 0;
    ASSERT_TRUE(runOnTwin(image, done, kDumpBytes, onTwin, error, &faults))
        << "seed " << seed << ": " << error;
    // Every sequence ran (a fault would have ended the program early, leaving the later slots empty on both):
    // the last slot holds the pushed registers.
    EXPECT_EQ(faults, 0U) << "seed " << seed;
    const size_t last = kSlots - kRam + (kSequences - 1) * kSlotBytes;
    EXPECT_TRUE(std::any_of(onTwin.begin() + static_cast<long>(last),
                            onTwin.begin() + static_cast<long>(last + kSlotBytes),
                            [](uint8_t b) { return b != 0; }))
        << "seed " << seed << ": the last sequence left nothing";
    const std::string d = firstDifference(onTwin, onQemu);
    if (!d.empty()) {
      const uint32_t at = static_cast<uint32_t>(std::strtoul(d.c_str() + 8, nullptr, 16));
      ADD_FAILURE() << "seed " << seed << ": " << d
                    << (at >= kSlots ? " (sequence " + std::to_string((at - kSlots) / kSlotBytes) + ")" : "");
    }
    ++programs;
  }
  if (HasFailure()) return;
  std::printf("REPORT twin core: %u random instruction sequences agree with QEMU's Cortex-M0 (%d programs)\n",
              kSequences * static_cast<uint32_t>(programs), programs);
}

TEST(QemuDifferential, ExceptionsNvicPrimaskControlBranchesAndFaultsAgreeWithQemu) {
  if (qemuBinary().empty()) GTEST_SKIP() << kNoQemu;
  twin::ElfFile elf;
  ASSERT_TRUE(elf.load(std::string(TWIN_PROGRAMS) + "/qemu_exceptions.elf")) << elf.error();
  const auto done = elf.symbol("done");
  ASSERT_TRUE(done.has_value());
  std::vector<uint8_t> image = elf.flashImage();
  image.resize(kFlashSize, 0xFF);
  std::vector<uint8_t> onQemu, onTwin;
  std::string error;
  ASSERT_TRUE(runOnQemu(image, onQemu, error)) << error;
  ASSERT_TRUE(runOnTwin(image, done->value & ~1U, 0x800, onTwin, error)) << error;
  // The log ends with the mark 0x10FF: the program ran to the end on both.
  uint32_t words = 0;
  for (size_t i = 0; i + 4 <= onQemu.size(); i += 4) {
    uint32_t w = 0;
    std::memcpy(&w, &onQemu[i], 4);
    if (w == 0x10FF) words = static_cast<uint32_t>(i / 4 + 1);
  }
  EXPECT_GT(words, 100U) << "QEMU's run did not reach the end of the program";
  EXPECT_EQ(firstDifference(onTwin, onQemu), "");
  if (HasFailure()) return;
  std::printf("REPORT twin core: the exception program's %u log words agree with QEMU's Cortex-M0\n", words);
}

}  // namespace
