// SpscQueue<T, N>: a fixed-capacity single-producer / single-consumer ring, safe from one ISR to one task.
//
// Contract
// - Exactly one producer context calls push() (typically an ISR) and exactly one consumer context calls
//   pop()/front()/size() (typically a task). Neither side ever blocks or masks interrupts.
// - push() on a full queue stores nothing and returns false; the caller decides the policy (count and drop,
//   or assert). The scheduler's EventQueue wraps this with a named policy.
// - N must be a power of two (indices run freely and are masked); capacity is exactly N.
// - Ordering: producer and consumer are an ISR and a task on the same core, so each sees the other's memory
//   accesses in program order (ARMv6-M has no LDREX/STREX and no lock-free std::atomic, and needs none
//   here). Only the compiler could reorder the slot access against the index update; a signal fence on each
//   side prevents that. The indices are volatile so each side re-reads the other's index.
#pragma once

#include <atomic>  // std::atomic_signal_fence only
#include <cstddef>
#include <cstdint>

namespace fw {

template <class T, size_t N>
class SpscQueue {
  static_assert(N >= 2 && N <= 32768 && (N & (N - 1)) == 0, "capacity must be a power of two");
  using Index = uint16_t;  // a 16-bit load or store is a single, indivisible instruction

 public:
  static constexpr size_t capacity() { return N; }

  // Producer side. Returns false (and stores nothing) when full.
  bool push(const T& item) {
    const Index head = head_;
    const Index tail = tail_;
    if (static_cast<Index>(head - tail) == N) return false;
    std::atomic_signal_fence(std::memory_order_acquire);  // the consumer is done with that slot
    slots_[head & kMask] = item;
    std::atomic_signal_fence(std::memory_order_release);  // the slot is written before it is published
    head_ = static_cast<Index>(head + 1);
    return true;
  }

  // Consumer side. Returns false when empty; otherwise moves the oldest element into `out`.
  bool pop(T& out) {
    const Index tail = tail_;
    const Index head = head_;
    if (head == tail) return false;
    std::atomic_signal_fence(std::memory_order_acquire);  // the slot is read after its publication
    out = slots_[tail & kMask];
    std::atomic_signal_fence(std::memory_order_release);  // the slot is read before it is freed
    tail_ = static_cast<Index>(tail + 1);
    return true;
  }

  // Consumer side: number of stored elements (a lower bound while the producer is active).
  size_t size() const { return static_cast<Index>(head_ - tail_); }
  bool empty() const { return size() == 0; }

 private:
  static constexpr Index kMask = static_cast<Index>(N - 1);
  T slots_[N]{};
  volatile Index head_ = 0;  // written by the producer only
  volatile Index tail_ = 0;  // written by the consumer only
};

}  // namespace fw
