// TimgModel: a TIMG counter in the register model, counting up at the timer clock, with the events a
// wake-up alarm depends on. Offsets: mspm0l1306.tsv "GPTIMER.*" rows (CTR 0x1800, LOAD 0x1808, CC0/CC1
// 0x1810/0x1814; CPU_INT IMASK 0x1028, MIS 0x1038, ISET 0x1040, ICLR 0x1048).
//
// Rules (TI source next to each)
// - Up counting (CTRCTL.CM = up): 0, 1, ..., LOAD, 0, ...; one timer clock per value, so a period is LOAD + 1
//   clocks (SLAU847D / SLAU846B TIMx chapter, "up counting mode"; hw_gptimer.h CTRCTL.CM).
// - The LOAD event (CPU_INT bit 1) is set when the counter becomes LOAD; CCUn (bits 8, 9) when it becomes
//   CCn counting up; nothing is set for a value the counter does not pass (hw_gptimer.h CPU_INT RIS L, CCU0,
//   CCU1 descriptions). A compare matches once per wrap: a CC value behind the counter fires a period later.
// - MIS = RIS & IMASK; ICLR clears RIS bits, ISET sets them (hw_gptimer.h CPU_INT MIS/ICLR/ISET).
// The model's time starts at 0 with the counter at 0 (CTRCTL.CVAE = zero); the test advances it.
#pragma once

#include <cstdint>

namespace bsp::mspm0::test {

class TimgModel {
 public:
  static constexpr uint32_t kLoad = 1U << 1, kCcu0 = 1U << 8, kCcu1 = 1U << 9;

  explicit TimgModel(uintptr_t base) : base_(base) {}
  void attach();

  uint64_t now() const { return ticks_; }
  // Advances the counter tick by tick (at most `limit` ticks) until an unmasked event is pending; returns
  // false if none came. The CPU would take the interrupt at now().
  bool runUntilInterrupt(uint64_t limit);
  uint32_t pending() const;

 private:
  uint32_t counter() const;
  uint32_t reg(uintptr_t offset) const;

  uintptr_t base_;
  uint64_t ticks_ = 0;
  uint32_t ris_ = 0;
};

}  // namespace bsp::mspm0::test
