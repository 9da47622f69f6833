#include "app/frame_plan.hpp"

#include "can/bms.hpp"

namespace fw::app {
namespace bms = fw::can::bms;

namespace {

uint16_t clampU16(int32_t v) {
  return static_cast<uint16_t>(v < 0 ? 0 : (v > 0xFFFF ? 0xFFFF : v));
}
int16_t clampI16(int32_t v) {
  return static_cast<int16_t>(v < -32768 ? -32768 : (v > 32767 ? 32767 : v));
}

}  // namespace

// A cycle is a numbered sequence of frames; which frame index k is follows from the pack's shape:
//   fast: summary, extremes, [event]
//   slow: the same, then cells (boards x frames per board), temperatures (likewise), temperature extremes
//   ti:   boards x 4 frames, top of stack first
void FramePlan::begin(Kind kind) {
  kind_ = kind;
  next_ = 0;
  const auto boards = static_cast<uint16_t>(pack_.boards.size());
  if (kind == kTi) {
    count_ = pack_.rawCells != nullptr ? static_cast<uint16_t>(boards * 4) : 0;
    return;
  }
  event_ = (status_.pendingTripped | status_.pendingCleared) != 0;
  count_ = static_cast<uint16_t>(2 + event_);
  if (kind == kSlow) {
    count_ = static_cast<uint16_t>(
        count_ + boards * (framesPerBoard(pack_.cellsPerBoard) + framesPerBoard(pack_.tempsPerBoard)) +
        (pack_.tempsPerBoard != 0 ? 1 : 0));
  }
}

bool FramePlan::build(Instant now, hal::CanFrame& out) {
  // Each case fills the raw values of one message in its field order (can/bms.hpp kFields); one call packs
  // them, so every message costs only its stores and all share one packing loop.
  uint32_t v[9] = {};  // the longest message (PackSummary) has nine fields
  const can::Field* fields = nullptr;
  uint8_t count = 0;
  uint32_t id = 0;
  auto use = [&](const auto& table, uint32_t messageId) {
    fields = table;
    count = static_cast<uint8_t>(sizeof table / sizeof table[0]);
    id = messageId;
  };
  static_assert(sizeof bms::PackSummary::kFields / sizeof(can::Field) <= 9);

  if (next_ >= count_) return false;
  // Map the frame index to its message, board and frame within the board.
  enum Step : uint8_t { kSummary, kExtremes, kEvent, kCells, kTemps, kTempExtremes, kTiCells };
  Step step = kTiCells;
  uint16_t k = next_;
  uint16_t board = 0;
  uint8_t frame = 0;
  if (kind_ == kTi) {
    board = static_cast<uint16_t>(k / 4), frame = static_cast<uint8_t>(k % 4);
  } else if (k < 2 + event_) {
    step = k == 0 ? kSummary : (k == 1 ? kExtremes : kEvent);
  } else {
    k = static_cast<uint16_t>(k - 2 - event_);
    const uint8_t cellFrames = framesPerBoard(pack_.cellsPerBoard);
    const uint8_t tempFrames = framesPerBoard(pack_.tempsPerBoard);
    const auto cellPart = static_cast<uint16_t>(pack_.boards.size() * cellFrames);
    const auto tempPart = static_cast<uint16_t>(pack_.boards.size() * tempFrames);
    if (k < cellPart) {
      step = kCells, board = static_cast<uint16_t>(k / cellFrames),
      frame = static_cast<uint8_t>(k % cellFrames);
    } else if (k - cellPart < tempPart) {
      k = static_cast<uint16_t>(k - cellPart);
      step = kTemps, board = static_cast<uint16_t>(k / tempFrames),
      frame = static_cast<uint8_t>(k % tempFrames);
    } else {
      step = kTempExtremes;
    }
  }

  // Totals of the last scan go out only while that scan is fresh: never an old value as a current one.
  const PackTotals& t = pack_.totals;
  const bool fresh = elapsed(t.takenAt, now) <= staleAfter_;
  switch (step) {
    case kSummary:
      use(bms::PackSummary::kFields, bms::PackSummary::kId);
      if (fresh && t.cells) {
        v[0] = clampU16((t.packMv + 5) / 10);
        v[1] = static_cast<uint16_t>(pack_.hasCurrent ? clampI16(pack_.currentMa / 10) : 0);
        v[6] = 1;  // DataValid
      }
      v[2] = (fresh && t.cells) ? pack_.stateOfCharge : 255;
      v[3] = status_.chargeOn;
      v[4] = status_.dischargeOn;
      v[5] = status_.faultOutput;
      v[7] = counter_ & 0xFU;
      v[8] = status_.active;
      break;
    case kExtremes:
      use(bms::CellExtremes::kFields, bms::CellExtremes::kId);
      if (fresh && t.cells)
        v[0] = clampU16(t.maxCell), v[1] = t.maxCellAt, v[2] = clampU16(t.minCell), v[3] = t.minCellAt;
      break;
    case kTempExtremes:
      use(bms::TemperatureExtremes::kFields, bms::TemperatureExtremes::kId);
      if (fresh && t.temps)
        v[0] = clampU16(t.maxTemp), v[1] = clampU16(t.minTemp), v[2] = t.maxTempAt, v[3] = t.minTempAt;
      break;
    case kEvent:
      use(bms::ProtectionEvent::kFields, bms::ProtectionEvent::kId);
      v[0] = status_.active, v[1] = status_.pendingTripped, v[2] = status_.pendingCleared,
      v[3] = status_.commErrors;
      break;
    case kCells:
    case kTemps: {
      // Board, frame index, status, then three slots of cells or temperatures (zero unless Valid).
      const bool cells = step == kCells;
      if (cells) {
        use(bms::CellVoltages::kFields, bms::CellVoltages::kId);
      } else {
        use(bms::Temperatures::kFields, bms::Temperatures::kId);
      }
      const BoardSample& s = pack_.boards[board];
      const BoardStatus st = boardStatus(s, now, staleAfter_);
      const uint8_t items = cells ? pack_.cellsPerBoard : pack_.tempsPerBoard;
      v[0] = board, v[1] = frame, v[2] = static_cast<uint8_t>(st);
      for (uint8_t j = 0; j < 3; ++j) {
        const auto i = static_cast<uint8_t>(frame * 3 + j);
        if (st == BoardStatus::Valid && i < items) v[3 + j] = clampU16(cells ? s.cellMv[i] : s.tempDeciK[i]);
      }
      break;
    }
    case kTiCells: {
      // Top of stack first: slot 0 is the highest board. A board that is not Valid is left out (the layout
      // has no status field to say so): its four frames are skipped.
      const auto b = static_cast<uint16_t>(pack_.boards.size() - 1 - board);
      if (boardStatus(pack_.boards[b], now, staleAfter_) != BoardStatus::Valid) {
        next_ = static_cast<uint16_t>((board + 1) * 4);
        return build(now, out);
      }
      use(bms::TiCellVoltages::kFields, bms::TiCellVoltages::kId);
      const int16_t* raw = pack_.rawCells + b * kMaxCellsPerBoard;
      for (uint8_t j = 0; j < 4; ++j)
        v[j] = static_cast<uint16_t>(raw[15 - (frame * 4 + j)]);  // cells 16..1
      break;
    }
  }
  out = hal::CanFrame{id, false, 8, {}};
  can::pack(out.data, fields, v, count);
  return true;
}

void FramePlan::advance() {
  if (next_ >= count_) return;
  if (next_ == 0 && kind_ != kTi) ++counter_;  // PackSummary's rolling counter counts summaries sent
  if (kind_ != kTi && event_ && next_ == 2) {
    status_.pendingTripped = 0;
    status_.pendingCleared = 0;
  }
  ++next_;
}

}  // namespace fw::app
