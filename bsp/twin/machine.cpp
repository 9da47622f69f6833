#include "machine.hpp"

#include <algorithm>
#include <cstdio>

#include "cpu/timing.hpp"
#include "profiler.hpp"
#include "race_watch.hpp"
#include "sim/sim_clock.hpp"

namespace twin {

namespace {
constexpr uint32_t kStormEntries = 1000;  // IRQ-STORM: entries in a row with the source left pending
}  // namespace

Machine::Machine(const MemoryLayout& layout)
    : layout_(layout),
      flash_(layout.flashSize, 0xFF),
      sram_(layout.sramSize, 0),
      core_(map_, nvic_),
      scs_(core_, nvic_, timeline_,
           [this] { requestReset(ResetKind::Sysrst, "AIRCR.SYSRESETREQ", rstcause::kCpuSoftware); }) {
  core_.setFlash(flash_.data(), layout.flashSize);
  core_.setSram(sram_.data(), layout.sramBase, layout.sramSize);
  core_.setObserver(this);
  map_.add(Scs::kBase, Scs::kSize, scs_);
}

Machine::~Machine() = default;

bool Machine::loadFlash(const std::vector<uint8_t>& image) {
  if (image.size() > flash_.size()) return false;
  std::fill(flash_.begin(), flash_.end(), 0xFF);
  std::copy(image.begin(), image.end(), flash_.begin());
  return true;
}

void Machine::powerOn() {
  reset(ResetKind::Por, "power-on", rstcause::kPorSupply);
}

void Machine::requestReset(ResetKind kind, const std::string& cause, uint8_t causeId) {
  if (pendingReset_ && *pendingReset_ >= kind) return;
  pendingReset_ = kind;
  pendingResetCause_ = cause;
  pendingCauseId_ = causeId;
}

void Machine::reset(ResetKind kind, const std::string& cause, uint8_t causeId) {
  pendingReset_.reset();
  sleptIn_ = PowerMode::Run;
  wakeUntil_ = 0;
  if (causeId != 0 && (resetCause_ == 0 || causeId < resetCause_)) resetCause_ = causeId;
  if (kind != ResetKind::Sysrst) {
    // SRAM content is undefined after power-up / BOOTRST: a fixed pseudo-random pattern keeps runs repeatable
    // and makes code that reads uninitialised memory visible.
    uint32_t x = 0x2545F491;
    for (uint8_t& b : sram_) {
      x = x * 1664525U + 1013904223U;
      b = static_cast<uint8_t>(x >> 24);
    }
  }
  if (race_) race_->reset();
  if (uninit_) uninit_->reset();
  idleSeen_ = false;
  pendingAtReturn_.fill(0);
  stormCount_.fill(0);
  for (auto& hook : resetHooks_)
    hook(kind);
  scs_.reset();
  irqLevels_ = 0;
  requested_.fill(false);
  if (!held_) core_.reset();  // held: the ROM runs, the image's vectors may be erased or half written
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f s: ", static_cast<double>(now()) / layout_.clockHz);
  resetLog_.push_back(buf + cause);
}

void Machine::stop(const std::string& why) {
  char buf[48];
  const uint32_t pc = core_.pc();
  std::snprintf(buf, sizeof buf, " (PC 0x%08X", pc);
  std::string where = buf;
  if (symbolizer_) {
    const std::string fn = symbolizer_(pc);
    if (!fn.empty()) where += " in " + fn;
  }
  core_.halt(why + where + ")");
}

std::string Machine::describePc(uint32_t pc) const {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", pc);
  std::string text = buf;
  if (symbolizer_) {
    const std::string fn = symbolizer_(pc);
    if (!fn.empty()) text += " in " + fn;
  }
  return text;
}

void Machine::violate(Rule rule, const std::string& detail) {
  if (ruleInfo(rule).stops) {
    stop(ruleText(rule, detail));
    return;
  }
  const std::string text = ruleText(rule, detail) + " (PC " + describePc(core_.pc()) + ")";
  if (std::find(ruleWarnings_.begin(), ruleWarnings_.end(), text) == ruleWarnings_.end())
    ruleWarnings_.push_back(text);
}

bool Machine::checkKey(const std::string& reg, uint32_t value, uint32_t key) {
  if ((value >> 24) == key) return true;
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "%s written with 0x%08X, KEY 0x%02X instead of 0x%02X: the part ignores the write",
                reg.c_str(), value, value >> 24, key);
  violate(Rule::KeyWrite, buf);
  return false;
}

