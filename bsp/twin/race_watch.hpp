// RaceWatch: the twin's data-race rule (rules.hpp RACE-ISR-RMW). A deterministic run never fires a race, so
// the rule does not wait for one: it watches who writes each byte of the image's static RAM and where Thread
// code updates one outside a critical section, and stops the run as soon as both meet.
//
// Per byte of SRAM [low, high) (the images keep their long-lived objects in .data/.bss and in main()'s
// frame on the stack, the scheduler among them):
// - writers: the exceptions whose handler code stored to it (IPSR at the store; the entry's stacking and the
//   return's unstacking are the hardware's, not a handler's). A store into the stack reservation [stackLow,
//   the MSP the outermost exception was taken at) is the handler's own frame, not the Thread's data: left
//   out;
// - a Thread-mode read-modify-write: a load of the byte, then a store to it with no other Thread store in
//   between, not both inside one unbroken PRIMASK section (Core::maskSections()). The load and the store may
//   lie far apart: `if (flag) { flag = false; ... }` is one too.
// The rule fires when a handler that writes the byte could have run between the load and the store: its
// exception was "armed" at the store (an external interrupt enabled in the NVIC with its source able to
// assert, i.e. the peripheral's IMASK not zero; SysTick with TICKINT; PendSV and SVCall always). A handler
// that cannot run then (the thread set busy before unmasking the peripheral, as the drivers' start() does) is
// no race. Whichever comes second - the handler's write or the Thread's update - stops the run, with both
// places named.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cpu/core.hpp"

namespace twin {

class RaceWatch final : public SramWatch {
 public:
  // `armed`: the exceptions (bit = exception number) that can run now. `report`: called once per byte pair.
  RaceWatch(Core& core, uint32_t low, uint32_t high, uint32_t stackLow, std::function<uint64_t()> armed,
            std::function<void(const std::string&)> report);

  void onSramLoad(uint32_t address, unsigned bytes) override;
  void onSramStore(uint32_t address, unsigned bytes) override;
  void reset();  // SRAM content lost (BOOTRST, POR): nothing is known any more
  // Turns a PC into "0x... in function" for messages.
  void setDescribe(std::function<std::string(uint32_t pc)> describe) { describe_ = std::move(describe); }

 private:
  struct Byte {
    uint64_t writers = 0;       // handlers that stored to it
    uint64_t raced = 0;         // handlers armed at an unprotected Thread update of it
    uint32_t loadSection = 0;   // maskSections() at the Thread load, 0 = PRIMASK was clear
    uint32_t threadPc = 0;      // the unprotected Thread update
    uint32_t handlerPc = 0;     // the latest handler store
    bool threadLoaded = false;  // a Thread load not yet followed by a Thread store
  };
  void fire(uint32_t address, int exception, uint32_t threadPc, uint32_t handlerPc);

  Core& core_;
  uint32_t low_, high_, stackLow_;
  std::function<uint64_t()> armed_;
  std::function<void(const std::string&)> report_;
  std::function<std::string(uint32_t)> describe_;
  std::vector<Byte> bytes_;
  bool fired_ = false;
};

}  // namespace twin
