// FlashctlStorage: fw::hal::FlashStorage on the MSPM0 flash controller (FLASHCTL), for the data region the
// linker scripts reserve (linker/mspm0_sections.ld: __record_store_start__ .. __record_store_end__, excluded
// from the image and from `bmsctl flash`'s erase).
//
// Contract (beyond hal/flash.hpp)
// - Only sectors of the configured region are ever addressed: every command's address is computed from a
//   sector index or offset checked against the region, so the image, NONMAIN (0x41C00000) and the rest of
//   MAIN cannot be reached. The region must lie in sectors 0..31 (the ones CMDWEPROTA protects one by one;
//   also the lower 32 KB with 100 k erase cycles, data sheet 7.7): checked by the constructor's caller with
//   regionFits().
// - Each command first clears the protection bit of its one sector (CMDWEPROTA): the controller protects
//   every sector again after each command (TRM FLASHCTL "write/erase protection"; dl_flashctl.h
//   DL_FlashCTL_unprotectSector before every command in TI's examples).
// - Program: one 64-bit word, CMDBYTEN with the ECC byte enabled on parts with ECC (G3507: the hardware
//   computes the 8 ECC bits, CMDCTL.ECCGENOVR clear), without it on the L1306 (no ECC).
// - The write of CMDEXEC and the STATCMD poll run from SRAM (section .ramfunc, copied with .data by the
//   reset handler): during the operation every read of the one flash bank, instruction fetches included,
//   stalls. The poll is bounded by a number of iterations computed from the data sheet maximum (word
//   program 275 us, sector erase 20 ms at <= 2 k cycles, MSPM0L110x SLASEX5C / MSPM0G310x-Q1 7.7), x2, at
//   the CPU clock, with at least 4 cycles per iteration (LDR 2 + taken branch 2, Cortex-M0+ TRM DDI 0484C
//   3.3): the real wait is at most that, and longer only if iterations are slower.
// - Results: STATCMD not DONE within the bound: Timeout; DONE without PASS (protection, verify, illegal
//   address...): VerifyFailed; read-back differs: VerifyFailed.
// - Protection during the operation (watchFaultLine): the wait runs with PRIMASK set, so no interrupt whose
//   vector and handler are in flash starts and stalls there (they run right after, in their order). With a
//   watch, each iteration also looks at the board's fault line; the first time its edge is pending (and
//   unmasked) while the watch is armed, it drives the watch's outputs high at once, as the fast path would
//   (FETs off through CFETOFF/DFETOFF, or the fault output), then waits on. After the operation the pending
//   edge interrupt runs the normal path: protection, which takes the fault line as a fault exactly while the
//   watch is armed (PackView::monitorRunning), opens the same paths and so agrees with the pins.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "hal/flash.hpp"
#include "pin.hpp"
#include "regs/common.hpp"
#include "regs/gpio.hpp"

namespace bsp::mspm0 {

// What the wait watches while the flash bank is busy. It and everything it points to must be in SRAM or a
// peripheral (the wait reads no flash): register addresses computed before the call, no code.
struct FlashFaultWatch {
  uintptr_t edgeStatus = 0;  // the fault line's GPIO port CPU_INT MIS: its edge pending and unmasked
  uint32_t edgeMask = 0;     // the fault line's bit there
  uintptr_t outputSet = 0;   // DOUTSET31_0 of the outputs' port
  uint32_t outputMask = 0;   // the outputs driven high (that path off / fault asserted)
  const volatile bool* armed = nullptr;  // the fault line counts as a fault now (nullptr: never)
};

// The watch of `line` (falling-edge input, GpioEdgeInput) driving `outputs` of port `outputPort` (0 = GPIOA,
// 1 = GPIOB) high; armed later (the armed flag is the application's).
constexpr FlashFaultWatch faultLineWatch(const Pin& line, uint8_t outputPort, uint32_t outputs) {
  const Pin port{outputPort, 0, 0};
  return {line.portBase() + reg::kCpuIntOffset + offsetof(reg::EventBlock, mis), line.mask(),
          port.portBase() + reg::gpio::kDataOffset + offsetof(reg::gpio::Data, doutset), outputs, nullptr};
}

struct FlashctlConfig {
  uintptr_t base;          // FLASHCTL_BASE
  uint32_t regionAddress;  // bus address of the region's first byte (sector aligned)
  const uint8_t* mapped;   // where reads see the region (the same address on the target)
  uint32_t sectors;        // sectors in the region
  bool ecc;                // the part computes and stores ECC (G3507)
  uint32_t cpuMhz;         // the CPU clock the bounds are computed for, MHz
};

// The data sheet maxima the bounds use (us), and the iteration bound of a wait of `us` at `cpuMhz` (32-bit
// arithmetic: no 64-bit division helper from libgcc in the image).
inline constexpr uint32_t kFlashProgramMaxUs = 275;
inline constexpr uint32_t kFlashEraseMaxUs = 20000;
constexpr uint32_t flashPollBound(uint32_t us, uint32_t cpuMhz) {
  constexpr uint32_t kMinCyclesPerIteration = 4;
  constexpr uint32_t kMargin = 2;
  return us * cpuMhz * kMargin / kMinCyclesPerIteration;
}

class FlashctlStorage final : public fw::hal::FlashStorage {
 public:
  explicit constexpr FlashctlStorage(const FlashctlConfig& config)
      : FlashStorage(config.mapped, config.sectors),
        base_(config.base),
        regionAddress_(config.regionAddress),
        cpuMhz_(config.cpuMhz),
        ecc_(config.ecc) {}
  // The region is sector aligned and within sectors 0..31.
  static constexpr bool regionFits(uint32_t address, uint32_t sectors) {
    return address % kSectorBytes == 0 && sectors > 0 && address / kSectorBytes + sectors <= 32;
  }
  // Every later operation watches `watch` (see the contract; nullptr: none). It must stay valid and in SRAM.
  void watchFaultLine(const FlashFaultWatch* watch) { watch_ = watch; }

 private:
  fw::Status doErase(uint32_t sector) override;
  fw::Status doProgram(uint32_t offset, std::span<const uint8_t, kWordBytes> word) override;
  // Programs `word` at `offset`, or erases the sector at `offset` when `word` is nullptr.
  fw::Status execute(uint32_t offset, const uint8_t* word);
  bool reads(uint32_t offset, uint32_t bytes, const uint8_t* expect) const;

  // The configuration beyond the region FlashStorage keeps (FlashctlConfig).
  uintptr_t base_;
  uint32_t regionAddress_;
  uint32_t cpuMhz_;
  bool ecc_;
  const FlashFaultWatch* watch_ = nullptr;
};

}  // namespace bsp::mspm0
