#include "app/store/persistence.hpp"

#include <array>
#include <cstring>

#include "core/assert.hpp"
#include "hal/irq.hpp"

namespace fw::app::store {

namespace {

constexpr uint8_t type(RecordType t) {
  return static_cast<uint8_t>(t);
}

}  // namespace

template <class Record>
bool Persistence::read(RecordType t, Record& r) const {
  std::array<uint8_t, Record::kBytes> b;
  uint32_t length = 0;
  return store_.read(type(t), b, length) == Status::Ok &&
         decode(std::span<const uint8_t>(b.data(), length), r);
}

// The settings written by command before the reset, each limit checked as a write is (settings.hpp); the
// state of charge, for restoredSoc() and as the value the next one is compared with. Apart from start(): its
// 128 B of record and bytes are off the stack before start() writes the fault record (the deepest path).
[[gnu::noinline]] void Persistence::restoreSettingsAndSoc() {
  SettingsRecord settings;
  if (read(RecordType::Settings, settings)) state_->settingsRefused = settings_.restore(settings.value);
  state_->settingsSeen = settings_.changes();
  SocRecord soc;
  if (read(RecordType::StateOfCharge, soc)) {
    state_->socKept = true;
    state_->socStored = soc.permille;
  }
}

void Persistence::start(StartupInfo& info) {
  info.kept.logEntries = 0;
  info.kept.faultSource = FaultSource::None;
  state_->last = store_.restore();
  if (state_->last != Status::Ok) {  // a region of fewer than two sectors: nothing kept, nothing said
    info.kept.logEntries = KeptRecordsInfo::kNotAvailable;
    info.kept.faultSource = FaultSource::NotAvailable;
    return;
  }
  restoreSettingsAndSoc();
  uint32_t length = 0;
  if (store_.read(type(RecordType::ProtectionLog), state_->log, length) == Status::Ok &&
      length == ProtectionLogRecord::kBytes && state_->log[0] <= ProtectionLogRecord::kEntries)
    info.kept.logEntries = state_->log[0];
  else
    state_->log = {};  // none, or another format version's: start a new one

  // The fault of this reset (recorded in SRAM by the previous run, or the watchdog's own), written to flash;
  // else the newest one an earlier run kept.
  FaultRecord fault{info.resetCause, info.faultLine, 0, 0, info.faultModule};
  FaultSource source = FaultSource::LastReset;
  if (!info.faultValid) {
    if (info.resetCause == kResetCauseWatchdog)
      fault = {info.resetCause, kWatchdogCode, 0, 0, static_cast<uint8_t>(fw::Module::Bsp)};
    else if (read(RecordType::Fault, fault))
      source = FaultSource::Stored;
    else
      return;
  }
  info.faultValid = true;
  info.faultModule = fault.module;
  info.faultLine = fault.code;
  info.kept.faultSource = source;
  if (source == FaultSource::Stored) return;
  std::array<uint8_t, FaultRecord::kBytes> b;
  encode(fault, b);
  state_->last = store_.write(type(RecordType::Fault), b);
  if (state_->last == Status::Busy && (state_->last = store_.eraseStep()) == Status::Ok)
    state_->last = store_.write(type(RecordType::Fault), b);
}

void Persistence::evaluated(FaultMask newlyTripped, bool settled, Instant now) {
  const uint32_t s = uptimeS(now);
  for (uint8_t i = 0; newlyTripped != 0; ++i, newlyTripped >>= 1)
    if ((newlyTripped & 1U) != 0) addTrip(static_cast<FaultId>(i), s);
  State& st = *state_;
  if (settings_.changes() != st.settingsSeen) {  // a command's write took effect at this scan
    st.settingsSeen = settings_.changes();
    st.settingsDirty = true;
  }
  if (socMoved(s - st.socStoredAtS >= kSocMaxAgeS ? 1 : kSocStep)) st.socDirty = true;
  if (settled && !st.posted && hasWork()) repost();
}

// Whether the published state of charge is a counted one (the gauge keeps its own) at least `step` from the
// stored one (any, when none is stored). Restored moves nothing until the count does.
bool Persistence::socMoved(uint16_t step) const {
  if (!kSoc || !pack_.soc.known() || pack_.soc.basis == SocBasis::Gauge) return false;
  const uint16_t now = pack_.soc.permille, kept = state_->socStored;
  return !state_->socKept || (now > kept ? now - kept : kept - now) >= step;
}

Persistence::Job Persistence::nextJob() const {
  const State& st = *state_;
  return st.logDirty ? Job::Log : st.settingsDirty ? Job::Settings : st.socDirty ? Job::Soc : Job::None;
}

Status Persistence::write(Job job) {
  std::array<uint8_t, SettingsRecord::kBytes> b;  // the longest record
  std::span<const uint8_t> payload = state_->log;
  RecordType t = RecordType::ProtectionLog;
  if (job == Job::Settings) {
    SettingsRecord r;
    for (uint8_t id = 0; id < command::kSettingCount; ++id)
      r.value[id] = settings_.read(id);
    encode(r, b);
    payload = b;
    t = RecordType::Settings;
  } else if (job == Job::Soc) {
    const auto soc = std::span<uint8_t, SocRecord::kBytes>(b.data(), SocRecord::kBytes);
    encode(SocRecord{pack_.soc.permille, pack_.soc.remainingMah}, soc);
    payload = soc;
    t = RecordType::StateOfCharge;
  }
  return store_.write(type(t), payload);
}

// The job is over, written or failed: a failed write is not retried (the flash's status stays in
// lastStatus()); the next trip, settings change or state-of-charge step writes again. So a failing flash
// costs one job an event, never a loop (the state of charge counts as stored either way, or every scan would
// try again).
void Persistence::done(Job job) {
  State& st = *state_;
  if (job == Job::Log) st.logDirty = false;
  if (job == Job::Settings) st.settingsDirty = false;
  if (job == Job::Soc) {
    st.socDirty = false;
    st.socKept = true;
    st.socStored = pack_.soc.permille;
    st.socStoredAtS = st.seconds;
  }
}

void Persistence::step() {
  // Masked for the whole job: between two word programs the CPU runs the store's code from flash, where an
  // interrupt would run the fault line's handler, whose protection task then waits for this task to return
  // (up to a compaction's 81 programs). Held pending instead, the edge is seen by the flash driver's wait at
  // the next program or erase (bsp/mspm0/flashctl.hpp), which drives the fast path's pins.
  const hal::CriticalSection masked;
  State& st = *state_;
  st.posted = false;
  if (const Job job = nextJob(); job != Job::None) {
    // Busy: a compaction is due and no sector is erased yet; erase one now and write in the next step.
    if ((st.last = write(job)) == Status::Busy && (st.last = store_.eraseStep()) == Status::Ok)
      return repost();
    done(job);
  } else if (store_.needsErase()) {
    st.last = store_.eraseStep();
  }
}

void Persistence::beforeReset() {
  if (socMoved(1)) state_->socDirty = true;
  // The steps the lowest task would run, now: at most three jobs, each a write or an erase and the write
  // (the step's own post is harmless: the reset comes first).
  for (uint8_t n = 0; n < 6 && nextJob() != Job::None; ++n)
    step();
}

bool Persistence::restoredSoc(uint16_t& permille) const {
  permille = state_->socStored;
  return state_->socKept;
}

// The log waits for its write: the next step, after everything else that is ready.
void Persistence::repost() {
  state_->posted = true;
  scheduler_.post(kCommandTask, command_event::kStore);
}

ProtectionLogRecord Persistence::log() const {
  ProtectionLogRecord r;
  decode(state_->log, r);
  return r;
}

// Appends `id` to the log, dropping the oldest entry when full, with the value that tripped it: the ones
// Protection::evaluate compares (protection.cpp), read back from the pack view it evaluated.
void Persistence::addTrip(FaultId id, uint32_t uptimeS) {
  using Log = ProtectionLogRecord;
  uint8_t* log = state_->log.data();  // byte 0: the count
  if (log[0] == Log::kEntries) {
    std::memmove(log + Log::entryOffset(0), log + Log::entryOffset(1),
                 (Log::kEntries - 1) * Log::kEntryBytes);
    --log[0];
  }
  const PackTotals& t = pack_.totals;
  int32_t value = 0;
  switch (id) {
    case FaultId::CellOvervoltage:
      value = t.extreme[kMaxCell];
      break;
    case FaultId::CellUndervoltage:
      value = t.extreme[kMinCell];
      break;
    case FaultId::ChargeOvercurrent:
    case FaultId::DischargeOvercurrent:
      value = pack_.currentMa;
      break;
    case FaultId::OvertempDischarge:
    case FaultId::OvertempCharge:
      value = t.extreme[kMaxTemp];
      break;
    case FaultId::UndertempDischarge:
    case FaultId::UndertempCharge:
      value = t.extreme[kMinTemp];
      break;
    case FaultId::DeviceSafety:
      value = pack_.deviceBlocks;
      break;
    default:
      break;  // the rules of counts and time: the record's rule says it all
  }
  encode(Log::Entry{static_cast<uint8_t>(id), uptimeS, value},
         std::span<uint8_t, Log::kEntryBytes>(log + Log::entryOffset(log[0]++), Log::kEntryBytes));
  state_->logDirty = true;
}

// Seconds since start-up from the evaluations' instants (the microsecond clock wraps every 71.6 minutes;
// the protection task evaluates at least every check period, so no gap spans a wrap).
uint32_t Persistence::uptimeS(Instant now) {
  state_->subUs += now.us - state_->lastEvaluation.us;
  state_->lastEvaluation = now;
  while (state_->subUs >= 1'000'000U) {
    state_->subUs -= 1'000'000U;
    ++state_->seconds;
  }
  return state_->seconds;
}

}  // namespace fw::app::store
