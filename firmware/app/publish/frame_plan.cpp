#include "app/publish/frame_plan.hpp"

#include <type_traits>

#include "app/balancing/balancing_status.hpp"
#include "app/version.hpp"  // generated: the CMake project version
#include "can/bms.hpp"

namespace fw::app {
namespace bms = fw::can::bms;

namespace {

// Readings are clamped to their signal's physical range, which stops one short of the not-available value
// (all ones for the unsigned signals, the most negative value for PackCurrent): a reading never looks
// missing, and a missing one never looks like a reading.
constexpr uint32_t kNotAvailable = 0xFFFFFFFFU;  // every unsigned signal's, once packStream() masks it
static_assert(bms::PackSummary::kPackVoltageNotAvailable == 0xFFFF &&
                  bms::PackSummary::kStateOfChargeNotAvailable == 0xFF &&
                  bms::PackSummary::kPackCurrentNotAvailable == INT16_MIN &&
                  bms::CellExtremes::kMaxCellVoltageNotAvailable == 0xFFFF &&
                  bms::CellExtremes::kMaxCellIndexNotAvailable == 0xFFFF &&
                  bms::CellExtremes::kMinCellVoltageNotAvailable == 0xFFFF &&
                  bms::CellExtremes::kMinCellIndexNotAvailable == 0xFFFF &&
                  bms::TemperatureExtremes::kMaxTemperatureNotAvailable == 0xFFFF &&
                  bms::TemperatureExtremes::kMinTemperatureNotAvailable == 0xFFFF &&
                  bms::TemperatureExtremes::kMaxTemperatureIndexNotAvailable == 0xFFFF &&
                  bms::TemperatureExtremes::kMinTemperatureIndexNotAvailable == 0xFFFF &&
                  bms::CellVoltages::kCellNotAvailable == 0xFFFF &&
                  bms::Temperatures::kTempNotAvailable == 0xFFFF,
              "bms.yaml's not-available values are the ones this plan sends");
static_assert(bms::CellVoltages::kCellTotal == kMaxCellsPerBoard &&
              bms::Temperatures::kTempTotal == kMaxTempsPerBoard);
static_assert(
    [] {
      for (size_t i = 0; i < 4; ++i) {
        const can::Field a = bms::CellExtremes::kFields[i], b = bms::TemperatureExtremes::kFields[i];
        if (a.start != b.start || a.length != b.length) return false;
      }
      return true;
    }(),
    "CellExtremes and TemperatureExtremes share one layout (fill() builds both alike)");
static_assert(bms::CellVoltages::kBoardField == bms::Temperatures::kBoardField &&
                  bms::CellVoltages::kFrameIndexField == bms::Temperatures::kFrameIndexField &&
                  bms::CellVoltages::kStatusField == bms::Temperatures::kStatusField &&
                  bms::CellVoltages::kCellField == bms::Temperatures::kTempField &&
                  bms::CellVoltages::kCellPerFrame == bms::Temperatures::kTempPerFrame,
              "CellVoltages and Temperatures share one layout (fill() builds both alike)");
constexpr uint8_t kOpenWireStatus =
    4;  // CellVoltages.Status: some cells of the frame are beside an open wire
uint16_t clampU16(int32_t v) {
  return static_cast<uint16_t>(v < 0 ? 0 : (v > 0xFFFE ? 0xFFFE : v));
}
// A 16-bit reading (mV, 0.1 K) never reaches the not-available value: only a negative one needs clamping.
inline uint32_t reading(int32_t v) {
  return static_cast<uint32_t>(v & ~(v >> 31));
}
int16_t clampI16(int32_t v) {
  return static_cast<int16_t>(v < -32767 ? -32767 : (v > 32767 ? 32767 : v));
}
// Frames of three items (cells or temperatures) per board: ceil(items / 3) as a multiply and shift
// (exact for items + 2 < 128; items <= kMaxCellsPerBoard), since ARMv6-M has no divide instruction.
constexpr uint16_t framesPerBoard(uint8_t items) {
  return static_cast<uint16_t>(((items + 2U) * 43U) >> 7);
}
static_assert(kMaxCellsPerBoard + 2 < 128 && kMaxTempsPerBoard <= kMaxCellsPerBoard);
// index / perBoard for the frame indexes of a step (below kMaxBoards * perBoard; perBoard = 1..6): a multiply
// by 2^15 / perBoard, rounded up, and a shift, exact over that range (checked below for every case).
constexpr uint16_t kReciprocal[] = {0, 32768, 16384, 10923, 8192, 6554, 5462};
constexpr uint16_t boardOf(uint16_t index, uint16_t perBoard) {
  return static_cast<uint16_t>((index * uint32_t{kReciprocal[perBoard]}) >> 15);
}
static_assert(framesPerBoard(kMaxCellsPerBoard) == 6 && framesPerBoard(kMaxTempsPerBoard) <= 6);
static_assert([] {
  for (uint16_t perBoard = 1; perBoard <= 6; ++perBoard)
    for (uint32_t index = 0; index < uint32_t{kMaxBoards} * perBoard; ++index)
      if (boardOf(static_cast<uint16_t>(index), perBoard) != index / perBoard) return false;
  return true;
}());
// x / 10, truncated toward zero as C division is, without a division: the quotient of |x| by shifts and
// adds (Hacker's Delight 10-17), corrected by the remainder.
constexpr int32_t divideBy10(int32_t x) {
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

// The messages of the steps (can/bms.hpp), indexed by Step: identifiers and one shared table of their
// fields' stream codes (can_bits.hpp: a byte a field), so a step costs 4 bytes of flash and no pointer. The
// TI message is left out where the layout is compiled out, and a message the build leaves out
// (FW_PUBLISH_LEVEL) keeps its identifier but no fields.
struct Message {
  uint16_t id;
  uint8_t first;  // index of its first field in Catalogue::fields
  uint8_t count;
};
template <class M>
struct Left {  // a message this build does not send
  static constexpr uint32_t kId = M::kId;
};
template <class M>
constexpr size_t fieldCount() {
  if constexpr (requires { M::kFields; }) {
    return sizeof M::kFields / sizeof(can::Field);
  } else {
    return 0;
  }
}
template <class... M>
struct Catalogue {
  static constexpr size_t kFieldCount = (fieldCount<M>() + ...);
  Message messages[sizeof...(M)];
  uint8_t fields[kFieldCount];  // stream codes
};
template <class... M>
constexpr Catalogue<M...> catalogue() {
  Catalogue<M...> c{};
  uint8_t m = 0;
  uint8_t f = 0;
  auto add = [&]<class T>(T*) {
    constexpr auto n = static_cast<uint8_t>(fieldCount<T>());
    c.messages[m++] = {static_cast<uint16_t>(T::kId), f, n};
    if constexpr (n != 0) {
      for (const uint8_t code : can::streamCodes<T>())
        c.fields[f++] = code;
    }
  };
  (add(static_cast<M*>(nullptr)), ...);
  return c;
}
template <class M, bool kSent>
using Sent = std::conditional_t<kSent, M, Left<M>>;
#if FW_STORAGE != 0
#define FW_STORAGE_MESSAGE , Sent<bms::StorageStatus, kAllMessages>
#else
#define FW_STORAGE_MESSAGE
#endif
#define FW_NATIVE_MESSAGES                                                                            \
  bms::PackSummary, Sent<bms::CellExtremes, kAllMessages>, Sent<bms::ProtectionEvent, kCoreMessages>, \
      bms::Startup, Sent<bms::CellVoltages, kCoreMessages>, Sent<bms::Temperatures, kAllMessages>,    \
      Sent<bms::TemperatureExtremes, kAllMessages>, Sent<bms::StateOfCharge, kAllMessages>,           \
      Sent<bms::BalancingStatus, kAllMessages> FW_STORAGE_MESSAGE
#if FW_CAN_TI_LAYOUT
constexpr auto kCatalogue = catalogue<FW_NATIVE_MESSAGES, bms::TiCellVoltages>();
#else
constexpr auto kCatalogue = catalogue<FW_NATIVE_MESSAGES>();
#endif
#undef FW_NATIVE_MESSAGES
#undef FW_STORAGE_MESSAGE
static_assert(
    [] {
      for (const Message& m : kCatalogue.messages)
        if (m.id == 0 || m.id >= 0x800) return false;  // fill() returns 0 for "no frame"
      return true;
    }(),
    "standard identifiers above 0");

constexpr uint8_t kMaxFields = bms::PackSummary::kFieldCount;  // the longest message
static_assert(bms::CellExtremes::kFieldCount <= kMaxFields &&
              bms::TemperatureExtremes::kFieldCount <= kMaxFields &&
              bms::ProtectionEvent::kFieldCount <= kMaxFields &&
              bms::CellVoltages::kFieldCount <= kMaxFields && bms::Temperatures::kFieldCount <= kMaxFields &&
              bms::BalancingStatus::kFieldCount <= kMaxFields &&
              bms::TiCellVoltages::kFieldCount <= kMaxFields && bms::Startup::kFieldCount <= kMaxFields &&
              bms::StateOfCharge::kFieldCount <= kMaxFields && bms::StorageStatus::kFieldCount <= kMaxFields);
static_assert(bms::StorageStatus::kMeasurementAgeNotAvailable == 0xFFFFFF);
// StateOfCharge's capacities go out unclamped: a pack file's capacity is at most 1 048 574 mAh (regmapgen
// pack), the remaining charge never above it, and the gauge's words are 16 bits; all below not available.
static_assert(bms::StateOfCharge::kRemainingCapacityNotAvailable == 0xFFFFF &&
              bms::StateOfCharge::kFullChargeCapacityNotAvailable == 0xFFFFF &&
              bms::StateOfCharge::kSocNotAvailable == 0xFFFF &&
              bms::StateOfCharge::kBasisNotAvailable == 0xF);
static_assert(bms::Startup::kFaultModuleNotAvailable == 0xFF &&
                  bms::Startup::kFaultLineNotAvailable == 0xFFFF &&
                  bms::Startup::kProtectionLogEntriesNotAvailable == KeptRecordsInfo::kNotAvailable &&
                  bms::Startup::kFaultSourceNotAvailable == static_cast<uint8_t>(FaultSource::NotAvailable),
              "a Startup field left unset goes out as not available");

}  // namespace

// A cycle walks steps in order, each with framesIn() frames:
//   fast part: summary, extremes, [event], [startup]; then the slow part if one is waiting (resume_)
//   slow part: cells (boards x frames per board), temperatures (likewise), temperature extremes, balancing
//              (one per board, where the pack balances)
//   ti:        boards x 4 frames, top of stack first
inline uint16_t FramePlan::framesIn(Step step) const {
  const uint16_t boards = pack_.boardCount();
  if (!sent(step)) return 0;
  switch (step) {
    case kStartup:
      return startupPending_;
    case kSummary:
    case kExtremes:
      return 1;
    case kEvent:
      return event_;
    case kCells:
    case kTemps:
      return static_cast<uint16_t>(
          boards * framesPerBoard(step == kCells ? pack_.cellsPerBoard : pack_.tempsPerBoard));
    case kTempExtremes:
      return pack_.tempsPerBoard != 0;
    case kStateOfCharge:
      return 1;
    case kBalancing:
      return pack_.balancing != nullptr ? boards : 0;
#if FW_STORAGE != 0
    case kStorage:  // only a monitor with a storage mode sets the period (storage_mode.hpp)
      return pack_.storage.period.us != 0;
#endif
    case kTiCells:
      return kTiLayout && pack_.rawCells != nullptr ? static_cast<uint16_t>(boards * 4) : 0;
    default:
      return 0;
  }
}

// Moves on from steps whose frames are all done (or that have none): after the fast part to the Startup
// frame (if announced) and then the slow part waiting (if any), after the slow part or a TI set to the end.
void FramePlan::settle() {
  if constexpr (!kCoreMessages && !kTiLayout) {  // PackSummary is the only message (and Startup once)
    if (index_ != 0) {
      step_ = step_ == kSummary && startupPending_ ? kStartup : kDone;
      index_ = 0;
    }
    return;
  }
  while (step_ != kDone && index_ >= framesIn(step_)) {
    index_ = 0;
    if (step_ == kStartup) {  // the end of the fast part (or the start of a TI set)
      if (kTiLayout && tiStartup_) {
        step_ = kTiCells;
        tiStartup_ = false;
      } else {
        step_ = resume_, index_ = resumeIndex_;
        resume_ = kDone;
      }
    } else {
      step_ = step_ == kLastSlow ? kDone : static_cast<Step>(step_ + 1);
    }
  }
}

bool FramePlan::begin(bool slow) {
  bool dropped = startFast();
  if (slow) {
    dropped = dropped || resume_ != kDone;  // the last second's slow part had not finished
    resume_ = kCells, resumeIndex_ = 0;
  }
  return dropped;
}

void FramePlan::beginTi() {
  if constexpr (!kTiLayout) return;
  if (active()) return;  // a set is going out: it finishes whole, and carries this scan's data from here on
  // Only after a scan (it has just ended) that validated every board and shows no open wire: those codes are
  // not cell voltages, and the layout cannot say so.
  if (!pack_.totals.complete) return;
  tiStartup_ = startupPending_;
  step_ = startupPending_ ? kStartup : kTiCells;
  index_ = 0;
  settle();
}

uint16_t FramePlan::fill(Instant now, std::array<uint8_t, 8>& data) {
  if (step_ == kDone) return 0;  // the end of every cycle: before the values are filled
  // Steps a build leaves out never come up (framesIn() gives them no frames); each case says so, which drops
  // its code. (Inside the switch, not before it: a test of sent(step_) ahead of the switch made GCC thread it
  // into a second copy of the dispatch, 80 B on the L1306 image.)
  // Each step fills the raw values of its message in field order (can/bms.hpp kFields); one call packs them,
  // so every message costs only its stores and all share one packing loop (with the command answers). A value
  // left unset goes out as not available.
  uint32_t v[kMaxFields];
  for (uint32_t& x : v)
    x = kNotAvailable;
  const PackTotals& t = pack_.totals;
  // Totals of the last scan go out only while that scan is fresh: never an old value as a current one.
  // Fresh: the age is no more than staleAfter_ (no borrow from staleAfter_ - age). Computed, not tested: GCC
  // threads a test of it (`elapsed(...) <= staleAfter_`) into a second copy of the dispatch below (measured
  // 2026-11-29: +80 B on L1306-BQ76952, +40 B on the other images).
  // In pack storage the scans are further apart: stale after as many of them (PackView::storage).
  const Duration staleAfter = staleAfter_ + pack_.storage.staleExtra;
  const auto fresh = static_cast<bool>(1U ^ ((uint64_t{staleAfter.us} - elapsed(t.takenAt, now).us) >> 63));
  const bool cells = fresh & (t.cells != 0);
  const bool temps = fresh & (t.temps != 0);
  switch (step_) {
    case kDone:
      return 0;
    case kStartup: {
      using U = bms::Startup;
      v[U::kResetCauseField] = startup_.resetCause;
      v[U::kFirmwareMajorField] = kFirmwareVersionMajor;
      v[U::kFirmwareMinorField] = kFirmwareVersionMinor;
      v[U::kFirmwarePatchField] = kFirmwareVersionPatch;
      if (startup_.faultValid) {
        v[U::kFaultModuleField] = startup_.faultModule;
        v[U::kFaultLineField] = startup_.faultLine;
      }
      if constexpr (FW_RECORD_STORE != 0) {  // without the store both stay not available
        v[U::kProtectionLogEntriesField] = startup_.kept.logEntries;
        v[U::kFaultSourceField] = static_cast<uint8_t>(startup_.kept.faultSource);
      }
      break;
    }
    case kSummary:
      // The pack voltage is the sum over every board, so only a scan that validated all of them gives it.
      {
        using S = bms::PackSummary;
        if (fresh && t.complete) v[S::kPackVoltageField] = clampU16(divideBy10(divideBy10(t.packMv + 50)));
        v[S::kPackCurrentField] = static_cast<uint16_t>(
            cells && pack_.hasCurrent ? clampI16(divideBy10(pack_.currentMa)) : S::kPackCurrentNotAvailable);
        // Whole %, rounded (the StateOfCharge message has it in 0.1 %).
        if (cells && pack_.soc.known()) v[S::kStateOfChargeField] = (pack_.soc.permille + 5U) / 10U;
        // The paths only as confirmed (publish_status.hpp); not available otherwise.
        if (status_.pathsKnown) {
          v[S::kChargeFetField] = status_.chargeOn;
          v[S::kDischargeFetField] = status_.dischargeOn;
        }
        v[S::kFaultOutputField] = status_.faultOutput;
        v[S::kDataValidField] = cells;
        v[S::kCounterField] = counter_;
        v[S::kActiveFaultsField] = status_.active;
        break;
      }
    case kExtremes:
    case kTempExtremes: {
      if (!sent(kExtremes)) return 0;  // sent together with TemperatureExtremes (FW_PUBLISH_LEVEL)
      // CellExtremes and TemperatureExtremes share their layout (highest, where, lowest, where), as
      // PackTotals keeps both pairs alike.
      const uint8_t e = step_ == kExtremes ? kMaxCell : kMaxTemp;
      if (step_ == kExtremes ? cells : temps) {
        using X = bms::CellExtremes;  // the temperature layout is the same (static_assert above)
        v[X::kMaxCellVoltageField] = reading(t.extreme[e]), v[X::kMaxCellIndexField] = t.at[e];
        v[X::kMinCellVoltageField] = reading(t.extreme[e + 1]), v[X::kMinCellIndexField] = t.at[e + 1];
      }
      break;
    }
    case kEvent: {
      if (!sent(kEvent)) return 0;
      using E = bms::ProtectionEvent;
      v[E::kActiveFaultsField] = status_.active;
      v[E::kNewlyTrippedField] = status_.pendingTripped;
      v[E::kNewlyClearedField] = status_.pendingCleared;
      v[E::kCommErrorsField] = pack_.commErrors;
      break;
    }
    case kCells:
    case kTemps: {
      if (!sent(step_)) return 0;
      // Board, frame index, status, then three slots of cells or temperatures: readings of a Valid board,
      // not available otherwise, and for slots with no reading (past the board's items, kNoReading, beside
      // an open wire).
      const bool isCells = step_ == kCells;
      const uint8_t items = isCells ? pack_.cellsPerBoard : pack_.tempsPerBoard;
      const uint16_t perBoard = framesPerBoard(items);
      // index = board * perBoard + frame, split by a multiply (boardOf()): ARMv6-M has no divide
      // instruction, and this is the only division the plan would need.
      const uint16_t board = kMaxBoards > 1 ? boardOf(index_, perBoard) : 0;
      const auto frame = static_cast<uint16_t>(index_ - board * perBoard);
      const BoardSample& s = pack_.boards[board];
      const int16_t* values = isCells ? s.cellMv : s.tempDeciK;
      using C = bms::CellVoltages;  // Temperatures: the same layout (static_assert above)
      auto status = static_cast<uint8_t>(boardStatus(s, now, staleAfter));
      if (status == static_cast<uint8_t>(BoardStatus::Valid)) {
        // The open-wire verdict of this frame's cells only (their neighbours decide it), not the whole
        // board's. Only after a scan whose totals show an open wire: summarize() walked every board that
        // validated (each Valid board among them) after the monitor wrote them, so without one no frame's
        // cells are beside one either (the walk per frame was 2 % of the 64-device BQ79616 image's busy
        // cycles, twin profile). A single-board build walks every time: the test cost it 44 B (L1306).
        const auto first = static_cast<uint8_t>(frame * C::kCellPerFrame);
        const bool walk = isCells && (kMaxBoards == 1 || t.openWire);
        const uint32_t open = walk ? openWireCells(s.cellMv, items, first, C::kCellPerFrame) : 0;
        if ((open & 7U) != 0) status = kOpenWireStatus;
        for (uint8_t j = 0, i = first; j < C::kCellPerFrame; ++j, ++i) {
          if (i < items && ((open >> j) & 1U) == 0 && values[i] != kNoReading)
            v[C::kCellField + j] = reading(values[i]);
        }
      }
      // Stored once, after the status is known (stored first, GCC copied these stores into every way
      // through boardStatus()).
      v[C::kBoardField] = board, v[C::kFrameIndexField] = frame, v[C::kStatusField] = status;
      break;
    }
    case kStateOfCharge: {
      if (!sent(kStateOfCharge)) return 0;
      // Sent as PackSummary's StateOfCharge: once known, while the scan behind it is fresh. Builds without
      // a state of charge (FW_SOC=0: known() is constant false) send it not available, for the price of its
      // identifier and fields.
      const SocView& soc = pack_.soc;
      if (cells && soc.known()) {
        using Q = bms::StateOfCharge;
        v[Q::kSocField] = soc.permille;
        v[Q::kRemainingCapacityField] = soc.remainingMah;
        v[Q::kFullChargeCapacityField] = soc.fullChargeMah;
        v[Q::kBasisField] = static_cast<uint8_t>(soc.basis);
      }
      break;
    }
    case kBalancing: {
      if (!sent(kBalancing)) return 0;
      // One frame per board: what its device confirmed and for how long, and the pack's mode and state.
      using B = bms::BalancingStatus;
      const BalancingStatus& b = *pack_.balancing;
      v[B::kBoardField] = index_;
      v[B::kModeField] = static_cast<uint8_t>(b.mode());
      v[B::kStateField] = static_cast<uint8_t>(b.state);
      v[B::kCellsField] = b.cells[index_];
      v[B::kTimeField] = b.seconds[index_] < 0xFFFFFFU ? b.seconds[index_] : 0xFFFFFFU;
      break;
    }
#if FW_STORAGE != 0
    case kStorage: {
      if (!sent(kStorage)) return 0;
      // The age at worst: since the oldest board's scan, plus the device's own interval while it may SLEEP
      // (PackView::storage); not available before any board validated.
      using G = bms::StorageStatus;
      const StorageView& st = pack_.storage;
      v[G::kModeField] = st.on;
      v[G::kDeviceSleepField] = st.deviceAge.us != 0;
      v[G::kScanPeriodField] = st.period.toMs();
      if (t.oldest.us != 0) {
        const uint32_t age = (elapsed(t.oldest, now) + st.deviceAge).toMs();
        v[G::kMeasurementAgeField] = age < 0xFFFFFEU ? age : 0xFFFFFEU;
      }
      break;
    }
#endif
    case kTiCells: {
      if constexpr (!kTiLayout) return 0;  // compiled out: framesIn() gives this step no frames
      // Top of stack first: slot 0 is the highest board. A board that stopped being Valid since the set
      // began ends the set (the layout cannot say so, and a receiver would give the next board's cells to
      // it).
      const auto b = static_cast<uint16_t>(pack_.boardCount() - 1 - index_ / 4);
      if (boardStatus(pack_.boards[b], now, staleAfter) != BoardStatus::Valid) {
        step_ = kDone;
        return 0;
      }
      const int16_t* raw = pack_.rawCells + b * kMaxCellsPerBoard + 15 - (index_ % 4) * 4;
      for (uint8_t j = 0; j < bms::TiCellVoltages::kVCellPerFrame; ++j)
        v[bms::TiCellVoltages::kVCellField + j] = static_cast<uint16_t>(raw[-j]);  // cells 16..1
      break;
    }
  }
  const Message& m = kCatalogue.messages[step_];
  can::packStream(data, &kCatalogue.fields[m.first], v, m.count);
  return m.id;
}

void FramePlan::advance() {
  // On a finished plan this only counts index_ up: settle() leaves kDone alone.
  if (step_ == kStartup) startupPending_ = false;
  if (sent(kEvent) && step_ == kEvent) {
    status_.pendingTripped = 0;
    status_.pendingCleared = 0;
  }
  ++index_;
  settle();
}

}  // namespace fw::app
