// Machine: the Cortex-M0+ core, its memories, the System Control Space and the address map, run on the
// twin's timeline together with the world outside the chip (the device emulators' SimClock).
//
// Time: the timeline counts CPU cycles at the image's clock (32 MHz on every image: SYSOSC, MCLK /1; the
// SYSCTL model stops the run if the firmware selects anything else). The emulators live on a SimClock in
// microseconds; the machine keeps it in step (one microsecond = clockHz / 1e6 cycles), firing both kinds of
// events in time order, so a peripheral model can call an emulator and the emulator sees the right time.
//
// run(end): executes instructions, fires events, and while the core sleeps in WFI jumps straight to the next
// event. It stops at `end` or when the run is stopped (an access no model covers, a lockup, a rule a model
// enforces: stopped() and stopReason() say which, with the PC).
//
// Figures: busy cycles (the core not asleep), and per interrupt the worst latency from the request (the
// line asserting, or still asserted when its handler returned) to the first instruction of its handler, and
// the longest handler run (entry to return, including nested handlers).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "address_map.hpp"
#include "cpu/core.hpp"
#include "cpu/nvic.hpp"
#include "cpu/scs.hpp"
#include "elf_file.hpp"
#include "power_mode.hpp"
#include "race_watch.hpp"
#include "rules.hpp"
#include "timeline.hpp"
#include "uninit_watch.hpp"

namespace bsp::host {
class SimClock;
}

namespace twin {

class Profiler;

struct MemoryLayout {
  uint32_t flashSize = 0;
  uint32_t sramBase = 0;
  uint32_t sramSize = 0;
  uint32_t clockHz = 32000000;
};

enum class ResetKind : uint8_t { Sysrst, Bootrst, Por };

// SYSCTL RSTCAUSE.ID of the resets the twin performs (hw_sysctl_*.h SYSCTL_RSTCAUSE_ID_*; SLAU846B Table 2-12
// / SLAU847D Table 2-9 give each cause's reset level: 0x01..0x03 POR, 0x0C..0x0E BOOTRST, 0x10..0x1B SYSRST,
// 0x1C..0x1D CPURST).
namespace rstcause {
inline constexpr uint8_t kPorSupply = 0x01;  // VDD < POR- (power-on)
inline constexpr uint8_t kPorSoftware = 0x03;
inline constexpr uint8_t kBootSoftware = 0x0D;
inline constexpr uint8_t kBootWwdt0 = 0x0E;  // "WWDT0 violation" (a BOOTRST: SLAU846B/SLAU847D WWDT overview)
inline constexpr uint8_t kSysBslExit = 0x10;   // RESETLEVEL 4, "BSL exit"
inline constexpr uint8_t kSysBslEntry = 0x11;  // RESETLEVEL 2, "BSL entry"
inline constexpr uint8_t kSysSoftware = 0x1B;
inline constexpr uint8_t kCpuSoftware = 0x1D;  // AIRCR.SYSRESETREQ: a CPU-only reset (SLAU893B 2.4.x)
}  // namespace rstcause

struct InterruptFigures {
  uint64_t entries = 0;
  uint64_t worstLatencyCycles = 0;
  uint64_t worstHandlerCycles = 0;
};

class Machine final : public CoreObserver {
 public:
  explicit Machine(const MemoryLayout& layout);
  ~Machine();

  // Copies the image's flash bytes (ElfFile::flashImage) into the flash; false if it does not fit.
  bool loadFlash(const std::vector<uint8_t>& image);
  // MAIN flash as the part holds it (0xFF = erased): the ROM bootloader model (bsl/rom_bsl.hpp) erases and
  // programs it.
  std::vector<uint8_t>& flash() { return flash_; }
  const std::vector<uint8_t>& flash() const { return flash_; }
  // The CPU runs code the twin does not interpret (the ROM bootloader, modelled at its pins by
  // bsl/rom_bsl.hpp): no instruction of the image executes, events and the world go on.
  void holdCore(bool held) { held_ = held; }
  bool coreHeld() const { return held_; }
  // Power-on reset: SRAM filled with a pattern (its content is undefined at power-up), every model reset.
  void powerOn();
  // A reset of the given level (SLAU846B Table 2-12 / SLAU847D Table 2-9): every peripheral and the CPU;
  // SRAM keeps its content on SYSRST and is lost on BOOTRST and POR. `cause` is logged; `causeId` is the
  // RSTCAUSE.ID it leaves for the firmware (rstcause::*, 0: none).
  void reset(ResetKind kind, const std::string& cause, uint8_t causeId = 0);
  // The same from a model (a register write, a watchdog event): done before the next instruction.
  void requestReset(ResetKind kind, const std::string& cause, uint8_t causeId = 0);
  // RSTCAUSE.ID: the lowest-level cause of the resets since it was last taken (the lowest ID: the IDs rise
  // with the level), and 0 once taken: "always cleared upon a read" (SLAU846B, text above Table 2-12).
  uint8_t takeResetCause() {
    const uint8_t id = resetCause_;
    resetCause_ = 0;
    return id;
  }

