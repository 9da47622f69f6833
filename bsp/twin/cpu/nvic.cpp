#include "cpu/nvic.hpp"

namespace twin {

namespace {
// Exceptions that exist on ARMv6-M (B1.5.2): Reset, NMI, HardFault, SVCall, PendSV, SysTick, IRQ 0..31.
constexpr uint64_t kSystemExceptions = (1ULL << Nvic::kNmi) | (1ULL << Nvic::kHardFault) |
                                       (1ULL << Nvic::kSvcall) | (1ULL << Nvic::kPendsv) |
                                       (1ULL << Nvic::kSystick);
}  // namespace

void Nvic::reset() {
  latch_ = level_ = active_ = 0;
  enabled_ = 0;
  everEnabled_ = 0;
  priority_.fill(0);
  priority_[kReset] = -3;  // B1.5.4: fixed priorities
  priority_[kNmi] = -2;
  priority_[kHardFault] = -1;
}

void Nvic::setIrqLevel(int irq, bool asserted) {
  const uint64_t bit = 1ULL << (kIrq0 + irq);
  // A rising level latches pending even while the exception is active (it is entered again after return).
  if (asserted && (level_ & bit) == 0) latch_ |= bit;
  level_ = asserted ? (level_ | bit) : (level_ & ~bit);
}

void Nvic::setPending(int exception) {
  latch_ |= 1ULL << exception;
}

void Nvic::clearPending(int exception) {
  latch_ &= ~(1ULL << exception);
}

void Nvic::setPriorityField(int exception, uint8_t value) {
  if (exception <= kHardFault) return;  // fixed
  priority_[exception] = static_cast<int8_t>(value >> 6);
}

uint64_t Nvic::candidates() const {
  return pendingMask() & (kSystemExceptions | (static_cast<uint64_t>(enabled_) << kIrq0));
}

int Nvic::executionPriority(bool primask) const {
  int prio = kThreadPriority;
  for (uint64_t a = active_; a != 0; a &= a - 1) {
    const int e = __builtin_ctzll(a);
    if (priority_[e] < prio) prio = priority_[e];
  }
  if (primask && prio > 0) prio = 0;
  return prio;
}

int Nvic::pendingToTake(int executionPriority) const {
  int best = 0;
  int bestPrio = executionPriority;
  // Lowest exception number first, so a later one only wins with a strictly more urgent priority.
  for (uint64_t c = candidates(); c != 0; c &= c - 1) {
    const int e = __builtin_ctzll(c);
    if (priority_[e] < bestPrio) {
      best = e;
      bestPrio = priority_[e];
    }
  }
  return best;
}

void Nvic::activate(int exception) {
  latch_ &= ~(1ULL << exception);
  active_ |= 1ULL << exception;
}

void Nvic::deactivate(int exception) {
  active_ &= ~(1ULL << exception);
}

}  // namespace twin
