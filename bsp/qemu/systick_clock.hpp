// SysTickClock: the firmware clock (fw::hal::Clock) on the QEMU target, from the Cortex-M SysTick.
//
// SysTick runs from the CPU clock (QEMU's microbit: 16 MHz) and interrupts every tick period; the handler
// counts ticks and calls an optional hook (the tests post from it). now() combines the tick count with the
// current down-count, so it has sub-tick resolution (1/16 us). wakeAt() needs nothing: the periodic tick
// wakes the CPU at least once per period, which the Clock contract allows ("waking early is allowed").
#pragma once

#include <cstdint>

#include "hal/clock.hpp"

namespace bsp::qemu {

class SysTickClock final : public fw::hal::Clock {
 public:
  static constexpr uint32_t kCpuHz = 16000000;

  // Starts SysTick with the given tick period in microseconds (at most 1 048 575 us: 24-bit reload).
  void start(uint32_t periodUs);
  void stop();
  uint32_t ticks() const { return ticks_; }

  // Called from SysTick_Handler.
  void onTick();
  void setTickHook(void (*hook)()) { hook_ = hook; }

 private:
  fw::Instant doNow() const override;
  void doWakeAt(fw::Instant) override {}

  volatile uint32_t ticks_ = 0;
  uint32_t periodUs_ = 1000;
  uint32_t reload_ = 0;
  void (*hook_)() = nullptr;
};

SysTickClock& sysTickClock();

}  // namespace bsp::qemu