  void attachWorld(bsp::host::SimClock& clock) { world_ = &clock; }
  // Brings the world clock up to the CPU's time now (from a register access, outside any world event), so
  // what the world records at this moment carries the right time.
  void syncWorld();
  void run(uint64_t endCycle);
  void stop(const std::string& why);  // the run stops after the current instruction
  // A rule of rules.hpp broken here: stops the run, or (a rule that warns) records the warning once, with the
  // PC and the function either way.
  void violate(Rule rule, const std::string& detail);
  const std::vector<std::string>& ruleWarnings() const { return ruleWarnings_; }
  // KEY-WRITE (rules.hpp): `reg` written with `value`, whose KEY (31:24) is not `key`: the part ignores it.
  // True if the key is right.
  bool checkKey(const std::string& reg, uint32_t value, uint32_t key);
  // The rules that hold for a firmware image but not for the core's own test programs: IDLE-WFI and
  // RACE-ISR-RMW over all SRAM, the stack reservation starting at `stackLow` (rules.hpp, race_watch.hpp), and
  // BSS-UNINIT over [bssLow, bssHigh) (uninit_watch.hpp; an empty range: none).
  void enableImageRules(uint32_t stackLow, uint32_t bssLow = 0, uint32_t bssHigh = 0);
  // The flash was reprogrammed (the ROM BSL): the loaded ELF's .bss range no longer describes the image, so
  // BSS-UNINIT is off from now on.
  void flashReprogrammed() {
    if (!uninit_) return;
    core_.setSramWatch(race_.get());
    uninit_.reset();
  }
  // What can raise IRQ n now (race_watch.hpp InterruptSources: the peripheral's IMASK and MIS); a line
  // without one counts as able to assert at any time, for no source in particular.
  void setIrqSources(int irq, std::function<InterruptSources()> sources) {
    irqSources_[static_cast<size_t>(irq)] = std::move(sources);
  }
  // Cycles per function and per exception (profiler.hpp); null: none.
  void setProfiler(Profiler* profiler) { profiler_ = profiler; }
  bool stopped() const { return core_.halted(); }
  std::string stopReason() const;

  // --- for the chip's models ---------------------------------------------------------------------------
  Timeline& timeline() { return timeline_; }
  uint64_t now() const { return timeline_.now(); }
  uint32_t clockHz() const { return layout_.clockHz; }
  // The rules that hold only for the product's images (enableImageRules): not for bare register tests.
  bool imageRules() const { return imageRules_; }
  uint64_t cyclesPerUs() const { return layout_.clockHz / 1000000; }
  AddressMap& map() { return map_; }
  Nvic& nvic() { return nvic_; }
  Core& core() { return core_; }
  const MemoryLayout& layout() const { return layout_; }
  bool inSram(uint32_t address) const { return address - layout_.sramBase < layout_.sramSize; }
  // FLASHCTL programs or erases until `cycle` (0: not, or no longer): the one flash bank stalls every read,
  // so the core neither fetches an instruction nor loads data from flash before then; code in SRAM that
  // reads no flash runs on (periph/flashctl.hpp).
  void stallFlashUntil(uint64_t cycle) {
    flashBusyUntil_ = cycle;
    core_.setFlashBusy(cycle != 0);
  }
  // An external interrupt line's level (IRQ n of the NVIC).
  void setIrq(int irq, bool asserted);
  // IRQ-UNSERVED (rules.hpp): the lines asserted now for at least `minCycles` whose NVIC enable was never set
  // since the reset, with the cycles each has been asserted.
  std::vector<std::pair<int, uint64_t>> unservedIrqs(uint64_t minCycles) const;
  // A bus master other than the CPU (DMA): same map, flash and SRAM included. False: nothing there.
  bool busRead(uint32_t address, unsigned bytes, uint32_t& value);
  bool busWrite(uint32_t address, unsigned bytes, uint32_t value);
  // Registered by the chip: called on every reset, after the core's state is reset.
  void onReset(std::function<void(ResetKind)> hook) { resetHooks_.push_back(std::move(hook)); }
  // Called at the first WFI in Thread mode after each reset, with the image rules on: bring-up is over and
  // the scheduler has nothing to do (the WWDT-STOPPED rule looks at the watchdog then).
  void onFirstIdle(std::function<void()> hook) { firstIdleHook_ = std::move(hook); }
  // Called after every batch of events (the board samples signals the emulators drive, e.g. nFAULT).
  void onEvents(std::function<void()> hook) { eventHooks_.push_back(std::move(hook)); }
  // Power modes (power.hpp): the chip's SYSCTL tells which deep-sleep mode SCR.SLEEPDEEP enters now; each
  // model with an event the core may wait for says why that event would not arrive in a mode ("" if it
  // would). A sleep in a mode some check refuses breaks SLEEP-EVENT-LOST (rules.hpp).
  void setDeepSleepMode(std::function<PowerMode()> mode) { deepSleepMode_ = std::move(mode); }
  void addSleepCheck(std::function<std::string(PowerMode)> check) {
    sleepChecks_.push_back(std::move(check));
  }
  // Called whenever the core is found asleep, in any mode (a model's rule about what the firmware left
  // armed before it slept: rules.hpp TIMER-COMPARE-PASSED).
  void onSleep(std::function<void()> hook) { sleepHooks_.push_back(std::move(hook)); }
  // The mode a sleep would enter now.
  PowerMode sleepMode() const;
  // Cycles from a wake-up event to the core's first instruction after a sleep in each mode (power.hpp): the
  // core stays stopped that long after a deep sleep ends; the residency counts them as RUN.
  void setWakeCycles(const std::array<uint32_t, kPowerModes>& cycles) { wakeCycles_ = cycles; }
  void setSymbolizer(std::function<std::string(uint32_t)> s) { symbolizer_ = std::move(s); }

