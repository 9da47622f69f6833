#include "flashctl.hpp"

#include "core/bytes.hpp"
#include "regs/flashctl.hpp"

namespace bsp::mspm0 {

namespace {

namespace fc = reg::flashctl;

// The only code that runs while the flash bank is busy. In SRAM (.ramfunc, placed in .data by
// linker/mspm0_sections.ld and copied by the reset handler): a fetch from flash, or a data read (a literal, a
// constant), would stall until the operation ends (SLAU846A NVM chapter, flash banks; SLAAE56A: a program or
// erase stalls every read request to the one bank), which would make the bound meaningless and the watch
// late. long_call: SRAM is beyond the reach of a BL from flash. It calls nothing and reads no constant from
// flash (the masks are immediates; the watch is an SRAM struct whose addresses were computed before).
// PRIMASK is set from before CMDEXEC to after the wait: an interrupt's vector and handler are in flash, so it
// could only stall the bus and the watch (ARMv6-M: PRIMASK masks every configurable interrupt; the pending
// ones are taken when it is cleared). Returns the last STATCMD value read.
#if defined(BSP_MSPM0_MMIO_MODEL) && BSP_MSPM0_MMIO_MODEL
#define BSP_MSPM0_RAMFUNC __attribute__((noinline))
#else
#define BSP_MSPM0_RAMFUNC __attribute__((section(".ramfunc"), noinline, long_call))
#endif
BSP_MSPM0_RAMFUNC uint32_t executeAndPoll(fc::Command& command, const mmio::Reg& statcmd, uint32_t bound,
                                          const FlashFaultWatch* watch) {
#if !(defined(BSP_MSPM0_MMIO_MODEL) && BSP_MSPM0_MMIO_MODEL)
  uint32_t primask;
  __asm volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
#endif
  command.cmdexec.write(fc::kExecute);
  uint32_t status = 0;
  for (uint32_t i = 0; i < bound; ++i) {
    status = statcmd.read();
    if ((status & fc::kStatDone) != 0) break;
    // The fault line's edge: the fast path's action now, once (the pins stay as driven: protection takes
    // them over after the operation, see the contract).
    if (watch != nullptr && (mmio::block<const mmio::Reg>(watch->edgeStatus).read() & watch->edgeMask) != 0 &&
        *watch->armed) {
      mmio::block<mmio::Reg>(watch->outputSet).write(watch->outputMask);
      watch = nullptr;
    }
  }
#if !(defined(BSP_MSPM0_MMIO_MODEL) && BSP_MSPM0_MMIO_MODEL)
  __asm volatile("msr primask, %0" ::"r"(primask) : "memory");
#endif
  return status;
}

}  // namespace

// The flash changes under the compiler's feet (the controller writes it): every check reads it afresh.
// Whether `bytes` of the region from `offset` read as `expect` (nullptr: erased).
bool FlashctlStorage::reads(uint32_t offset, uint32_t bytes, const uint8_t* expect) const {
  const volatile uint8_t* flash = read().data() + offset;
  for (uint32_t i = 0; i < bytes; ++i) {
    if (flash[i] != (expect != nullptr ? expect[i] : kErased)) return false;
  }
  return true;
}

// One command on the region, erase and program alike: set up, unprotect the one sector, execute, wait at
// most the data sheet's bound, then read back. `word` is the word to program at `offset`; nullptr erases
// the sector at `offset`.
fw::Status FlashctlStorage::execute(uint32_t offset, const uint8_t* word) {
  const bool program = word != nullptr;
  const uint32_t address = regionAddress_ + offset;
  fc::Command& command = fc::command(base_);
  // CMDCTL 0: address translation by the hardware, MAIN region from the address; ECCGENOVR clear, so on the
  // G3507 the hardware computes the ECC byte.
  command.cmdctl.write(0);
  command.cmdtype.write(program ? fc::kCommandProgram | fc::kSizeOneWord
                                : fc::kCommandErase | fc::kSizeSector);
  command.cmdaddr.write(address);
  if (program) {
    command.cmdbyten.write(fc::kByteEnableData | (ecc_ ? fc::kByteEnableEcc : 0));
    command.cmddata0.write(fw::bytes::loadLe32(word));
    command.cmddata1.write(fw::bytes::loadLe32(word + 4));
  }
  // Protection is re-armed by the controller after every command, so it is cleared here, for this one
  // sector, right before CMDEXEC (SLAU846A/SLAU847 FLASHCTL write/erase protection; CMDWEPROTA bit n =
  // sector n, hw_flashctl.h).
  fc::protect(base_).cmdweprota.write(~(1U << (address / kSectorBytes)));
  const uint32_t status = executeAndPoll(
      command, fc::statcmd(base_), flashPollBound(program ? kFlashProgramMaxUs : kFlashEraseMaxUs, cpuMhz_),
      watch_ != nullptr && watch_->armed != nullptr ? watch_ : nullptr);
  if ((status & fc::kStatDone) == 0) return fw::Status::Timeout;
  if ((status & fc::kStatPass) == 0) return fw::Status::VerifyFailed;
  return reads(offset, program ? kWordBytes : kSectorBytes, word) ? fw::Status::Ok : fw::Status::VerifyFailed;
}

fw::Status FlashctlStorage::doErase(uint32_t sector) {
  if (sector >= sectorCount()) return fw::Status::InvalidArgument;
  return execute(sector * kSectorBytes, nullptr);
}

fw::Status FlashctlStorage::doProgram(uint32_t offset, std::span<const uint8_t, kWordBytes> word) {
  if (offset % kWordBytes != 0 || offset >= size()) return fw::Status::InvalidArgument;
  if (!reads(offset, kWordBytes, nullptr)) return fw::Status::InvalidArgument;  // one program per erase
  return execute(offset, word.data());
}

}  // namespace bsp::mspm0