void Machine::enableImageRules(uint32_t stackLow, uint32_t bssLow, uint32_t bssHigh) {
  imageRules_ = true;
  race_ = std::make_unique<RaceWatch>(
      core_, layout_.sramBase, layout_.sramBase + layout_.sramSize, stackLow,
      [this] { return armedExceptions(); }, [this](int exception) { return interruptSources(exception); },
      [this](const std::string& what) { violate(Rule::IsrRace, what); });
  race_->setDescribe([this](uint32_t pc) { return describePc(pc); });
  core_.setSramWatch(race_.get());
  if (bssHigh <= bssLow) return;
  uninit_ = std::make_unique<UninitWatch>(bssLow, bssHigh, race_.get(), [this](uint32_t address) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "load of .bss byte 0x%08X that no instruction stored since the reset: the start-up did not "
                  "zero .bss, the firmware reads what SRAM held at power-up",
                  address);
    violate(Rule::BssUninit, buf);
  });
  core_.setSramWatch(uninit_.get());
}

uint64_t Machine::armedExceptions() const {
  // PendSV and SVCall are the software's own; SysTick only with TICKINT (the SCS pends it only then).
  uint64_t armed = (1ULL << Nvic::kSvcall) | (1ULL << Nvic::kPendsv) | (1ULL << Nvic::kSystick);
  const uint32_t enabled = nvic_.enabledIrqs();
  for (int irq = 0; irq < 32; ++irq) {
    if (((enabled >> irq) & 1U) == 0) continue;
    const auto& sources = irqSources_[static_cast<size_t>(irq)];
    if (!sources || sources().possible != 0) armed |= 1ULL << (Nvic::kIrq0 + irq);
  }
  return armed;
}

InterruptSources Machine::interruptSources(int exception) const {
  const int irq = exception - Nvic::kIrq0;
  if (irq < 0 || irq >= 32) return {};
  const auto& sources = irqSources_[static_cast<size_t>(irq)];
  return sources ? sources() : InterruptSources{};
}

void Machine::onWfi() {
  // The idle rule (firmware/hal/irq.hpp): Thread code sleeps with interrupts masked, so an interrupt that
  // arrives between its last check for work and the WFI leaves the WFI at once.
  if (imageRules_ && !core_.handlerMode() && !core_.primask()) {
    violate(Rule::IdleWfi,
            "WFI in Thread mode with PRIMASK clear: an interrupt between the last check for work and the WFI "
            "is slept through until the next one");
  }
  if (imageRules_ && !core_.handlerMode() && !idleSeen_) {
    idleSeen_ = true;
    if (firstIdleHook_) firstIdleHook_();
  }
}

PowerMode Machine::sleepMode() const {
  return scs_.sleepDeep() && deepSleepMode_ ? deepSleepMode_() : PowerMode::Sleep;
}

void Machine::checkSleep(PowerMode mode) {
  for (const auto& check : sleepChecks_) {
    const std::string why = check(mode);
    if (why.empty()) continue;
    violate(Rule::SleepEventLost, std::string("the core sleeps in ") + powerModeName(mode) + ": " + why);
    return;
  }
}

Residency Machine::residency() const {
  Residency r = deepCycles_;
  const uint64_t total = now(), busy = std::min(busy_, total);
  uint64_t deep = 0;
  for (const uint64_t c : deepCycles_)
    deep += c;
  // Waking from a deep mode counts as RUN: the data sheets give no current for it, RUN is the safe side.
  const uint64_t run = std::min(busy + waking_, total);
  r[static_cast<size_t>(PowerMode::Run)] = run;
  r[static_cast<size_t>(PowerMode::Sleep)] = total - run > deep ? total - run - deep : 0;
  return r;
}

std::string Machine::stopReason() const {
  if (!core_.halted()) return "";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.6f s: ", static_cast<double>(now()) / layout_.clockHz);
  std::string text = buf + core_.haltReason();
  if (symbolizer_ && text.find(" in ") == std::string::npos) {
    const std::string fn = symbolizer_(core_.pc());
    if (!fn.empty()) text += " in " + fn;
  }
  return text;
}

void Machine::setIrq(int irq, bool asserted) {
  const uint32_t bit = 1U << irq;
  const bool was = (irqLevels_ & bit) != 0;
  if (was == asserted) return;
  irqLevels_ = asserted ? (irqLevels_ | bit) : (irqLevels_ & ~bit);
  if (asserted) assertedAt_[static_cast<size_t>(irq)] = now();
  nvic_.setIrqLevel(irq, asserted);
  const int e = Nvic::kIrq0 + irq;
  if (asserted && !requested_[e] && (nvic_.enabledIrqs() & bit) != 0) {
    requested_[e] = true;
    requestedAt_[e] = now();
  }
}

