// TimgOneShot: a one-shot microsecond delay on a TIMG timer, used to time UART pings and receive timeouts
// in hardware instead of busy loops.
//
// The timer counts down from the delay at 1 MHz and raises its zero event once (REPEAT = 0 stops it).
// Delays longer than the 16-bit counter are run as successive 65.535 ms chunks.
//
// Contract
// - init(): thread mode, once; enables the timer's NVIC line. start(us) re-arms (cancelling a running
//   delay); stop() cancels. Both ISR-safe as long as only the owning driver calls them.
// - onInterrupt() is called from the owner's handler for this timer's IRQ; it returns true exactly once per
//   started delay, when the whole delay has elapsed (MIS -> ICLR discipline inside).
#pragma once

#include <cstdint>

namespace bsp::mspm0 {

class TimgOneShot {
 public:
  struct Config {
    uintptr_t base = 0;
    uint8_t irq = 0;
    uint8_t prescaler = 31;  // CPS.PCNT for 1 MHz: reg::timg::prescalerFor1MHz(bus clock)
  };
  constexpr explicit TimgOneShot(const Config& config) : config_(config) {}

  void init();
  void start(uint32_t microseconds);
  void stop();
  bool onInterrupt();

 private:
  // Loads and starts the next chunk of `microseconds` (at most 0xFFFF); the rest goes to remaining_.
  void load(uint32_t microseconds);

  Config config_;
  uint32_t remaining_ = 0;  // microseconds still to run after the current chunk
  bool running_ = false;
};

}  // namespace bsp::mspm0
