// SimClock: virtual time for host builds. Nothing happens until a test or tool advances it.
//
// - Time is kept in 64-bit microseconds (nowUs()); the firmware sees the low 32 bits through hal::Clock.
// - schedule(at, fn) queues a simulation event (a device emulator finishing a byte, a bus completing a
//   transfer). advanceTo(t) runs due events in time order (ties in scheduling order), setting now to each
//   event's time while it runs, then sets now = t. Events typically raise a SimIrq line.
// - The scheduler's wakeAt() becomes an alarm event on the "timer" interrupt line, exactly as a compare
//   interrupt would wake the target.
// - A task body may call advance() to model CPU time it consumes; due events (interrupts) fire inside it.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <utility>

#include "hal/clock.hpp"

namespace bsp::host {

class SimIrq;

class SimClock final : public fw::hal::Clock {
 public:
  using Callback = std::function<void()>;
  using EventId = uint64_t;

  explicit SimClock(SimIrq& irq);

  uint64_t nowUs() const { return now_; }
  EventId schedule(uint64_t atUs, Callback callback);
  EventId scheduleIn(fw::Duration delay, Callback callback) {
    return schedule(now_ + delay.us, std::move(callback));
  }
  void cancel(EventId id);

  void advanceTo(uint64_t timeUs);
  // The same, except that events due exactly at `timeUs` stay pending (they run on the next advance).
  void advanceBefore(uint64_t timeUs);
  void advance(fw::Duration d) { advanceTo(now_ + d.us); }
  // Runs only the earliest pending event (if any is due by `limitUs`), moving time to it. False if none.
  bool step(uint64_t limitUs);
  // Time of the earliest pending event (including the wake alarm); false if none.
  bool nextEvent(uint64_t& atUs) const;

  // How often the firmware read the clock and armed its wake-up (the scheduler's cost, tests).
  uint64_t reads() const { return reads_; }
  uint64_t wakeAts() const { return wakeAts_; }

  // Converts a firmware Instant (32-bit) to the nearest 64-bit time at or around now.
  uint64_t expand(fw::Instant instant) const;

 private:
  fw::Instant doNow() const override {
    ++reads_;
    return fw::Instant{static_cast<uint32_t>(now_)};
  }
  void doWakeAt(fw::Instant deadline) override;

  SimIrq& irq_;
  int timerLine_;
  uint64_t now_ = 0;
  uint64_t nextSeq_ = 1;
  std::map<std::pair<uint64_t, uint64_t>, Callback> events_;  // (time, seq) -> callback
  EventId alarm_ = 0;
  uint64_t alarmAt_ = 0;  // the alarm's time: doWakeAt() erases it by key, not by a search of every event
  bool advancing_ = false;
  mutable uint64_t reads_ = 0;
  uint64_t wakeAts_ = 0;
};

}  // namespace bsp::host
