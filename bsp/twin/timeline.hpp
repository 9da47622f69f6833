// Timeline: the twin's virtual time, counted in CPU cycles (MCLK), and the peripheral events on it.
//
// Every model that does something later (a UART byte leaves, a timer reaches its compare, an I2C bit ends)
// owns TimedEvents and arms them for a cycle. The machine (machine.hpp) runs the CPU up to the earliest
// armed event and fires it; events fire in time order, ties in the order they were armed. An event's action
// runs with now() equal to the event's time, so state computed in it is exact to the cycle even though the
// CPU's instruction that crossed that time has already completed.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace twin {

class Timeline;

class TimedEvent {
 public:
  TimedEvent(Timeline& timeline, std::function<void()> action);
  ~TimedEvent();
  TimedEvent(const TimedEvent&) = delete;
  TimedEvent& operator=(const TimedEvent&) = delete;

  void at(uint64_t cycle);  // (re)arms; a time in the past fires at the next opportunity
  void after(uint64_t cycles);
  void cancel() { armed_ = false; }
  bool armed() const { return armed_; }
  uint64_t when() const { return at_; }

 private:
  friend class Timeline;
  Timeline& timeline_;
  std::function<void()> action_;
  uint64_t at_ = 0;
  uint64_t order_ = 0;
  bool armed_ = false;
};

class Timeline {
 public:
  uint64_t now() const { return now_; }
  // The earliest armed event's time, or UINT64_MAX.
  uint64_t next() const;
  // Fires the earliest event if it is due at or before `limit` (now() becomes its time, if later than now).
  bool fireNext(uint64_t limit);
  // Moves time forward (never back): the CPU spent cycles, or slept to an event.
  void advanceTo(uint64_t cycle) {
    if (cycle > now_) now_ = cycle;
  }
  // Set when an event is armed; the machine clears it and recomputes its horizon.
  bool rearmed() const { return rearmed_; }
  void clearRearmed() { rearmed_ = false; }

 private:
  friend class TimedEvent;
  void attach(TimedEvent* e) { events_.push_back(e); }
  void detach(TimedEvent* e);

  uint64_t now_ = 0;
  uint64_t order_ = 0;
  bool rearmed_ = false;
  std::vector<TimedEvent*> events_;
};

}  // namespace twin
