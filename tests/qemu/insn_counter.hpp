// InsnCounter: instructions executed, from a free-running SysTick, for the benchmarks under QEMU.
//
// QEMU runs with -icount shift=0 (tests/qemu/CMakeLists.txt): virtual time advances exactly 1 ns per executed
// instruction, and SysTick counts that virtual time at 16 MHz, so one SysTick count is 62.5 instructions. The
// counter runs without interrupts and is read directly; read() must be called at least once per 24-bit wrap
// (16.7 M instructions). With sleep=off a WFI jumps virtual time, so only code that never sleeps (or stands
// in for sleeping without WFI) is measured this way.
#pragma once

#include <cstdint>

#include "scs.hpp"
#include "semihosting.hpp"

namespace qbench {

class InsnCounter {
 public:
  static constexpr uint32_t kReload = 0xFFFFFF;

  void start() {
    using bsp::scs::reg;
    reg(bsp::scs::kSystCsr) = 0;
    reg(bsp::scs::kSystRvr) = kReload;
    reg(bsp::scs::kSystCvr) = 0;
    reg(bsp::scs::kSystCsr) = 0x5;  // CPU clock, enabled, no interrupt
    last_ = reg(bsp::scs::kSystCvr);
    total_ = 0;
  }
  // SysTick counts since start().
  uint64_t read() {
    const uint32_t now = bsp::scs::reg(bsp::scs::kSystCvr);
    total_ += (now <= last_) ? (last_ - now) : (last_ + (kReload + 1) - now);
    last_ = now;
    return total_;
  }
  // Instructions x 100 per iteration from a count of SysTick counts over `iterations`.
  static uint32_t centiInsnPer(uint64_t counts, uint32_t iterations) {
    return static_cast<uint32_t>((counts * 6250) / iterations);
  }

 private:
  uint64_t total_ = 0;
  uint32_t last_ = kReload;
};

// Prints "REPORT <key>=<n>.<d>" (./ci/test collects lines starting with REPORT) for a figure in hundredths.
inline void reportCenti(const char* key, uint32_t centi) {
  bsp::qemu::print("REPORT ");
  bsp::qemu::print(key);
  bsp::qemu::print("=");
  bsp::qemu::printUnsigned(centi / 100);
  bsp::qemu::print(".");
  bsp::qemu::printUnsigned((centi % 100) / 10);
  bsp::qemu::print("\n");
}

}  // namespace qbench
