// RaceWatch: the twin's data-race rule (rules.hpp RACE-ISR-RMW). A deterministic run never fires a race, so
// the rule does not wait for one: it watches who writes each byte of the image's static RAM and where Thread
// code updates one outside a critical section, and stops the run as soon as both meet.
//
// Per byte of SRAM [low, high) (the images keep their long-lived objects in .data/.bss and in main()'s
// frame on the stack, the scheduler among them):
// - writes: the exceptions whose handler code stored to it (IPSR at the store; the entry's stacking and the
//   return's unstacking are the hardware's, not a handler's), each with the interrupt sources that were
//   pending and enabled (the peripheral's CPU_INT.MIS; none for SysTick, PendSV and SVCall) at that
//   handler's entry or at one of its RAM accesses before the store: what the handler could be serving. A
//   store into the stack reservation [stackLow, the MSP the outermost exception was taken at) is the
//   handler's own frame, not the Thread's data: left out;
// - a Thread-mode read-modify-write: a load of the byte, then a store to it with no other Thread store in
//   between, not both inside one unbroken PRIMASK section (Core::maskSections()). The load and the store may
//   lie far apart: `if (flag) { flag = false; ... }` is one too.
// The rule fires when a handler write could have come between the load and the store: at the store its
// exception could run (an external interrupt enabled in the NVIC; SysTick with TICKINT; PendSV and SVCall
// always) and every source it was entered for is one that can assert now (enabled in the peripheral's
// CPU_INT.IMASK, or pending). A handler that cannot run then (the thread set busy before unmasking the
// peripheral, as the drivers' start() does) is no race; nor is a handler's write that only one source leads
// to, while that source is masked: the UART driver clears its busy flag in the EOT path after masking EOT,
// and the Thread tests and sets the flag while only reception can interrupt (the same exception, another
// path). Whichever comes second - the handler's write or the Thread's update - stops the run, with both
// places named.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cpu/core.hpp"

namespace twin {

// What can raise one exception's interrupt now (bit = the peripheral's CPU_INT event, or the member of an
// interrupt group): `possible` the sources that can assert (enabled and able to occur, or already pending),
// `pending` those pending and enabled (MIS). Zero for an exception that has no sources of its own.
struct InterruptSources {
  uint32_t possible = 0;
  uint32_t pending = 0;
};

class RaceWatch final : public SramWatch {
 public:
  // `armed`: the exceptions (bit = exception number) that can run now. `sources`: what can raise one of
  // them now. `report`: called once per byte pair.
  RaceWatch(Core& core, uint32_t low, uint32_t high, uint32_t stackLow, std::function<uint64_t()> armed,
            std::function<InterruptSources(int exception)> sources,
            std::function<void(const std::string&)> report);

  void onSramLoad(uint32_t address, unsigned bytes) override;
  void onSramStore(uint32_t address, unsigned bytes) override;
  // The core entered `exception`: what it was entered for is what its stores are attributed to.
  void onExceptionEntry(int exception);
  void reset();  // SRAM content lost (BOOTRST, POR): nothing is known any more
  // Turns a PC into "0x... in function" for messages.
  void setDescribe(std::function<std::string(uint32_t pc)> describe) { describe_ = std::move(describe); }

 private:
  static constexpr int kExceptions = 48;  // Cortex-M0+: 16 system exceptions and 32 external interrupts
  static constexpr size_t kKept = 4;      // per byte: distinct handler writes, Thread updates

  struct Write {
    uint8_t exception = 0;
    uint32_t sources = 0;  // pending and enabled while that handler ran, up to the store
  };
  // The exceptions that could run at a Thread update and what could raise each (an index into updates_).
  struct Update {
    uint64_t armed = 0;
    std::array<uint32_t, kExceptions> possible{};
    bool operator<(const Update& other) const {
      return armed != other.armed ? armed < other.armed : possible < other.possible;
    }
  };
  struct Byte {
    std::array<Write, kKept> writes{};
    std::array<uint32_t, kKept> updates{};  // indexes into updates_
    uint8_t writeCount = 0;
    uint8_t updateCount = 0;
    uint32_t loadSection = 0;   // maskSections() at the Thread load, 0 = PRIMASK was clear
    uint32_t threadPc = 0;      // the latest unprotected Thread update
    uint32_t handlerPc = 0;     // the latest handler store
    bool threadLoaded = false;  // a Thread load not yet followed by a Thread store
  };
  static bool couldPreempt(const Write& write, const Update& update);
  void addWrite(Byte& byte, Write write);
  void addUpdate(Byte& byte, uint32_t update);
  uint32_t currentUpdate();
  void noteHandlerSources();
  uint32_t intern(const Update& update);
  static bool sameUpdate(const Update& a, const Update& b);
  void fire(uint32_t address, int exception, uint32_t threadPc, uint32_t handlerPc);

  Core& core_;
  uint32_t low_, high_, stackLow_;
  std::function<uint64_t()> armed_;
  std::function<InterruptSources(int)> sources_;
  std::function<void(const std::string&)> report_;
  std::function<std::string(uint32_t)> describe_;
  std::vector<Byte> bytes_;
  std::vector<Update> updates_;                  // distinct, in order of first use
  std::map<Update, uint32_t> known_;             // each one's index in updates_
  std::array<uint32_t, kExceptions> entered_{};  // each exception's sources since its latest entry
  uint32_t last_ = ~0U;                          // the index of the latest Thread update's configuration
  bool fired_ = false;
};

}  // namespace twin
