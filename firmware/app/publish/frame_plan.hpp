// FramePlan: the CAN frames of one publish cycle, built one at a time from the live pack.
//
// A cycle is a list of messages; frames are built only when the sink is ready to take them (build()), and the
// plan moves on only once a frame was accepted (advance()). So a frame held back by a full queue or a bus-off
// is rebuilt from the current data when it finally goes, never sent with the data it had when the cycle
// began. A value with no reading behind it goes out as its signal's not-available value (bms.yaml): the
// cells and sensors of a board whose data is not Valid (pack_view.hpp, sent with its status), slots beyond
// the board's cells or sensors, cells beside an open sense wire (status open_wire), extremes and totals with
// nothing fresh behind them.
//
// Cycles
//   start-up              after announceStartup(), the Startup message once: at the end of the next native
//                         cycle's fast part (PackSummary keeps its time), or before the next TI set; reset
//                         cause, firmware version, surviving fault record
//   fast (every 100 ms)   PackSummary, CellExtremes, then ProtectionEvent if a fault tripped or cleared
//   slow (every 1000 ms)  the fast frames, then CellVoltages and Temperatures of every board,
//                         TemperatureExtremes, StateOfCharge (not available where the build or the monitor
//                         has none), BalancingStatus of every board where the pack balances
//                         (PackView::balancing), and StorageStatus where the build has storage (FW_STORAGE)
//                         and the monitor a storage mode (PackView::storage.period set). The slow part may
//                         take longer than 100 ms (64 boards: 449 frames, about 120 ms at 500 kbit/s): a fast
//                         cycle that begins while it is still going sends its own frames first and then lets
//                         the slow part continue where it stopped. Only a slow cycle drops what is left of
//                         the previous one.
//   ti (after each scan)  seed 001's layout: per board, top of stack first, four TiCellVoltages frames with
//                         cells 16..13, 12..9, 8..5, 4..1 as raw big-endian codes. Only whole sets: a set
//                         begins only after a fresh scan that validated every board with no open wire (the
//                         layout has no board index or status, so a receiver counts frames from the top),
//                         a scan that ends while a set is going out starts none (the rest of the set
//                         carries its data), and a board that stops being Valid mid-set ends the set there.
// Images short of flash may build the native cycles with fewer messages (FW_PUBLISH_LEVEL,
// app/publish/publish_status.hpp); a message a build leaves out never comes up in a cycle.
// Contract: thread mode (the publish task); the referenced pack and status must outlive the plan.
#pragma once

#include <array>
#include <cstdint>

#include "app/pack/pack_view.hpp"
#include "app/publish/can_bits.hpp"
#include "app/publish/publish_status.hpp"
#include "can/bms.hpp"
#include "core/time.hpp"
#include "hal/can_bus.hpp"

namespace fw::app {

// The TI layout is built only where it is used (FW_CAN_TI_LAYOUT in can_bits.hpp: the lp-mspm0g3507-bq79616
// image and the host). Images built without it have no TI cycle: beginTi() starts none.

inline constexpr bool kTiLayout = FW_CAN_TI_LAYOUT != 0;

enum class CanLayout : uint8_t { Native, Ti };

// The native cycles' timing, from bms.yaml's cycle_ms: the fast messages (PackSummary) every kFastPeriod, the
// slow ones (CellVoltages) every kSlowEvery fast periods. Every publisher is built with these.
inline constexpr Duration kFastPeriod = ms(can::bms::PackSummary::kCycleMs);
inline constexpr uint8_t kSlowEvery = can::bms::CellVoltages::kCycleMs / can::bms::PackSummary::kCycleMs;
static_assert(can::bms::CellVoltages::kCycleMs % can::bms::PackSummary::kCycleMs == 0,
              "a slow cycle is a whole number of fast ones");

class FramePlan {
 public:
  FramePlan(const PackView& pack, PublishStatus& status, Duration staleAfter)
      : pack_(pack), status_(status), staleAfter_(staleAfter) {}

  // Each begin returns true when it dropped frames of an earlier cycle that had not gone out (a saturated
  // bus): the fast part of the last cycle, or, for a slow cycle, what was left of the last slow part.
  bool beginFast() { return kCoreMessages ? begin(false) : startFast(); }
  bool beginSlow() { return begin(true); }
  // A TI set after a scan; none while a set is going out.
  void beginTi();
  // The native cycle of a publish tick: slow every `slowEvery` ticks (`tick` counts them, 0 = slow), fast
  // otherwise. A build that sends only what every cycle carries (FW_PUBLISH_LEVEL 0) has no slow cycle.
  bool beginNative(uint8_t& tick, uint8_t slowEvery) {
    if (!kCoreMessages) return startFast();
    const bool slow = tick == 0;
    if (++tick == slowEvery) tick = 0;
    return begin(slow);
  }
  bool active() const { return step_ != kDone; }
  // The Startup message, sent once at the start of the next cycle (the image calls this once, at start-up).
  void announceStartup(const StartupInfo& info) {
    startup_ = info;
    startupPending_ = true;
  }

