// EventQueue<T, N>: a data-carrying event channel from one ISR (or task) to one task.
//
// post(item) pushes the item and posts `event` to the owning task, so the task wakes and drains the queue
// with pop(). The queue-full policy is chosen per queue:
//   Policy::CountAndDrop  the newest item is dropped, counted in dropped() and in the task's queueDrops,
//                         and traced; post() returns false. For data where loss is tolerable and must be
//                         visible (received CAN frames, UART bytes).
//   Policy::Assert        a full queue is a design error (the queue was sized for the worst case): FW_ASSERT.
// The owning task is still posted when an item is dropped, so a slow consumer is woken to catch up.
//
// Contract: one producer context, one consumer context (see SpscQueue). post() is ISR-safe.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/assert.hpp"
#include "core/spsc_queue.hpp"
#include "sched/scheduler.hpp"

namespace fw::sched {

enum class QueuePolicy : uint8_t { CountAndDrop, Assert };

template <class T, size_t N>
class EventQueue {
 public:
  EventQueue(Scheduler& scheduler, TaskId owner, EventMask event, QueuePolicy policy)
      : scheduler_(scheduler), owner_(owner), event_(event), policy_(policy) {}

  bool post(const T& item) {
    const bool stored = queue_.push(item);
    if (!stored) {
      FW_ASSERT_MODULE(::fw::Module::Sched, policy_ != QueuePolicy::Assert);
      dropped_ = dropped_ + 1;
      scheduler_.noteQueueDrop(owner_);
    }
    scheduler_.post(owner_, event_);
    return stored;
  }

  bool pop(T& item) { return queue_.pop(item); }
  size_t size() const { return queue_.size(); }
  uint32_t dropped() const { return dropped_; }

 private:
  SpscQueue<T, N> queue_;
  Scheduler& scheduler_;
  volatile uint32_t dropped_ = 0;  // written by the producer, read by anyone
  TaskId owner_;
  EventMask event_;
  QueuePolicy policy_;
};

}  // namespace fw::sched
