// UninitWatch: the twin's rule BSS-UNINIT (rules.hpp). SRAM holds whatever it held at power-up or a BOOTRST
// (the twin fills it with a pseudo-random pattern, Machine::reset), so C++'s zero-initialised statics exist
// only once the start-up code has zeroed .bss. The rule tracks, per byte of [__bss_start__, __bss_end__),
// whether an instruction stored to it since the last reset; a load of a byte never stored stops the run: the
// firmware reads start-up garbage where the language promises 0. Every other access is passed on to `next`
// (the data-race watch), so both rules see the same accesses.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cpu/core.hpp"

namespace twin {

class UninitWatch final : public SramWatch {
 public:
  // `report` is called once (until the next reset) with the address of the first byte read unwritten.
  UninitWatch(uint32_t low, uint32_t high, SramWatch* next, std::function<void(uint32_t address)> report);

  void reset();  // every byte of .bss is unwritten again (SRAM kept or not: the start-up zeroes it anew)
  void onSramLoad(uint32_t address, unsigned bytes) override;
  void onSramStore(uint32_t address, unsigned bytes) override;

 private:
  uint32_t low_, high_;
  SramWatch* next_;
  std::function<void(uint32_t)> report_;
  std::vector<bool> written_;
  bool reported_ = false;
};

}  // namespace twin
