// Wwdt: the window watchdog WWDT0 (0x40080000 on both parts), registers from mspm0-sdk hw_wwdt.h:
// WWDTCTL0 0x1100 (KEY 0xC9 in 31:24, CLKDIV 2:0, PER 6:4 = 2^25, 2^21, 2^18, 2^15, 2^12, 2^10, 2^8, 2^6
// counts, WINDOW0 10:8, WINDOW1 14:12, MODE 16: 0 watchdog, 1 interval timer), WWDTCTL1 0x1104 (KEY 0xBE,
// WINSEL bit 0), WWDTCNTRST 0x1108, WWDTSTAT 0x110C (RUN bit 0).
//
// Rules (hw_wwdt.h field descriptions; SLAU846B/SLAU847D "WWDT" chapter):
// - the counter runs from LFCLK, 32 768 Hz, divided by CLKDIV + 1; a keyed WWDTCTL0 write in watchdog mode
//   starts it (RUN); without the key a write is ignored;
// - "Writing 00A7h to [WWDTCNTRST] restarts the WWDT Counter. Writing any other value causes an error": a
//   wrong value, a restart inside the closed window (WINDOWx percent of the period, WINSEL choosing), or the
//   period expiring is a violation, and a WWDT0 violation resets the device. The reset level is BOOTRST, so
//   SRAM is not kept: "A WWDT0 violation generates a BOOTRST ... A WWDT1 violation generates a SYSRST"
//   (SLAU846A/B and SLAU847D WWDT overview); RSTCAUSE reads 0x0E "WWDT0 violation" (hw_sysctl RSTCAUSE_ID,
//   a BOOTRST row of SLAU893B Table 2-5 and of the MSPM0 reset tables).
// Interval-timer mode is not modelled (the run stops).
#pragma once

#include <cstdint>
#include <functional>

#include "periph/peripheral.hpp"
#include "timeline.hpp"

namespace twin {

class Wwdt final : public Peripheral {
 public:
  Wwdt(Machine& machine, const char* name);
  // Called at every restart (0xA7 write) with the cycle it happened.
  void onRestart(std::function<void()> hook) { restartHook_ = std::move(hook); }
  bool running() const { return running_; }

 private:
  bool readRegister(uint32_t offset, uint32_t& value) override;
  bool writeRegister(uint32_t offset, uint32_t value) override;
  void resetRegisters() override;
  uint64_t periodCycles() const;
  void violation(const std::string& why);

  TimedEvent timeout_;
  std::function<void()> restartHook_;
  uint32_t ctl0_ = 0, ctl1_ = 0;
  bool running_ = false;
  uint64_t startedAt_ = 0;
};

}  // namespace twin
