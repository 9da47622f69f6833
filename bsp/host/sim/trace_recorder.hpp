// TraceRecorder: keeps every scheduler decision (fw::sched::TraceSink) with its virtual time, for trace
// tests.
//
// Each record is (time in us, kind, task, arg). compact() renders the sequence in a short form that tests
// compare against expectations, e.g. {"post:2", "run:2", "idle"}; a filter selects the kinds of interest.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "sched/trace.hpp"

namespace bsp::host {

class SimClock;

struct TraceRecord {
  uint64_t timeUs;
  fw::sched::TraceKind kind;
  uint8_t task;
  uint32_t arg;
};

class TraceRecorder final : public fw::sched::TraceSink {
 public:
  explicit TraceRecorder(const SimClock& clock) : clock_(clock) {}

  void record(fw::sched::TraceKind kind, uint8_t task, uint32_t arg) override;

  const std::vector<TraceRecord>& records() const { return records_; }
  void clear() { records_.clear(); }
  size_t count(fw::sched::TraceKind kind) const;
  size_t count(fw::sched::TraceKind kind, uint8_t task) const;

  // "post:2", "run:2", "runend:2", "idle", "timer:1", "timeroverrun:1", "queuefull:3", "overrun:2",
  // "wdfeed", "wdstarved:0x4". With an empty filter every kind is included.
  std::vector<std::string> compact(std::initializer_list<fw::sched::TraceKind> kinds = {}) const;
  static std::string render(const TraceRecord& record);

 private:
  const SimClock& clock_;
  std::vector<TraceRecord> records_;
};

}  // namespace bsp::host
