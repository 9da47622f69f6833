#include "race_watch.hpp"

#include <cstdio>

namespace twin {

RaceWatch::RaceWatch(Core& core, uint32_t low, uint32_t high, uint32_t stackLow,
                     std::function<uint64_t()> armed, std::function<InterruptSources(int)> sources,
                     std::function<void(const std::string&)> report)
    : core_(core),
      low_(low),
      high_(high > low ? high : low),
      stackLow_(stackLow),
      armed_(std::move(armed)),
      sources_(std::move(sources)),
      report_(std::move(report)),
      bytes_(high_ - low_) {}

void RaceWatch::reset() {
  std::fill(bytes_.begin(), bytes_.end(), Byte{});
  entered_.fill(0);
}

void RaceWatch::onExceptionEntry(int exception) {
  if (exception >= 0 && exception < kExceptions)
    entered_[static_cast<size_t>(exception)] = sources_(exception).pending;
}

// What a handler runs for: the sources pending at its entry and those that come while it runs, seen at each
// of its RAM accesses (a handler reads MIS once and may then serve a source raised after its entry: the UART
// handler entered for a received byte finishes a transmission whose EOT came meanwhile).
void RaceWatch::noteHandlerSources() {
  const int e = static_cast<int>(core_.ipsr());
  if (e < kExceptions) entered_[static_cast<size_t>(e)] |= sources_(e).pending;
}

void RaceWatch::onSramLoad(uint32_t address, unsigned bytes) {
  if (core_.handlerMode()) {
    noteHandlerSources();
    return;
  }
  for (unsigned i = 0; i < bytes; ++i) {
    const uint32_t a = address + i;
    if (a - low_ >= bytes_.size()) continue;
    Byte& b = bytes_[a - low_];
    b.threadLoaded = true;
    b.loadSection = core_.primask() ? core_.maskSections() : 0;
  }
}

// The handler's write can come at the update when its exception can run then and every source it was
// entered for can assert then. A write whose entry had no sources (SysTick, PendSV, SVCall, a line without
// a source model) needs only the exception.
bool RaceWatch::couldPreempt(const Write& write, const Update& update) {
  if (((update.armed >> write.exception) & 1U) == 0) return false;
  return (write.sources & ~update.possible[write.exception]) == 0;
}

// Up to kKept distinct writes per byte; one more merges into the last kept write: of the same exception, it
// needs only the sources both share; of another, the last entry becomes a write that needs no source at all.
// Either way the rule only gets more cautious.
void RaceWatch::addWrite(Byte& byte, Write write) {
  for (uint8_t i = 0; i < byte.writeCount; ++i) {
    Write& w = byte.writes[i];
    if (w.exception == write.exception && w.sources == write.sources) return;
  }
  if (byte.writeCount < kKept) {
    byte.writes[byte.writeCount++] = write;
    return;
  }
  Write& last = byte.writes[kKept - 1];
  last.sources = last.exception == write.exception ? (last.sources & write.sources) : 0;
  last.exception = write.exception;
}

void RaceWatch::addUpdate(Byte& byte, uint32_t update) {
  for (uint8_t i = 0; i < byte.updateCount; ++i) {
    if (byte.updates[i] == update) return;
  }
  if (byte.updateCount < kKept) {
    byte.updates[byte.updateCount++] = update;
    return;
  }
  // A fifth configuration: the last slot becomes the union of both (more exceptions, more sources).
  Update merged = updates_[byte.updates[kKept - 1]];
  const Update& added = updates_[update];
  merged.armed |= added.armed;
  for (size_t e = 0; e < merged.possible.size(); ++e)
    merged.possible[e] |= added.possible[e];
  byte.updates[kKept - 1] = intern(merged);
}

// The firmware moves between a few interrupt configurations: each is kept once.
uint32_t RaceWatch::intern(const Update& update) {
  const auto [at, added] = known_.try_emplace(update, static_cast<uint32_t>(updates_.size()));
  if (added) updates_.push_back(update);
  return at->second;
}

// Computed at every unprotected Thread update, so kept cheap: an update like the one before reuses its index
// without a look-up.
uint32_t RaceWatch::currentUpdate() {
  Update now;
  now.armed = armed_();
  for (int e = 0; e < kExceptions; ++e) {
    if ((now.armed >> e) & 1U) now.possible[static_cast<size_t>(e)] = sources_(e).possible;
  }
  if (last_ < updates_.size() && sameUpdate(updates_[last_], now)) return last_;
  last_ = intern(now);
  return last_;
}

bool RaceWatch::sameUpdate(const Update& a, const Update& b) {
  if (a.armed != b.armed) return false;
  for (size_t e = 0; e < a.possible.size(); ++e) {
    if (a.possible[e] != b.possible[e]) return false;
  }
  return true;
}

void RaceWatch::onSramStore(uint32_t address, unsigned bytes) {
  const uint32_t pc = core_.pc();
  if (core_.handlerMode()) {
    noteHandlerSources();
    const int e = static_cast<int>(core_.ipsr());
    const Write write{static_cast<uint8_t>(e), e < kExceptions ? entered_[static_cast<size_t>(e)] : 0};
    const uint32_t ownTop = core_.handlerStackTop();
    for (unsigned i = 0; i < bytes; ++i) {
      const uint32_t a = address + i;
      if (a - low_ >= bytes_.size() || (a >= stackLow_ && a < ownTop)) continue;
      Byte& b = bytes_[a - low_];
      addWrite(b, write);
      b.handlerPc = pc;
      for (uint8_t u = 0; u < b.updateCount; ++u) {
        if (couldPreempt(write, updates_[b.updates[u]])) fire(a, e, b.threadPc, pc);
      }
    }
    return;
  }
  bool updateKnown = false;
  uint32_t update = 0;
  for (unsigned i = 0; i < bytes; ++i) {
    const uint32_t a = address + i;
    if (a - low_ >= bytes_.size()) continue;
    Byte& b = bytes_[a - low_];
    if (!b.threadLoaded) continue;
    b.threadLoaded = false;
    const bool protectedUpdate =
        core_.primask() && b.loadSection != 0 && b.loadSection == core_.maskSections();
    if (protectedUpdate) continue;
    if (!updateKnown) update = currentUpdate(), updateKnown = true;
    addUpdate(b, update);
    b.threadPc = pc;
    for (uint8_t w = 0; w < b.writeCount; ++w) {
      if (couldPreempt(b.writes[w], updates_[update])) fire(a, b.writes[w].exception, pc, b.handlerPc);
    }
  }
}

void RaceWatch::fire(uint32_t address, int exception, uint32_t threadPc, uint32_t handlerPc) {
  if (fired_) return;
  auto where = [&](uint32_t pc) {
    if (describe_) return describe_(pc);
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%08X", pc);
    return std::string(buf);
  };
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "RAM byte 0x%08X: Thread mode reads and writes it outside a critical section (PRIMASK) while "
                "exception %d, which writes it too, can preempt for the same interrupt source",
                address, exception);
  report_(std::string(buf) + "; the Thread update at " + where(threadPc) + ", the handler's store at " +
          where(handlerPc));
}

}  // namespace twin
