#include "app/frame_plan.hpp"

#include "can/bms.hpp"

namespace fw::app {
namespace bms = fw::can::bms;

namespace {

[[gnu::noinline]] uint16_t clampU16(int32_t v) {
  return static_cast<uint16_t>(v < 0 ? 0 : (v > 0xFFFF ? 0xFFFF : v));
}
int16_t clampI16(int32_t v) {
  return static_cast<int16_t>(v < -32768 ? -32768 : (v > 32767 ? 32767 : v));
}
// Frames of three items (cells or temperatures) per board: ceil(items / 3) as a multiply and shift
// (exact for items + 2 < 128; items <= kMaxCellsPerBoard), since ARMv6-M has no divide instruction.
constexpr uint16_t framesPerBoard(uint8_t items) {
  return static_cast<uint16_t>(((items + 2U) * 43U) >> 7);
}
static_assert(kMaxCellsPerBoard + 2 < 128 && kMaxTempsPerBoard <= kMaxCellsPerBoard);
// x / 10, truncated toward zero as C division is, without a division: the quotient of |x| by shifts and
// adds (Hacker's Delight 10-17), corrected by the remainder.
[[gnu::noinline]] constexpr int32_t divideBy10(int32_t x) {
  const uint32_t n = x < 0 ? 0U - static_cast<uint32_t>(x) : static_cast<uint32_t>(x);
  uint32_t q = (n >> 1) + (n >> 2);
  q += q >> 4;
  q += q >> 8;
  q += q >> 16;
  q >>= 3;
  q += (n - q * 10U) > 9U;
  return x < 0 ? -static_cast<int32_t>(q) : static_cast<int32_t>(q);
}
static_assert([] {
  for (int32_t x : {0, 9, 10, 19, 99, 12345, 5000005, 2147483647, -1, -9, -10, -40000, -2147483647})
    if (divideBy10(x) != x / 10) return false;
  for (uint8_t items = 0; items <= kMaxCellsPerBoard; ++items)
    if (framesPerBoard(items) != (items + 2) / 3) return false;
  return true;
}());

// The messages of the steps (can/bms.hpp), indexed by Step: identifiers and one shared field table, so a
// step costs 4 bytes of flash and no pointer. The TI message is left out where the layout is compiled out.
struct Message {
  uint16_t id;
  uint8_t first;  // index of its first field in Catalogue::fields
  uint8_t count;
};
template <class... M>
struct Catalogue {
  static constexpr size_t kFieldCount = ((sizeof M::kFields / sizeof(can::Field)) + ...);
  Message messages[sizeof...(M)];
  can::Field fields[kFieldCount];
};
template <class... M>
constexpr Catalogue<M...> catalogue() {
  Catalogue<M...> c{};
  uint8_t m = 0;
  uint8_t f = 0;
  auto add = [&](uint32_t id, const auto& fields) {
    const auto n = static_cast<uint8_t>(sizeof fields / sizeof fields[0]);
    c.messages[m++] = {static_cast<uint16_t>(id), f, n};
    for (uint8_t i = 0; i < n; ++i)
      c.fields[f++] = fields[i];
  };
  (add(M::kId, M::kFields), ...);
  return c;
}
#define FW_NATIVE_MESSAGES                                                                         \
  bms::PackSummary, bms::CellExtremes, bms::ProtectionEvent, bms::CellVoltages, bms::Temperatures, \
      bms::TemperatureExtremes
#if FW_CAN_TI_LAYOUT
constexpr auto kCatalogue = catalogue<FW_NATIVE_MESSAGES, bms::TiCellVoltages>();
#else
constexpr auto kCatalogue = catalogue<FW_NATIVE_MESSAGES>();
// Without the TI layout the packer only needs little-endian fields (can_bits.hpp): every native one is.
static_assert([] {
  for (const can::Field& f : kCatalogue.fields)
    if (f.bigEndian) return false;
  return true;
}());
#endif
#undef FW_NATIVE_MESSAGES
static_assert(bms::PackSummary::kId < 0x800 && bms::TiCellVoltages::kId < 0x800, "standard identifiers");
constexpr uint8_t kMaxFields = 9;  // the longest message (PackSummary)
static_assert(sizeof bms::PackSummary::kFields / sizeof(can::Field) == kMaxFields);

}  // namespace

// A cycle is the steps Summary .. TiCells in order, each with framesIn() frames:
//   fast: summary, extremes, [event]
//   slow: the same, then cells (boards x frames per board), temperatures (likewise), temperature extremes
//   ti:   boards x 4 frames, top of stack first
inline uint16_t FramePlan::framesIn(Step step) const {
  const uint16_t boards = pack_.boardCount();
  if (kind_ == kTi) {
    return kTiLayout && step == kTiCells && pack_.rawCells != nullptr ? static_cast<uint16_t>(boards * 4) : 0;
  }
  switch (step) {
    case kSummary:
    case kExtremes:
      return 1;
    case kEvent:
      return event_;
    case kCells:
    case kTemps:
      return kind_ == kSlow
                 ? static_cast<uint16_t>(
                       boards * framesPerBoard(step == kCells ? pack_.cellsPerBoard : pack_.tempsPerBoard))
                 : 0;
    case kTempExtremes:
      return kind_ == kSlow && pack_.tempsPerBoard != 0;
    default:
      return 0;
  }
}

// Moves on from steps whose frames are all done (or that have none).
void FramePlan::settle() {
  while (step_ != kDone && index_ >= framesIn(step_)) {
    step_ = static_cast<Step>(step_ + 1);
    index_ = 0;
  }
}

void FramePlan::begin(Kind kind) {
  kind_ = kind;
  event_ = kind != kTi && (status_.pendingTripped | status_.pendingCleared) != 0;
  step_ = kSummary;
  index_ = 0;
  settle();
}

bool FramePlan::build(Instant now, hal::CanFrame& out) {
  // Each step fills the raw values of its message in field order (can/bms.hpp kFields); one call packs them,
  // so every message costs only its stores and all share one packing loop.
  uint32_t v[kMaxFields] = {};
  const PackTotals& t = pack_.totals;
  // Totals of the last scan go out only while that scan is fresh: never an old value as a current one.
  const bool fresh = elapsed(t.takenAt, now) <= staleAfter_;
  const bool cells = fresh && t.cells;
  const bool temps = fresh && t.temps;
  switch (step_) {
    case kDone:
      return false;
    case kSummary:
      if (cells) {
        v[0] = clampU16(divideBy10(t.packMv + 5));
        v[1] = static_cast<uint16_t>(pack_.hasCurrent ? clampI16(divideBy10(pack_.currentMa)) : 0);
        v[6] = 1;  // DataValid
      }
      v[2] = cells ? pack_.stateOfCharge : 255;
      v[3] = status_.chargeOn;
      v[4] = status_.dischargeOn;
      v[5] = status_.faultOutput;
      v[7] = counter_ & 0xFU;
      v[8] = status_.active;
      break;
    case kExtremes:
      if (cells) {
        v[0] = clampU16(t.extreme[kMaxCell]), v[1] = t.at[kMaxCell];
        v[2] = clampU16(t.extreme[kMinCell]), v[3] = t.at[kMinCell];
      }
      break;
    case kTempExtremes:
      if (temps) {
        v[0] = clampU16(t.extreme[kMaxTemp]), v[1] = clampU16(t.extreme[kMinTemp]);
        v[2] = t.at[kMaxTemp], v[3] = t.at[kMinTemp];
      }
      break;
    case kEvent:
      v[0] = status_.active, v[1] = status_.pendingTripped, v[2] = status_.pendingCleared;
      v[3] = status_.commErrors;
      break;
    case kCells:
    case kTemps: {
      // Board, frame index, status, then three slots of cells or temperatures (zero unless Valid).
      const bool isCells = step_ == kCells;
      const uint8_t items = isCells ? pack_.cellsPerBoard : pack_.tempsPerBoard;
      const uint16_t perBoard = framesPerBoard(items);
      // index = board * perBoard + frame, split by subtraction (at most one step per board): ARMv6-M has no
      // divide instruction, and this is the only division the plan would need.
      uint16_t board = 0;
      uint16_t frame = index_;
      if constexpr (kMaxBoards > 1) {
        for (; frame >= perBoard; frame = static_cast<uint16_t>(frame - perBoard))
          ++board;
      }
      const BoardSample& s = pack_.boards[board];
      const BoardStatus st = boardStatus(s, now, staleAfter_);
      const int16_t* values = isCells ? s.cellMv : s.tempDeciK;
      v[0] = board, v[1] = frame, v[2] = static_cast<uint8_t>(st);
      for (uint8_t j = 0, i = static_cast<uint8_t>(frame * 3); j < 3; ++j, ++i) {
        if (st == BoardStatus::Valid && i < items) v[3 + j] = clampU16(values[i]);
      }
      break;
    }
    case kTiCells: {
      if constexpr (!kTiLayout) return false;  // compiled out: framesIn() gives this step no frames
      // Top of stack first: slot 0 is the highest board. A board that is not Valid is left out (the layout
      // has no status field to say so): its four frames are skipped.
      for (;;) {
        const auto slot = static_cast<uint16_t>(index_ / 4);
        const auto b = static_cast<uint16_t>(pack_.boardCount() - 1 - slot);
        if (boardStatus(pack_.boards[b], now, staleAfter_) == BoardStatus::Valid) {
          const int16_t* raw = pack_.rawCells + b * kMaxCellsPerBoard + 15 - (index_ % 4) * 4;
          for (uint8_t j = 0; j < 4; ++j)
            v[j] = static_cast<uint16_t>(raw[-j]);  // cells 16..1
          break;
        }
        index_ = static_cast<uint16_t>((slot + 1) * 4);
        settle();
        if (step_ == kDone) return false;
      }
      break;
    }
  }
  const Message& m = kCatalogue.messages[step_];
  out.id = m.id;
  out.extended = false;
  out.dlc = 8;
  can::pack(out.data, &kCatalogue.fields[m.first], v, m.count);  // writes all 8 bytes
  return true;
}

void FramePlan::advance() {
  if (step_ == kDone) return;
  if (step_ == kSummary) ++counter_;  // PackSummary's rolling counter counts summaries sent
  if (step_ == kEvent) {
    status_.pendingTripped = 0;
    status_.pendingCleared = 0;
  }
  ++index_;
  settle();
}

}  // namespace fw::app
