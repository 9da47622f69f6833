// Cpuss: the CPU subsystem's interrupt groups (CPUSS_BASE 0x40400000; INT_GROUP[n] at 0x1100 + 0x30 n with
// IIDX/IMASK/RIS/MIS/ISET/ICLR, mspm0-sdk hw_cpuss.h CPUSS_INT_GROUP_Regs; members from the tsv group_iidx
// rows / dl_interrupt.h: GROUP1 IIDX 1 = GPIOA, 2 = GPIOB on the G3507).
//
// A group is a read-only mux: RIS bit k is member k+1's interrupt output (a level), IMASK reads as the
// members present, IIDX the lowest pending member + 1 without clearing anything (hw_cpuss.h declares IMASK,
// RIS, MIS, IIDX read-only). The group's output is an NVIC line: GROUP0 IRQ 0, GROUP1 IRQ 1 (tsv irq rows).
// CTL (0x1300, prefetch/cache control): PREFETCH bit 0, ICACHE bit 1, LITEN bit 2 (hw_cpuss.h CPUSS_CTL_*),
// the other bits reserved (read 0). Its reset value is 0x7, all three on: TI's SVD for the parts (CPUSS CTL
// resetValue, as carried by the svd2rust crates generated from it: NanaHigh/mspm0g350x-pac src/cpuss/ctl.rs
// for the G350x, sigpwny/mspm0l222x-pac src/cpuss/cpuss_ctl.rs for the L222x; hw_cpuss.h gives no reset
// values; the L130x SVD was not read: bsp/twin/README.md). Every reset the twin performs (SYSRST and up)
// restores it. The bits are kept and have no effect on timing: the twin charges zero-wait-state cycles
// (README, open questions).
#pragma once

#include <array>
#include <cstdint>

#include "address_map.hpp"
#include "machine.hpp"

namespace twin {

class Cpuss final : public Device {
 public:
  static constexpr uint32_t kBase = 0x40400000;
  static constexpr uint32_t kSize = 0x2000;
  static constexpr uint32_t kCtlAtReset = 0x7;  // CTL: PREFETCH | ICACHE | LITEN

  explicit Cpuss(Machine& machine);
  const char* name() const override { return "CPUSS"; }
  bool read(uint32_t offset, unsigned bytes, uint32_t& value) override;
  bool write(uint32_t offset, unsigned bytes, uint32_t value) override;

  // Member `index` (1-based, as IIDX reports it) of group `group` changed level.
  void setMember(int group, int index, bool asserted);
  // Members a group has (IMASK's read value), set by the chip.
  void setMembers(int group, uint32_t mask) { members_[static_cast<size_t>(group)] = mask; }
  // CTL.PREFETCH (bit 0): the flash prefetcher is on (the PREFETCH-SLEEP rule, rules.hpp).
  bool prefetchOn() const { return (ctl_ & 1U) != 0; }

 private:
  Machine& machine_;
  std::array<uint32_t, 5> ris_{};
  std::array<uint32_t, 5> members_{};
  uint32_t ctl_ = kCtlAtReset;
};

}  // namespace twin
