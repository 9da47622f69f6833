#include "sim/trace_recorder.hpp"

#include <algorithm>
#include <cstdio>

#include "sim/sim_clock.hpp"

namespace bsp::host {

using fw::sched::TraceKind;

void TraceRecorder::record(TraceKind kind, uint8_t task, uint32_t arg) {
  records_.push_back(TraceRecord{clock_.nowUs(), kind, task, arg});
}

size_t TraceRecorder::count(TraceKind kind) const {
  return static_cast<size_t>(
      std::count_if(records_.begin(), records_.end(), [&](const TraceRecord& r) { return r.kind == kind; }));
}

size_t TraceRecorder::count(TraceKind kind, uint8_t task) const {
  return static_cast<size_t>(std::count_if(records_.begin(), records_.end(), [&](const TraceRecord& r) {
    return r.kind == kind && r.task == task;
  }));
}

std::string TraceRecorder::render(const TraceRecord& r) {
  char text[48];
  switch (r.kind) {
    case TraceKind::Post:
      std::snprintf(text, sizeof text, "post:%u", r.task);
      break;
    case TraceKind::Run:
      std::snprintf(text, sizeof text, "run:%u", r.task);
      break;
    case TraceKind::RunEnd:
      std::snprintf(text, sizeof text, "runend:%u", r.task);
      break;
    case TraceKind::Idle:
      std::snprintf(text, sizeof text, "idle");
      break;
    case TraceKind::TimerFire:
      std::snprintf(text, sizeof text, "timer:%u", r.task);
      break;
    case TraceKind::TimerOverrun:
      std::snprintf(text, sizeof text, "timeroverrun:%u", r.task);
      break;
    case TraceKind::QueueFull:
      std::snprintf(text, sizeof text, "queuefull:%u", r.task);
      break;
    case TraceKind::Overrun:
      std::snprintf(text, sizeof text, "overrun:%u", r.task);
      break;
    case TraceKind::WatchdogFeed:
      std::snprintf(text, sizeof text, "wdfeed");
      break;
    case TraceKind::WatchdogStarved:
      std::snprintf(text, sizeof text, "wdstarved:0x%x", r.arg);
      break;
  }
  return text;
}

std::vector<std::string> TraceRecorder::compact(std::initializer_list<TraceKind> kinds) const {
  std::vector<std::string> out;
  for (const auto& r : records_) {
    if (kinds.size() != 0 && std::find(kinds.begin(), kinds.end(), r.kind) == kinds.end()) continue;
    out.push_back(render(r));
  }
  return out;
}

}  // namespace bsp::host
