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

void FramePlan::begin(Kind kind) {
  kind_ = kind;
  step_ = kind == kTi ? kTiCells : kSummary;
  board_ = 0;
  frame_ = 0;
  skipEmpty();
}

// Steps past parts that have nothing to send in this cycle.
void FramePlan::skipEmpty() {
  for (;;) {
    switch (step_) {
      case kEvent:
        if ((status_.pendingTripped | status_.pendingCleared) != 0) return;
        step_ = kind_ == kSlow ? kCells : kDone;
        break;
      case kCells:
        if (pack_.cellsPerBoard != 0 && board_ < pack_.boards.size()) return;
        step_ = kTemps, board_ = 0, frame_ = 0;
        break;
      case kTemps:
        if (pack_.tempsPerBoard != 0 && board_ < pack_.boards.size()) return;
        step_ = kTempExtremes;
        break;
      case kTempExtremes:
        if (pack_.tempsPerBoard != 0) return;
        step_ = kDone;
        break;
      case kTiCells:
        if (pack_.rawCells != nullptr) return;
        step_ = kDone;
        break;
      default:
        return;
    }
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

  // Totals of the last scan go out only while that scan is fresh: never an old value as a current one.
  const PackTotals& t = pack_.totals;
  const bool fresh = elapsed(t.takenAt, now) <= staleAfter_;
  switch (step_) {
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
      const bool cells = step_ == kCells;
      if (cells) {
        use(bms::CellVoltages::kFields, bms::CellVoltages::kId);
      } else {
        use(bms::Temperatures::kFields, bms::Temperatures::kId);
      }
      const BoardSample& s = pack_.boards[board_];
      const BoardStatus st = boardStatus(s, now, staleAfter_);
      const uint8_t items = cells ? pack_.cellsPerBoard : pack_.tempsPerBoard;
      v[0] = board_, v[1] = frame_, v[2] = static_cast<uint8_t>(st);
      for (uint8_t k = 0; k < 3; ++k) {
        const auto i = static_cast<uint8_t>(frame_ * 3 + k);
        if (st == BoardStatus::Valid && i < items) v[3 + k] = clampU16(cells ? s.cellMv[i] : s.tempDeciK[i]);
      }
      break;
    }
    case kTiCells: {
      // Top of stack first: slot 0 is the highest board. Boards that are not Valid are left out.
      while (board_ < pack_.boards.size()) {
        const auto b = static_cast<uint16_t>(pack_.boards.size() - 1 - board_);
        if (boardStatus(pack_.boards[b], now, staleAfter_) == BoardStatus::Valid) break;
        ++board_;
      }
      if (board_ >= pack_.boards.size()) {
        step_ = kDone;
        return false;
      }
      use(bms::TiCellVoltages::kFields, bms::TiCellVoltages::kId);
      const int16_t* raw = pack_.rawCells + (pack_.boards.size() - 1 - board_) * kMaxCellsPerBoard;
      for (uint8_t k = 0; k < 4; ++k)
        v[k] = static_cast<uint16_t>(raw[15 - (frame_ * 4 + k)]);  // cells 16..1
      break;
    }
    case kDone:
      return false;
  }
  out = hal::CanFrame{id, false, 8, {}};
  can::pack(out.data, fields, v, count);
  return true;
}

void FramePlan::advance() {
  switch (step_) {
    case kSummary:
      ++counter_;
      step_ = kExtremes;
      break;
    case kExtremes:
      step_ = kEvent;
      break;
    case kEvent:
      status_.pendingTripped = 0;
      status_.pendingCleared = 0;
      step_ = kind_ == kSlow ? kCells : kDone;
      board_ = 0, frame_ = 0;
      break;
    case kCells:
      if (++frame_ >= framesPerBoard(pack_.cellsPerBoard)) frame_ = 0, ++board_;
      break;
    case kTemps:
      if (++frame_ >= framesPerBoard(pack_.tempsPerBoard)) frame_ = 0, ++board_;
      break;
    case kTempExtremes:
      step_ = kDone;
      break;
    case kTiCells:
      if (++frame_ >= 4) frame_ = 0, ++board_;
      break;
    case kDone:
      break;
  }
  skipEmpty();
}

}  // namespace fw::app
