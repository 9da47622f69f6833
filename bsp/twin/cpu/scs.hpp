// Scs: the ARMv6-M System Control Space at 0xE000E000 as the twin's core sees it: SysTick (DDI 0419E
// B3.3), the NVIC registers (B3.4) and the System Control Block (B3.2).
//
// Registers: SYST_CSR/RVR/CVR/CALIB; NVIC_ISER/ICER/ISPR/ICPR and IPR0..7; CPUID, ICSR, VTOR, AIRCR, SCR,
// CCR, SHPR2, SHPR3. Any other SCS address stops the run (AddressMap contract).
// - SysTick counts the processor clock (CLKSOURCE = 1). CLKSOURCE = 0 selects the implementation's
//   reference clock, which the MSPM0 TRMs do not describe for these parts: the twin stops rather than guess.
//   Reaching zero sets COUNTFLAG and, with TICKINT, pends SysTick; the next clock reloads RVR (B3.3.1).
// - AIRCR.SYSRESETREQ with VECTKEY 0x05FA requests a system reset (B3.2.6); the machine performs it.
#pragma once

#include <cstdint>
#include <functional>

#include "address_map.hpp"
#include "cpu/core.hpp"
#include "cpu/nvic.hpp"
#include "timeline.hpp"

namespace twin {

class Scs final : public Device {
 public:
  static constexpr uint32_t kBase = 0xE000E000;
  static constexpr uint32_t kSize = 0x1000;

  Scs(Core& core, Nvic& nvic, Timeline& timeline, std::function<void()> resetRequest);
  void reset();

  const char* name() const override { return "SCS"; }
  bool read(uint32_t offset, unsigned bytes, uint32_t& value) override;
  bool write(uint32_t offset, unsigned bytes, uint32_t value) override;
  // SCR.SLEEPDEEP (B3.2.7): a WFI or a sleep-on-exit enters the part's deep sleep (MSPM0: STOP or STANDBY,
  // as SYSCTL PMODECFG selects) instead of SLEEP.
  bool sleepDeep() const { return (scr_ & 0x4) != 0; }

 private:
  uint32_t systickValue() const;
  void armSystick();
  void onSystickZero();

  Core& core_;
  Nvic& nvic_;
  Timeline& timeline_;
  std::function<void()> resetRequest_;
  TimedEvent systickZero_;
  uint32_t csr_ = 0, rvr_ = 0;
  uint32_t loadedValue_ = 0;  // counter value at loadedAt_
  uint64_t loadedAt_ = 0;
  bool countFlag_ = false;
  uint32_t scr_ = 0;
};

}  // namespace twin
