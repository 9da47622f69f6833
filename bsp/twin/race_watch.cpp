#include "race_watch.hpp"

#include <cstdio>

namespace twin {

RaceWatch::RaceWatch(Core& core, uint32_t low, uint32_t high, uint32_t stackLow,
                     std::function<uint64_t()> armed, std::function<void(const std::string&)> report)
    : core_(core),
      low_(low),
      high_(high > low ? high : low),
      stackLow_(stackLow),
      armed_(std::move(armed)),
      report_(std::move(report)),
      bytes_(high_ - low_) {}

void RaceWatch::reset() {
  std::fill(bytes_.begin(), bytes_.end(), Byte{});
}

void RaceWatch::onSramLoad(uint32_t address, unsigned bytes) {
  if (core_.handlerMode()) return;
  for (unsigned i = 0; i < bytes; ++i) {
    const uint32_t a = address + i;
    if (a - low_ >= bytes_.size()) continue;
    Byte& b = bytes_[a - low_];
    b.threadLoaded = true;
    b.loadSection = core_.primask() ? core_.maskSections() : 0;
  }
}

void RaceWatch::onSramStore(uint32_t address, unsigned bytes) {
  const uint32_t pc = core_.pc();
  if (core_.handlerMode()) {
    const int e = static_cast<int>(core_.ipsr());
    const uint64_t bit = 1ULL << e;
    const uint32_t ownTop = core_.handlerStackTop();
    for (unsigned i = 0; i < bytes; ++i) {
      const uint32_t a = address + i;
      if (a - low_ >= bytes_.size() || (a >= stackLow_ && a < ownTop)) continue;
      Byte& b = bytes_[a - low_];
      b.writers |= bit;
      b.handlerPc = pc;
      if (b.raced & bit) fire(a, e, b.threadPc, pc);
    }
    return;
  }
  uint64_t armedNow = 0;
  bool armedKnown = false;
  for (unsigned i = 0; i < bytes; ++i) {
    const uint32_t a = address + i;
    if (a - low_ >= bytes_.size()) continue;
    Byte& b = bytes_[a - low_];
    if (!b.threadLoaded) continue;
    b.threadLoaded = false;
    const bool protectedUpdate =
        core_.primask() && b.loadSection != 0 && b.loadSection == core_.maskSections();
    if (protectedUpdate) continue;
    if (!armedKnown) armedNow = armed_(), armedKnown = true;
    b.raced |= armedNow;
    b.threadPc = pc;
    const uint64_t both = b.writers & armedNow;
    if (both != 0) fire(a, __builtin_ctzll(both), pc, b.handlerPc);
  }
}

void RaceWatch::fire(uint32_t address, int exception, uint32_t threadPc, uint32_t handlerPc) {
  if (fired_) return;
  fired_ = true;
  auto where = [&](uint32_t pc) {
    if (describe_) return describe_(pc);
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%08X", pc);
    return std::string(buf);
  };
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "RAM byte 0x%08X: Thread mode reads and writes it outside a critical section (PRIMASK) while "
                "exception %d, which writes it too, can preempt",
                address, exception);
  report_(std::string(buf) + "; the Thread update at " + where(threadPc) + ", the handler's store at " +
          where(handlerPc));
}

}  // namespace twin