  // Fills `data` with the payload of the current frame (all 8 bytes) and returns its standard identifier,
  // or 0 when the cycle is complete. Every message of the catalogue is a classic 8-byte frame with a
  // standard identifier above 0, so a sink that formats frames itself (SLCAN) needs nothing else.
  uint16_t fill(Instant now, std::array<uint8_t, 8>& data);
  // Builds the current frame into `out` (false when the cycle is complete).
  bool build(Instant now, hal::CanFrame& out) {
    const uint16_t id = fill(now, out.data);
    out.id = id;
    out.extended = false;
    out.dlc = 8;
    return id != 0;
  }
  // The frame from the last build() was accepted: move to the next one.
  void advance();
  // Drops the rest of the cycle and any slow part waiting (bus-off: the next cycle starts from fresh data).
  void abandon() { step_ = resume_ = kDone; }

 private:
  // The messages of a cycle, in the order they go out; a cycle walks them and skips those it has no frame
  // of (framesIn() == 0). Fast part: kSummary..kEvent, then kStartup once; slow part: kCells..kStorage;
  // TI: kTiCells (after kStartup once).
  enum Step : uint8_t {
    kSummary,
    kExtremes,
    kEvent,
    kStartup,
    kCells,
    kTemps,
    kTempExtremes,
    kStateOfCharge,
    kBalancing,
#if FW_STORAGE != 0
    kStorage,  // only where the build has storage: no step, no code without it
#endif
    kTiCells,
    kDone
  };
  // The last step of the slow part.
#if FW_STORAGE != 0
  static constexpr Step kLastSlow = kStorage;
#else
  static constexpr Step kLastSlow = kBalancing;
#endif
  bool begin(bool slow);  // (.cpp) the cycles with a slow part (FW_PUBLISH_LEVEL 1 and up)
  // The fast part, PackSummary first (every build sends it, so no settle() is needed); a slow part in
  // progress waits for it (resume_). Inline: a build with PackSummary alone and no statistics keeps only
  // the stores.
  bool startFast() {
    const bool dropped = step_ <= kEvent;
    if (kCoreMessages && step_ >= kCells && step_ <= kLastSlow) resume_ = step_, resumeIndex_ = index_;
    if (sent(kEvent)) event_ = (status_.pendingTripped | status_.pendingCleared) != 0;
    if (kTiLayout) tiStartup_ = false;  // never set without the TI layout
    step_ = kSummary;
    index_ = 0;
    // Each cycle's PackSummary carries the next Counter value whether it goes out or not, so one that never
    // did (dropped here by the next cycle, or abandoned on a bus-off) leaves the gap bms.yaml promises.
    ++counter_;
    return dropped;
  }
  inline uint16_t framesIn(Step step) const;
  // Whether this build sends the message of `step` (FW_PUBLISH_LEVEL).
  static constexpr bool sent(Step step) {
    if (step == kExtremes || step == kTemps || step == kTempExtremes || step == kStateOfCharge ||
        step == kBalancing)
      return kAllMessages;
#if FW_STORAGE != 0
    if (step == kStorage) return kAllMessages;
#endif
    if (step == kEvent || step == kCells) return kCoreMessages;
    return true;
  }
  void settle();

  Step step_ = kDone;
  Step resume_ = kDone;     // where a slow part continues once the fast part is done (kDone: none)
  bool tiStartup_ = false;  // the Startup frame opens a TI set (kTiCells follows it)
  bool event_ = false;  // this cycle carries a ProtectionEvent (a fault tripped or cleared before it began)
  bool startupPending_ = false;  // announceStartup() was called and its frame has not gone out yet
  StartupInfo startup_{};
  uint8_t counter_ = 0xFF;    // PackSummary.Counter of the current cycle (4 bits): the first cycle's is 0
  uint16_t index_ = 0;        // frame within the current step
  uint16_t resumeIndex_ = 0;  // ... and within resume_
  const PackView& pack_;
  PublishStatus& status_;
  Duration staleAfter_;
};

}  // namespace fw::app
