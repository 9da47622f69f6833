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
        if (pack_.rawCells == nullptr) {
          step_ = kDone;
          break;
        }
        return;
      default:
        return;
    }
  }
}

bool FramePlan::build(Instant now, hal::CanFrame& out) {
  // Extremes over the boards that are Valid now.
  int32_t maxCell = 0, minCell = 0, maxTemp = 0, minTemp = 0;
  uint16_t maxCellAt = 0, minCellAt = 0, maxTempAt = 0, minTempAt = 0;
  int32_t packMv = 0;
  bool any = false, anyTemp = false;
  const bool needExtremes = step_ == kSummary || step_ == kExtremes || step_ == kTempExtremes;
  for (uint16_t b = 0; needExtremes && b < pack_.boards.size(); ++b) {
    const BoardSample& s = pack_.boards[b];
    if (boardStatus(s, now, staleAfter_) != BoardStatus::Valid) continue;
    for (uint8_t c = 0; c < pack_.cellsPerBoard; ++c) {
      const int32_t v = s.cellMv[c];
      const uint16_t at = static_cast<uint16_t>(b * kMaxCellsPerBoard + c);
      packMv += v;
      if (!any || v > maxCell) maxCell = v, maxCellAt = at;
      if (!any || v < minCell) minCell = v, minCellAt = at;
      any = true;
    }
    for (uint8_t t = 0; t < pack_.tempsPerBoard; ++t) {
      const int32_t v = s.tempDeciK[t];
      const uint16_t at = static_cast<uint16_t>(b * kMaxTempsPerBoard + t);
      if (!anyTemp || v > maxTemp) maxTemp = v, maxTempAt = at;
      if (!anyTemp || v < minTemp) minTemp = v, minTempAt = at;
      anyTemp = true;
    }
  }

  switch (step_) {
    case kSummary: {
      bms::PackSummary m;
      m.packVoltage = clampU16((packMv + 5) / 10);
      const bool currentOk = any && pack_.hasCurrent;
      m.packCurrent = currentOk ? clampI16(pack_.currentMa / 10) : 0;
      m.stateOfCharge = any ? pack_.stateOfCharge : 255;
      m.chargeFet = status_.chargeOn ? 1 : 0;
      m.dischargeFet = status_.dischargeOn ? 1 : 0;
      m.faultOutput = status_.faultOutput ? 1 : 0;
      m.dataValid = any ? 1 : 0;
      m.counter = static_cast<uint8_t>(counter_ & 0xF);
      m.activeFaults = status_.active;
      out = m.pack();
      return true;
    }
    case kExtremes: {
      bms::CellExtremes m;
      if (any) {
        m.maxCellVoltage = clampU16(maxCell), m.maxCellIndex = maxCellAt;
        m.minCellVoltage = clampU16(minCell), m.minCellIndex = minCellAt;
      }
      out = m.pack();
      return true;
    }
    case kEvent: {
      bms::ProtectionEvent m;
      m.activeFaults = status_.active;
      m.newlyTripped = status_.pendingTripped;
      m.newlyCleared = status_.pendingCleared;
      m.commErrors = status_.commErrors;
      out = m.pack();
      return true;
    }
    case kCells: {
      const BoardSample& s = pack_.boards[board_];
      const BoardStatus st = boardStatus(s, now, staleAfter_);
      bms::CellVoltages m;
      m.board = static_cast<uint8_t>(board_);
      m.frameIndex = frame_;
      m.status = static_cast<uint8_t>(st);
      for (uint8_t k = 0; k < 3; ++k) {
        const uint8_t c = static_cast<uint8_t>(frame_ * 3 + k);
        m.cell[k] = (st == BoardStatus::Valid && c < pack_.cellsPerBoard) ? clampU16(s.cellMv[c]) : 0;
      }
      out = m.pack();
      return true;
    }
    case kTemps: {
      const BoardSample& s = pack_.boards[board_];
      const BoardStatus st = boardStatus(s, now, staleAfter_);
      bms::Temperatures m;
      m.board = static_cast<uint8_t>(board_);
      m.frameIndex = frame_;
      m.status = static_cast<uint8_t>(st);
      for (uint8_t k = 0; k < 3; ++k) {
        const uint8_t t = static_cast<uint8_t>(frame_ * 3 + k);
        m.temp[k] = (st == BoardStatus::Valid && t < pack_.tempsPerBoard) ? clampU16(s.tempDeciK[t]) : 0;
      }
      out = m.pack();
      return true;
    }
    case kTempExtremes: {
      bms::TemperatureExtremes m;
      if (anyTemp) {
        m.maxTemperature = clampU16(maxTemp), m.maxTemperatureIndex = maxTempAt;
        m.minTemperature = clampU16(minTemp), m.minTemperatureIndex = minTempAt;
      }
      out = m.pack();
      return true;
    }
    case kTiCells: {
      // Top of stack first: slot 0 is the highest board. Skip boards that are not Valid.
      while (board_ < pack_.boards.size()) {
        const uint16_t b = static_cast<uint16_t>(pack_.boards.size() - 1 - board_);
        if (boardStatus(pack_.boards[b], now, staleAfter_) == BoardStatus::Valid) break;
        ++board_;
      }
      if (board_ >= pack_.boards.size()) {
        step_ = kDone;
        return false;
      }
      const uint16_t b = static_cast<uint16_t>(pack_.boards.size() - 1 - board_);
      const int16_t* raw = pack_.rawCells + b * kMaxCellsPerBoard;
      bms::TiCellVoltages m;
      for (uint8_t k = 0; k < 4; ++k)
        m.vCell[k] = raw[15 - (frame_ * 4 + k)];  // cells 16..1
      out = m.pack();
      return true;
    }
    case kDone:
      return false;
  }
  return false;
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
