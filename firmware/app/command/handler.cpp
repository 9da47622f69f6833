#include "app/command/handler.hpp"

#include "app/command/identity.hpp"
#include "core/stats.hpp"

namespace fw::app::command {

namespace bms = can::bms;

namespace {

constexpr uint8_t kDlc[] = {bms::ClearFaults::kDlc,     bms::PathRequest::kDlc, bms::BalancingMode::kDlc,
                            bms::Identify::kDlc,        bms::SettingRead::kDlc, bms::SettingWrite::kDlc,
                            bms::EnterBootloader::kDlc, bms::StorageMode::kDlc};
static_assert(sizeof kDlc == kCommandCount, "one DLC per received message of bms.yaml");
// The commands' identifiers are consecutive, in catalogue order (ClearFaults .. StorageMode), so a
// command's index is its identifier's distance from the first.
constexpr bool consecutiveIds() {
  for (uint8_t i = 0; i < kCommandCount; ++i)
    if (bms::kReceivedIds[i] != bms::ClearFaults::kId + i) return false;
  return bms::kReceivedIds[kCommandCount - 1] == bms::StorageMode::kId;
}
static_assert(consecutiveIds(), "kReceivedIds: consecutive, ClearFaults .. StorageMode");
// Every command begins with the E2E header this handler reads: CRC in byte 0, counter in byte 1's low
// nibble, target in byte 2.
static_assert(bms::ClearFaults::kFields[bms::ClearFaults::kCrcField].start == 0 &&
              bms::ClearFaults::kFields[bms::ClearFaults::kCounterField].start == 8 &&
              bms::ClearFaults::kFields[bms::ClearFaults::kTargetField].start == 16);

constexpr uint8_t kBothPaths = static_cast<uint8_t>(Action::AllOff);
static_assert(bms::PathRequest::kFields[bms::PathRequest::kChargeOffField].start == 24 &&
              bms::PathRequest::kFields[bms::PathRequest::kDischargeOffField].start == 25 &&
              static_cast<uint8_t>(Action::ChargeOff) == 1 &&
              static_cast<uint8_t>(Action::DischargeOff) == 2);

// Every answer is a standard 8-byte frame (one SLCAN line each, slcan_link.cpp).
static_assert(bms::CommandAck::kDlc == 8 && bms::IdentifyVersion::kDlc == 8 && bms::IdentifyChip::kDlc == 8 &&
              bms::SettingValue::kDlc == 8 && bms::SettingRange::kDlc == 8);

// What differs between answer frames: every answer is a standard 8-byte frame (checked above), so only its
// identifier and payload layout (stream codes, can_bits.hpp). One constant per answer message, so a call
// passes one address.
struct AnswerLayout {
  uint16_t id;
  uint8_t count;
  uint8_t codes[6];  // the most fields an answer has (IdentifyVersion)
};
// The first kCount fields of M (every field after them goes out 0: packStream writes the whole payload).
template <class M, uint8_t kCount>
constexpr AnswerLayout layoutOf() {
  static_assert(kCount <= sizeof AnswerLayout::codes && !M::kExtended && M::kDlc == 8);
  AnswerLayout l{M::kId, kCount, {}};
  const auto codes = can::streamCodes<M>();
  for (uint8_t i = 0; i < kCount; ++i)
    l.codes[i] = codes[i];
  return l;
}
template <class M, uint8_t kCount>
constexpr AnswerLayout kAnswerLayout = layoutOf<M, kCount>();

// One out-of-line copy for every answer, packed by the loop that packs the published frames.
void answerFrame(hal::CanFrame& f, const AnswerLayout& layout, const uint32_t* raw) {
  f.id = layout.id;
  f.extended = false;
  f.dlc = 8;
  can::packStream(f.data, layout.codes, raw, layout.count);  // every byte of the payload
}

// Field `kField` of a received command M, read straight from its bytes. Every field a command carries is
// little-endian and either whole bytes or within one byte (checked here against the generated layout), so it
// needs no bit-by-bit walk of the generated unpack() (can::get).
template <class M, uint8_t kField>
uint32_t field(const hal::CanFrame& f) {
  constexpr can::Field kAt = M::kFields[kField];
  constexpr uint8_t kByte = kAt.start / 8, kShift = kAt.start % 8;
  static_assert(!kAt.bigEndian && (kShift + kAt.length <= 8 || (kShift == 0 && kAt.length % 8 == 0)));
  if constexpr (kShift + kAt.length <= 8) {
    return (f.data[kByte] >> kShift) & ((1U << kAt.length) - 1);
  } else {
    uint32_t value = 0;
    for (uint8_t i = kAt.length / 8; i-- > 0;)
      value = value << 8 | f.data[kByte + i];
    return value;
  }
}

// Answer frame `f` of message M from its raw values in the order of M's signals: all of them, or the first
// kCount where the ones after them are 0 in this build.
template <class M, uint8_t kCount = M::kFieldCount, class... Values>
void packAnswer(hal::CanFrame& f, Values... values) {
  static_assert(sizeof...(Values) == kCount);
  const uint32_t raw[] = {static_cast<uint32_t>(values)...};
  answerFrame(f, kAnswerLayout<M, kCount>, raw);
}

}  // namespace

// The acknowledgement, always the first answer (slot 0; a command's data follows it when accepted). The
// caller has counted the answers: 1, or more when an accepted command's data follows.
void CommandHandler::ack(Replies& out, uint32_t id, uint8_t counter, Result result) {
  State& st = *state_;
  if (result != Result::Accepted) {
    if (st.stats.rejected != 0xFFFF) ++st.stats.rejected;
    if (kStats) ++st.stats.rejectedFor[static_cast<uint8_t>(result)];
  } else if (kStats) {
    ++st.stats.accepted;
  }
  packAnswer<bms::CommandAck>(out.frame[0], ctx_.node, id, counter, result, st.stats.rejected);
}

void CommandHandler::handle(const hal::CanFrame& f, Replies& out) {
  State& st = *state_;
  if (kStats) ++st.stats.frames;
  const uint32_t index = f.id - bms::ClearFaults::kId;  // wraps to a large value below the first
  if (f.extended || index >= kCommandCount) {
    if (kStats) ++st.stats.filtered;
    return;
  }
  const uint8_t counter = counterOf(f);
  // The target is byte 2: a frame too short to carry it is answered (it may well be meant for this node).
  if (f.dlc > 2 && f.data[2] != ctx_.node && f.data[2] != kBroadcast) {
    if (kStats) ++st.stats.otherTarget;
    return;
  }
  Result r = Result::Accepted;
  out.count = 1;  // slot 0: the acknowledgement
  if (f.dlc != kDlc[index]) {
    r = Result::WrongLength;
  } else if (!crcValid(f)) {
    r = Result::BadCrc;
  } else if (!st.counters.take(static_cast<uint8_t>(index), counter)) {
    r = Result::RepeatedCounter;
  } else if (st.boot != Boot::Idle) {
    r = Result::Busy;
  } else {
    r = act(f, out);
    if (r == Result::Accepted && st.boot != Boot::Idle) {  // answered once the paths are off
      out.count = 0;
      return;
    }
  }
  ack(out, f.id, counter, r);
}

Result CommandHandler::act(const hal::CanFrame& f, Replies& out) {
  State& st = *state_;
  switch (f.id) {
    case bms::ClearFaults::kId:  // what is gone clears now; what is still there stays, and the answer says so
      return ctx_.protection.clearLatched() ? Result::Accepted : Result::ConditionPresent;
    case bms::PathRequest::kId:  // ChargeOff and DischargeOff are bits 0 and 1 of byte 3, as in Action
      st.hostRequest = f.data[3] & kBothPaths;
      applyHostOff();
      return Result::Accepted;
    case bms::BalancingMode::kId: {
      using M = bms::BalancingMode;
      const uint32_t mode = field<M, M::kModeField>(f);
      if (mode > static_cast<uint8_t>(BalancingMode::Forced)) return Result::OutOfRange;
      if (balancing_ == nullptr)
        return Result::Unsupported;  // this image does not balance (the BQ4050's gauge does)
      // A board the pack does not have or a mask the device does not allow: InvalidArgument, nothing changes.
      const Status s = balancing_->setMode(static_cast<BalancingMode>(mode),
                                           static_cast<uint8_t>(field<M, M::kBoardField>(f)),
                                           static_cast<uint16_t>(field<M, M::kCellMaskField>(f)),
                                           static_cast<uint16_t>(pack_->boards.size()), pack_->cellsPerBoard);
      return s == Status::Ok ? Result::Accepted : Result::OutOfRange;
    }
    case bms::Identify::kId: {
      packAnswer<bms::IdentifyVersion>(out.frame[1], ctx_.node, kVersion.major, kVersion.minor,
                                       kVersion.patch, kBuildId, kImage);
      const hal::ChipIdentity chip = ctx_.system.identity();
      packAnswer<bms::IdentifyChip>(out.frame[2], ctx_.node, chip.resetCause, chip.traceId, chip.partNumber);
      out.count = 3;
      return Result::Accepted;
    }
    case bms::SettingRead::kId: {
      const auto id = static_cast<uint8_t>(field<bms::SettingRead, bms::SettingRead::kSettingField>(f));
      if (id >= kSettingCount) return Result::OutOfRange;
      const SettingSpec s = ctx_.settings.spec(id);
      using V = bms::SettingValue;
      if constexpr (kKeptSettings)
        packAnswer<V>(out.frame[1], ctx_.node, id, s.unit, ctx_.settings.read(id), ctx_.settings.source(id));
      else  // no record store: Source, the last field, is always 0 (default) and costs nothing
        packAnswer<V, V::kSourceField>(out.frame[1], ctx_.node, id, s.unit, ctx_.settings.read(id));
      static_assert(V::kSourceField == V::kFieldCount - 1);
      packAnswer<bms::SettingRange>(out.frame[2], ctx_.node, id, s.min, s.max);
      out.count = 3;
      return Result::Accepted;
    }
    case bms::SettingWrite::kId: {
      using M = bms::SettingWrite;
      return ctx_.settings.write(static_cast<uint8_t>(field<M, M::kSettingField>(f)),
                                 static_cast<int32_t>(field<M, M::kValueField>(f)));
    }
#if FW_STORAGE != 0
    case bms::StorageMode::kId: {
      using M = bms::StorageMode;
      const uint32_t mode = field<M, M::kModeField>(f);
      if (mode > 1) return Result::OutOfRange;
      if (storage_ == nullptr) return Result::Unsupported;
      // Entering is refused while a fault is active or current flows (storage_mode.hpp); leaving never is.
      constexpr Result kAnswer[] = {Result::Accepted, Result::Unsupported, Result::FaultActive,
                                    Result::NotAtRest};
      return kAnswer[static_cast<uint8_t>(storage_->request(mode == 1))];
    }
#endif
    default: {  // EnterBootloader (and StorageMode where the build has no storage: FW_STORAGE,
                // app/config.hpp)
      if (FW_STORAGE == 0 && f.id == bms::StorageMode::kId) return Result::Unsupported;
      using M = bms::EnterBootloader;
      if (field<M, M::kTargetField>(f) != ctx_.node || field<M, M::kKeyField>(f) != kBootloaderKey ||
          field<M, M::kTraceIdField>(f) != ctx_.system.identity().traceId)
        return Result::WrongKey;
      st.boot = Boot::WaitingForPaths;
      st.bootCounter = counterOf(f);
      st.bootDeadline = ctx_.scheduler.now() + kBootTimeout;
      ctx_.scheduler.startTimer(st.bootTimer, kCommandTask, command_event::kTimer, kPoll, kPoll);
      applyHostOff();
      return Result::Accepted;
    }
  }
}

void CommandHandler::applyHostOff() {
  const uint8_t off =
      static_cast<uint8_t>(state_->hostRequest | (state_->boot != Boot::Idle ? kBothPaths : 0));
  ctx_.protection.requestOff(off);
  ctx_.scheduler.post(ctx_.protection.id(), ProtectionTask::kHostRequest);
}

void CommandHandler::poll(Replies& out) {
  State& st = *state_;
  if (st.boot != Boot::WaitingForPaths) return;
  Result r = Result::Accepted;
  if (ctx_.protection.pathsOffConfirmed()) {
    st.boot = Boot::Answered;
  } else if (isDue(st.bootDeadline, ctx_.scheduler.now())) {
    r = Result::PathsNotOff;  // the deadline has passed: release what entry held off
    st.boot = Boot::Idle;
    ctx_.scheduler.stopTimer(st.bootTimer);
    applyHostOff();
  } else {
    return;
  }
  out.count = 1;
  ack(out, bms::EnterBootloader::kId, st.bootCounter, r);
}

void CommandHandler::answerSent() {
  if (state_->boot == Boot::Answered) ctx_.system.enterBootloader();
}

}  // namespace fw::app::command
