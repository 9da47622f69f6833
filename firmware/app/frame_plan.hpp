// FramePlan: the CAN frames of one publish cycle, built one at a time from the live pack.
//
// A cycle is a list of messages; frames are built only when the sink is ready to take them (build()), and the
// plan moves on only once a frame was accepted (advance()). So a frame held back by a full queue or a bus-off
// is rebuilt from the current data when it finally goes, never sent with the data it had when the cycle
// began. Boards whose data is not Valid (pack_view.hpp) are sent with their status and zeroed values.
//
// Cycles
//   fast (every 100 ms)   PackSummary, CellExtremes, then ProtectionEvent if a fault tripped or cleared
//   slow (every 1000 ms)  the fast frames, then CellVoltages and Temperatures of every board,
//                         TemperatureExtremes
//   ti (after each scan)  seed 001's layout: per board, top of stack first, four TiCellVoltages frames with
//                         cells 16..13, 12..9, 8..5, 4..1 as raw big-endian codes; only Valid boards (the
//                         layout has no status field, so an invalid board is left out rather than faked)
// Contract: thread mode (the publish task); the referenced pack and status must outlive the plan.
#pragma once

#include <cstdint>

#include "app/pack_view.hpp"
#include "app/publish_status.hpp"
#include "core/time.hpp"
#include "hal/can_bus.hpp"

namespace fw::app {

enum class CanLayout : uint8_t { Native, Ti };

class FramePlan {
 public:
  FramePlan(const PackView& pack, PublishStatus& status, Duration staleAfter)
      : pack_(pack), status_(status), staleAfter_(staleAfter) {}

  void beginFast() { begin(kFast); }
  void beginSlow() { begin(kSlow); }
  void beginTi() { begin(kTi); }
  bool active() const { return next_ < count_; }

  // Builds the current frame into `out` (false when the cycle is complete).
  bool build(Instant now, hal::CanFrame& out);
  // The frame from the last build() was accepted: move to the next one.
  void advance();
  // Drops the rest of the cycle (bus-off: the next cycle starts from fresh data).
  void abandon() { next_ = count_; }

 private:
  enum Kind : uint8_t { kFast, kSlow, kTi };
  void begin(Kind kind);
  static uint8_t framesPerBoard(uint8_t items) { return static_cast<uint8_t>((items + 2) / 3); }

  const PackView& pack_;
  PublishStatus& status_;
  Duration staleAfter_;
  Kind kind_ = kFast;
  bool event_ = false;  // this cycle carries a ProtectionEvent (a fault tripped or cleared before it began)
  uint16_t next_ = 0;   // index of the frame to build in this cycle
  uint16_t count_ = 0;  // frames in this cycle
  uint8_t counter_ = 0;
};

}  // namespace fw::app