  // --- figures --------------------------------------------------------------------------------------------
  uint64_t busyCycles() const { return busy_; }
  // Cycles of the run in each power mode (RUN = busy; SLEEP = the rest that no deep mode took).
  Residency residency() const;
  const std::array<InterruptFigures, Nvic::kExceptions>& interrupts() const { return irqFigures_; }
  const std::vector<std::string>& resets() const { return resetLog_; }
  const std::vector<std::string>& hardFaults() const { return hardFaultLog_; }
  uint32_t readSram32(uint32_t address) const;

 private:
  void onExceptionEntry(int exception) override;
  void onExceptionReturn(int exception) override;
  void onHardFault(const std::string& why) override;
  // One step of the core, counted: busy cycles, time and the profiler. False when the core did nothing
  // (halted or still asleep).
  bool stepCore();
  void onWfi() override;
  std::string describePc(uint32_t pc) const;
  uint64_t armedExceptions() const;
  InterruptSources interruptSources(int exception) const;
  uint64_t worldNext() const;
  void fireDue();

  MemoryLayout layout_;
  std::vector<uint8_t> flash_;
  std::vector<uint8_t> sram_;
  Timeline timeline_;
  Nvic nvic_;
  AddressMap map_;
  Core core_;
  Scs scs_;
  bsp::host::SimClock* world_ = nullptr;
  bool worldBusy_ = false;
  bool held_ = false;
  std::vector<std::function<void(ResetKind)>> resetHooks_;
  std::vector<std::function<void()>> eventHooks_;
  std::function<std::string(uint32_t)> symbolizer_;
  uint64_t busy_ = 0;
  std::function<PowerMode()> deepSleepMode_;
  std::vector<std::function<std::string(PowerMode)>> sleepChecks_;
  std::vector<std::function<void()>> sleepHooks_;
  Residency deepCycles_{};  // cycles slept in each deep mode
  std::array<uint32_t, kPowerModes> wakeCycles_{};
  PowerMode sleptIn_ = PowerMode::Run;  // the mode of the sleep the core is in (Run: awake)
  uint64_t wakeUntil_ = 0;              // the core waking from a deep mode starts executing here
  uint64_t waking_ = 0;                 // cycles spent waking from deep modes
  void checkSleep(PowerMode mode);
  std::array<uint64_t, Nvic::kExceptions> requestedAt_{};
  std::array<bool, Nvic::kExceptions> requested_{};
  std::array<uint64_t, Nvic::kExceptions> enteredAt_{};
  std::array<InterruptFigures, Nvic::kExceptions> irqFigures_{};
  uint32_t irqLevels_ = 0;
  std::array<uint64_t, 32> assertedAt_{};
  std::array<uint32_t, Nvic::kExceptions> pendingAtReturn_{};  // IRQ-STORM: the sources still pending
  std::array<uint32_t, Nvic::kExceptions> stormCount_{};
  std::vector<std::string> resetLog_;
  std::vector<std::string> hardFaultLog_;
  std::optional<ResetKind> pendingReset_;
  std::string pendingResetCause_;
  std::vector<std::string> ruleWarnings_;
  bool imageRules_ = false;
  bool idleSeen_ = false;  // a Thread-mode WFI since the last reset
  std::function<void()> firstIdleHook_;
  std::unique_ptr<RaceWatch> race_;
  std::unique_ptr<UninitWatch> uninit_;
  std::array<std::function<InterruptSources()>, 32> irqSources_{};
  Profiler* profiler_ = nullptr;
  bool enteredException_ = false;  // the step just taken was an exception entry (profiler)
  uint8_t pendingCauseId_ = 0;
  uint8_t resetCause_ = 0;
  uint64_t flashBusyUntil_ = 0;
};

}  // namespace twin