std::vector<std::pair<int, uint64_t>> Machine::unservedIrqs(uint64_t minCycles) const {
  std::vector<std::pair<int, uint64_t>> out;
  for (int irq = 0; irq < 32; ++irq) {
    const uint32_t bit = 1U << irq;
    const uint64_t held = now() - assertedAt_[static_cast<size_t>(irq)];
    if ((irqLevels_ & bit) != 0 && (nvic_.everEnabledIrqs() & bit) == 0 && held >= minCycles)
      out.emplace_back(irq, held);
  }
  return out;
}

void Machine::onExceptionEntry(int exception) {
  enteredException_ = true;
  if (race_) race_->onExceptionEntry(exception);
  // The handler's first instruction; the vector fetch waits for a FLASHCTL program/erase to end (the bank
  // stalls every read, SLAAE56A), which the latency figure includes (the safe side: the whole entry after
  // it).
  const uint64_t start = std::max(now(), flashBusyUntil_) + cycles::kExceptionEntry;
  InterruptFigures& f = irqFigures_[exception];
  ++f.entries;
  if (requested_[exception]) {
    f.worstLatencyCycles = std::max(f.worstLatencyCycles, start - requestedAt_[exception]);
    requested_[exception] = false;
  }
  enteredAt_[exception] = start;
  // IRQ-STORM (rules.hpp): entered again for a source its last run left pending.
  const uint32_t again = pendingAtReturn_[exception] & interruptSources(exception).pending;
  stormCount_[exception] = again != 0 ? stormCount_[exception] + 1 : 0;
  if (imageRules_ && stormCount_[exception] == kStormEntries) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "exception %d returned %u times in a row with its source still pending (0x%X): the handler "
                  "never clears it, so the line re-enters it at once and Thread code starves",
                  exception, kStormEntries, again);
    violate(Rule::IrqStorm, buf);
  }
}

void Machine::onExceptionReturn(int exception) {
  InterruptFigures& f = irqFigures_[exception];
  f.worstHandlerCycles = std::max(f.worstHandlerCycles, now() - enteredAt_[exception]);
  pendingAtReturn_[exception] = interruptSources(exception).pending;
  // A level still asserted is a new request (the NVIC pends it again on return).
  if (exception >= Nvic::kIrq0 && (irqLevels_ >> (exception - Nvic::kIrq0)) & 1U) {
    requested_[exception] = true;
    requestedAt_[exception] = now();
  }
}

void Machine::onHardFault(const std::string& why) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.6f s: ", static_cast<double>(now()) / layout_.clockHz);
  std::string text = buf + why;
  if (symbolizer_) {
    const std::string fn = symbolizer_(core_.pc());
    if (!fn.empty()) text += " in " + fn;
  }
  hardFaultLog_.push_back(text);
}

bool Machine::busRead(uint32_t address, unsigned bytes, uint32_t& value) {
  const uint8_t* p = nullptr;
  if (address + bytes <= layout_.flashSize) {
    p = flash_.data() + address;
  } else if (address - layout_.sramBase < layout_.sramSize &&
             address - layout_.sramBase + bytes <= layout_.sramSize) {
    p = sram_.data() + (address - layout_.sramBase);
  }
  if (p == nullptr) return map_.load(address, bytes, value);
  value = 0;
  for (unsigned i = 0; i < bytes; ++i)
    value |= static_cast<uint32_t>(p[i]) << (8 * i);
  return true;
}

bool Machine::busWrite(uint32_t address, unsigned bytes, uint32_t value) {
  if (address - layout_.sramBase < layout_.sramSize &&
      address - layout_.sramBase + bytes <= layout_.sramSize) {
    uint8_t* p = sram_.data() + (address - layout_.sramBase);
    for (unsigned i = 0; i < bytes; ++i)
      p[i] = static_cast<uint8_t>(value >> (8 * i));
    return true;
  }
  if (address < layout_.flashSize) return false;
  return map_.store(address, bytes, value);
}

uint32_t Machine::readSram32(uint32_t address) const {
  const uint32_t at = address - layout_.sramBase;
  if (at + 4 > layout_.sramSize) return 0;
  return static_cast<uint32_t>(sram_[at] | sram_[at + 1] << 8 | sram_[at + 2] << 16) |
         static_cast<uint32_t>(sram_[at + 3]) << 24;
}

uint64_t Machine::worldNext() const {
  uint64_t us = 0;
  if (world_ == nullptr || !world_->nextEvent(us)) return UINT64_MAX;
  return us * cyclesPerUs();
}

void Machine::syncWorld() {
  if (world_ == nullptr || worldBusy_) return;
  worldBusy_ = true;
  world_->advanceTo(std::max(now() / cyclesPerUs(), world_->nowUs()));
  worldBusy_ = false;
}

void Machine::fireDue() {
  const uint64_t perUs = cyclesPerUs();
  auto advanceWorld = [&](uint64_t us) {
    if (world_ == nullptr || worldBusy_) return;
    worldBusy_ = true;
    world_->advanceTo(std::max(us, world_->nowUs()));  // runs every world event up to `us`, in order
    worldBusy_ = false;
  };
  for (;;) {
    const uint64_t t = now();
    const uint64_t mine = timeline_.next(), theirs = worldNext();
    if (mine > t && theirs > t) break;
    if (theirs <= mine) {
      advanceWorld(theirs / perUs);
    } else {
      advanceWorld(mine / perUs);
      timeline_.fireNext(t);
    }
  }
  advanceWorld(now() / perUs);
  for (auto& hook : eventHooks_)
    hook();
}

bool Machine::stepCore() {
  const uint32_t pc = core_.pc();
  const uint32_t ipsr = core_.ipsr();
  enteredException_ = false;
  const uint32_t spent = core_.step();
  if (spent == 0) return false;
  if (profiler_ != nullptr) profiler_->account(pc, ipsr, core_.ipsr(), enteredException_, spent);
  timeline_.advanceTo(now() + spent);
  busy_ += spent;
  return true;
}

void Machine::run(uint64_t endCycle) {
  while (!core_.halted() && now() < endCycle) {
    if (pendingReset_) reset(*pendingReset_, pendingResetCause_, pendingCauseId_);
    fireDue();
    if (core_.halted()) break;
    const uint64_t horizon = std::min({endCycle, timeline_.next(), worldNext()});
    if (held_) {
      timeline_.advanceTo(std::max(horizon, now()));
      continue;
    }
    if (now() < wakeUntil_) {
      // Waking from STOP or STANDBY (the data sheets' tWAKE, power.hpp): the core has not started yet; the
      // peripherals and the world run on, and interrupts that arrive meanwhile are pending when it starts.
      const uint64_t until = std::min(horizon, wakeUntil_);
      waking_ += until - now();
      timeline_.advanceTo(until);
      continue;
    }
    if (core_.sleeping()) {
      // Wakes only if an interrupt would preempt; the step that wakes takes that exception (sleep-on-exit,
      // PRIMASK clear) or runs the instruction after the WFI, and is counted like any other.
      stepCore();
      if (!core_.sleeping()) {
        if (isDeepSleep(sleptIn_)) wakeUntil_ = now() + wakeCycles_[static_cast<size_t>(sleptIn_)];
        sleptIn_ = PowerMode::Run;
        if (now() < wakeUntil_) continue;
      }
      if (core_.sleeping()) {
        const PowerMode mode = sleepMode();
        sleptIn_ = mode;
        const uint64_t from = now();
        for (const auto& hook : sleepHooks_)
          hook();
        if (isDeepSleep(mode)) checkSleep(mode);
        if (core_.halted()) break;
        timeline_.advanceTo(std::max(horizon, now()));
        deepCycles_[static_cast<size_t>(mode)] += isDeepSleep(mode) ? now() - from : 0;
        continue;
      }
    }
    timeline_.clearRearmed();
    while (now() < horizon) {
      if (now() < flashBusyUntil_ && (core_.pc() < layout_.flashSize || core_.waitingForFlash())) {
        // The next fetch, or the load of the instruction that waits, is from the flash bank FLASHCTL is busy
        // with: the core stalls (busy, not asleep).
        const uint64_t until = std::min(flashBusyUntil_, horizon);
        if (profiler_ != nullptr) {
          profiler_->account(core_.pc(), core_.ipsr(), core_.ipsr(), false,
                             static_cast<uint32_t>(until - now()));
        }
        busy_ += until - now();
        timeline_.advanceTo(until);
        continue;
      }
      if (!stepCore()) break;
      if (timeline_.rearmed() || pendingReset_ || core_.sleeping()) break;
    }
  }
  if (!core_.halted()) fireDue();
  if (pendingReset_ && !core_.halted()) reset(*pendingReset_, pendingResetCause_, pendingCauseId_);
}

}  // namespace twin
