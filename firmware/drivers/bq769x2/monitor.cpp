#include "drivers/bq769x2/monitor.hpp"

#include <cstring>

#include "core/bytes.hpp"

namespace fw::drivers::bq769x2 {

FW_MODULE(Module::DriverBq769x2);

namespace {

namespace sub = map::sub;

constexpr uint8_t kBatteryStatus = regmap::code8(map::cmd::BatteryStatus);
static_assert(kBatteryStatus == regmap::code8(map7690x::cmd::BatteryStatus));
static_assert(regmap::code16(sub::DeviceNumber) == regmap::code16(map7690x::sub::DeviceNumber) &&
              regmap::code16(sub::FwVersion) == regmap::code16(map7690x::sub::FwVersion) &&
              regmap::code16(sub::SetCfgupdate) == regmap::code16(map7690x::sub::SetCfgupdate) &&
              regmap::code16(sub::ExitCfgupdate) == regmap::code16(map7690x::sub::ExitCfgupdate) &&
              regmap::code16(sub::FetEnable) == regmap::code16(map7690x::sub::FetEnable) &&
              regmap::code16(sub::CbActiveCells) == regmap::code16(map7690x::sub::CbActiveCells));

static_assert(regmap::code16(sub::SleepDisable) == regmap::code16(map7690x::sub::SleepDisable) &&
              regmap::code16(sub::SleepEnable) == regmap::code16(map7690x::sub::SleepEnable));

// BQ769x2 FET_CONTROL (SLUUCW9, E2E 1453973): a 1 forces that FET off, a 0 allows it, all four at once.
using Fc = map::bits::FetControl;
constexpr uint8_t kChargeOff = Fc::pchg_off_mask | Fc::chg_off_mask;
constexpr uint8_t kDischargeOff = Fc::pdsg_off_mask | Fc::dsg_off_mask;
// BQ7690x FET Control (SLUUCJ0): the same meaning, one bit per FET. The host's intent is kept in these
// bits for both families (Monitor::kChargePathOff / kDischargePathOff, monitor.hpp).
using Fc7 = map7690x::bits::FetControl;
static_assert(Monitor::kChargePathOff == Fc7::chg_off_mask &&
              Monitor::kDischargePathOff == Fc7::dsg_off_mask);

constexpr uint8_t kAlarmStatus = regmap::code8(map::cmd::AlarmStatus);
constexpr uint8_t kAlarmEnable = regmap::code8(map::cmd::AlarmEnable);
static_assert(kAlarmStatus == regmap::code8(map7690x::cmd::AlarmStatus) &&
              kAlarmEnable == regmap::code8(map7690x::cmd::AlarmEnable));

// The status of a transfer a step function starts, which it does not need: the steps run from the link's
// completion (the link is idle: never Busy) and ask for lengths from the variant's and the settings table
// (1..4 bytes), which fit the link's buffers (never InvalidArgument), so the link cannot refuse them.
constexpr void next(Status started) {
  (void)started;
}

}  // namespace

Status Monitor::begin(Op op, Status started) {
  if (started == Status::Ok) {
    state_->op = op;
    state_->step = 0;
  }
  return started;
}

Status Monitor::startProbe(Identity& out) {
  if (busy()) return Status::Busy;
  state_->out.identity = &out;
  state_->restarted = false;
  if (kProbeCrc && probeCrc_) link_.setCrc(false);
  return begin(Op::Probe, link_.startSubcommandRead(regmap::code16(sub::DeviceNumber), 2));
}

Status Monitor::startConfigure(SettingsTable settings) {
  if (!kConfigPaths || settings.bytes().empty()) return Status::InvalidArgument;
  if (busy()) return Status::Busy;
  state_->settings = settings;
  for (uint8_t& d : state_->diff)
    d = 0;
  state_->index = 0;
  state_->at = 0;
  state_->written = 0;
  state_->error = Status::Ok;
  return begin(Op::Configure, nextSetting(false));
}

// Scan steps: the variant's blocks (0..3; every other scan writes the charge request first, at step 0:
// State::requesting), the charge read (the scans between), the Alarm Status clear.
constexpr uint8_t kScanBlocks = sizeof(Variant::blocks) / sizeof(ScanBlock);
constexpr uint8_t kScanCharge = kScanBlocks;
constexpr uint8_t kScanClear = kScanBlocks + 1;

Status Monitor::startScan(Instant* measurement, uint8_t bytes, ChargeCounter* charge, bool askCharge) {
  if (busy()) return Status::Busy;
  // A build for one family checks the record size at compile time (the front ends).
  if constexpr (kFamily == 0) FW_ASSERT(scanBytes(variant_) <= bytes);
  state_->out.record = measurement;
  state_->charge = charge;
  // The charge alternates between scans: one writes the request, the next reads its result (the request is
  // long done by then), so no scan carries both (the BQ76952 scan's budget of 6 transactions).
  if constexpr (kCharge) {
    state_->readCharge = askCharge && state_->chargeRequested;
    state_->requestCharge = askCharge && !state_->chargeRequested;
    state_->chargeRequested = false;
  }
  state_->restarted = false;
  state_->yield = false;
  state_->scanRetries = link_.stats().retries;
  return begin(Op::Scan, startScanFromTop());
}

// The scan's first transaction, also when it starts over: the charge request when this scan makes one (the
// first block's read follows it), else the first block's read.
Status Monitor::startScanFromTop() {
  state_->bytes = 0;
  state_->step = 0;  // startScanRead() reads it (begin() sets it too, after the start)
  state_->index = 0;
  state_->requesting = kCharge && state_->requestCharge;
  if (!state_->requesting) return startScanRead();
  const Status s = link_.startSubcommand(facts().chargeCode, false);
  state_->chargeAsked = clock_.now();
  return s;
}

Status Monitor::startFet(FetCommand command) {
  if (busy()) return Status::Busy;
  // Each command is the whole state of both paths (DischargeOff: charge allowed, discharge off); a value
  // outside the enum turns nothing off, as AllOn.
  constexpr uint8_t kPathsOff[] = {0, kBothPathsOff, kDischargePathOff, kChargePathOff};
  const auto c = static_cast<uint8_t>(command);
  state_->pendingOff = c < sizeof kPathsOff ? kPathsOff[c] : 0;
  return begin(Op::Fet, sendFet());
}

Status Monitor::startFetEnable() {
  if (busy()) return Status::Busy;
  return begin(Op::FetEnable, readFetEn());
}

Status Monitor::startRuntimeSetup(SettingsTable settings) {
  if (busy()) return Status::Busy;
  state_->settings = settings;
#if FW_BQ769X_SLEEP
  state_->sleepAllowed = state_->sleepOnly = false;
#endif
  return begin(Op::RuntimeSetup, link_.startSubcommand(regmap::code16(sub::SleepDisable)));
}

// The runtime set-up's first two steps alone, either way (SLUUBY2B 7.3, SLUUCI8 "SLEEP Mode").
Status Monitor::startSleep([[maybe_unused]] bool allow) {
#if FW_BQ769X_SLEEP
  if (busy()) return Status::Busy;
  state_->sleepAllowed = allow;
  state_->sleepOnly = true;
  return begin(Op::RuntimeSetup, link_.startSubcommand(allow ? regmap::code16(sub::SleepEnable)
                                                             : regmap::code16(sub::SleepDisable)));
#else
  return Status::InvalidArgument;
#endif
}

Status Monitor::startBalance(uint16_t cells) {
  const bool adjacent = facts().cbAdjacent || allowAdjacent_;
  if (!kBalance || (cells >> variant().cells) != 0 || (!adjacent && (cells & (cells >> 1)) != 0))
    return Status::InvalidArgument;
  if (busy()) return Status::Busy;
  state_->yield = false;
  state_->cbWritten = static_cast<uint16_t>(cells << facts().cbShift);
  uint8_t mask[2];
  bytes::storeLe16(mask, state_->cbWritten);
  return begin(Op::Balance,
               link_.startSubcommandWrite(regmap::code16(sub::CbActiveCells), {mask, facts().cbBytes}));
}

Status Monitor::startBalanceCheck() {
  if (!kBalance) return Status::InvalidArgument;
  if (busy()) return Status::Busy;
  // 0x3E..0x61: the echo, the 32-byte buffer, the checksum and the length, in one read.
  return begin(Op::BalanceCheck, link_.startRead(kCmdSubcommand, 2 + kWindowBytes));
}

Progress Monitor::onEvent(sched::EventMask events) {
  const bool running = busy();
  if (link_.onEvent(events) == Progress::Done && busy()) step(link_.result());
  return running && !busy() ? Progress::Done : Progress::Running;
}

Status Monitor::readStatus() {
  return link_.startRead(kBatteryStatus, 2, 0, link_.pollInterval());
}

Status Monitor::readFetEn() {
  if (facts().fetEnCode != 0) return link_.startSubcommandRead(facts().fetEnCode, 2);
  return link_.startRead(kBatteryStatus, 2);
}

Status Monitor::sendFet() {
  // Written from the intent alone (never from what the FETs report).
  const uint8_t off = state_->pendingOff;
  if (facts().fetControlCmd != 0)
    return link_.startWrite(facts().fetControlCmd, {&off, 1});  // FET Control's bits
  // BQ769x2: both paths the same way is one command-only subcommand (ALL_FETS_OFF is the ALERT fast path);
  // one path off is FET_CONTROL, which also re-allows the other path after ALL_FETS_OFF.
  if (off == 0) return link_.startSubcommand(regmap::code16(sub::AllFetsOn));
  if (off == kBothPathsOff) return link_.startSubcommand(regmap::code16(sub::AllFetsOff));
  const uint8_t value = off == kChargePathOff ? kChargeOff : kDischargeOff;
  return link_.startSubcommandWrite(regmap::code16(sub::FetControl), {&value, 1});
}

void Monitor::step(Status r) {
  switch (state_->op) {
    case Op::Idle:
      return;
    case Op::Probe:
      return probeStep(r);
    case Op::Configure:
      if constexpr (kConfigPaths) configStep(r);
      return;
    case Op::Scan:
      return scanStep(r);
    case Op::Fet:
      return fetStep(r);
    case Op::FetEnable:
      return fetEnableStep(r);
    case Op::RuntimeSetup:
      return runtimeSetupStep(r);
    case Op::Balance:
      if constexpr (kBalance) balanceStep(r);
      return;
    case Op::BalanceCheck:
      if constexpr (kBalance) balanceCheckStep(r);
      return;
  }
}

inline void Monitor::probeStep(Status r) {
  if (r != Status::Ok) {
    // The first attempt of a CRC probe was made without CRC; a device in CRC mode refuses it at its first
    // missing CRC byte (DataNack), a stale or misframed answer shows as one of the others.
    const bool framing = r == Status::DataNack || r == Status::Crc || r == Status::Checksum ||
                         r == Status::Length || r == Status::EchoMismatch;
    if (!kProbeCrc || !probeCrc_ || state_->step != 0 || state_->restarted || !framing) return finish(r);
    state_->restarted = true;
    link_.setCrc(!link_.crc());
    return next(link_.startSubcommandRead(regmap::code16(sub::DeviceNumber), 2));
  }
  const uint8_t* d = link_.data();
  if (state_->step++ == 0) {
    state_->tmp = bytes::loadLe16(d);
    return next(link_.startSubcommandRead(regmap::code16(sub::FwVersion), 6));
  }
  Identity& id = *state_->out.identity;
  id.deviceNumber = state_->tmp;
  std::memcpy(id.fw, d, sizeof id.fw);
  id.crc = link_.crc();
  finish(Status::Ok);
}

// The part of the scan's current block (state_->step) that the next read takes, from state_->index bytes
// into it: at most kScanReadBytes (kScanReadBytesCrc with CRC, whose wire carries two bytes per byte).
// Bounding each read bounds how long a FET command waits for the read in progress (yieldScan()): the
// BQ76952's 50-byte cell block in one read is 1.2 ms of wire at 400 kHz, which with the command and its echo
// poll (0.84 ms) overran the 2 ms ALERT-to-FETs-off budget when ALERT came as that read started. A block is
// the device's consecutive direct commands (auto-increment, E2E 1560065), so its parts are reads at
// cmd + offset; offsets stay even, so no 16-bit value is split between two reads.
Status Monitor::startScanRead() {
  const ScanBlock& b = facts().blocks[state_->step];
  const uint8_t limit = link_.crc() ? kScanReadBytesCrc : kScanReadBytes;
  const uint8_t rest = static_cast<uint8_t>(b.len - state_->index);
  state_->tmp = rest < limit ? rest : limit;  // this read's length
  return link_.startRead(static_cast<uint8_t>(b.cmd + state_->index), static_cast<uint8_t>(state_->tmp),
                         state_->bytes);
}

inline void Monitor::scanStep(Status r) {
  if (r != Status::Ok) return finish(r);
  if (state_->step == kScanClear) return publish();
  if (state_->yield) return finish(Status::Aborted);  // a read never stops half-way: it ends on a boundary
  const Variant& v = facts();
  if (kCharge && state_->requesting) {
    state_->requesting = false;
    state_->chargeRequested = true;  // the next scan reads it
    return next(startScanRead());
  }
  if (state_->step == kScanCharge) return scanEnd();
  state_->bytes = static_cast<uint8_t>(state_->bytes + state_->tmp);
  state_->index = static_cast<uint8_t>(state_->index + state_->tmp);
  if (state_->index == v.blocks[state_->step].len) {
    state_->index = 0;
    ++state_->step;
  }
  if (state_->step < sizeof v.blocks / sizeof v.blocks[0]) return next(startScanRead());
  if (link_.stats().retries != state_->scanRetries && !state_->restarted) {
    // A read of this scan had to be repeated: the device may have reset or the bus glitched between
    // reads, so the snapshot is taken again from its first read (once), the charge asked for again.
    state_->restarted = true;
    return next(startScanFromTop());
  }
  const uint8_t* raw = link_.scratch();
  for (uint8_t i = 0; i < v.checkCount; ++i) {
    if ((raw[v.checks[i].offset] & v.checks[i].mask) != 0) return finish(Status::Implausible);
  }
  if (kCharge && state_->readCharge) {
    // The charge the previous scan asked for, no earlier than the variant's wait after the request.
    state_->step = kScanCharge;
    const Duration since = elapsed(state_->chargeAsked, clock_.now());
    const Duration wait = us(v.chargeWaitUs) > since ? us(v.chargeWaitUs) - since : Duration{};
    return next(link_.startRead(kCmdSubcommand, kChargeReadBytes, state_->bytes, wait));
  }
  scanEnd();
}

// After the blocks (and the charge read): Alarm Status is latched and 1s written to the bits read clear them
// (SLUUBY2B / SLUUCJ0 "Alarm Status"), so ALERT releases and the next event asserts it again. A write does
// not touch the scratch buffer.
void Monitor::scanEnd() {
  const uint8_t* alarm = link_.scratch() + facts().alarmOffset;
  if ((alarm[0] | alarm[1]) != 0) {
    state_->step = kScanClear;
    return next(link_.startWrite(kAlarmStatus, {alarm, 2}));
  }
  publish();
}

void Monitor::publish() {
  // The record is the time stamp followed by the registers (the front ends check the layout).
  Instant* record = state_->out.record;
  std::memcpy(record + 1, link_.scratch(), state_->bytes);
  if (kCharge) {
    // The charge read's echo (0x3E/0x3F) names the subcommand once its result is in 0x40.. (FF FF while it
    // runs): only then are the bytes after it the result.
    const uint8_t* d = link_.scratch() + state_->bytes;
    ChargeCounter& c = *state_->charge;
    c.valid = state_->readCharge && bytes::loadLe16(d) == facts().chargeCode;
    if (c.valid) std::memcpy(c.raw, d + 2, kChargeBytes);
  }
  *record = clock_.now();
  finish(Status::Ok);
}

inline void Monitor::fetStep(Status r) {
  if (r == Status::Ok) state_->intentOff = state_->pendingOff;
  finish(r);
}

inline void Monitor::fetEnableStep(Status r) {
  if (r != Status::Ok) return finish(r);
  const bool enabled = (link_.data()[facts().fetEnByte] & facts().fetEnMask) != 0;
  switch (state_->step++) {
    case 0:  // FET_EN read: FET_ENABLE toggles it, so it is only sent when FET_EN is 0
      if (enabled) return finish(Status::Ok);
      return next(link_.startSubcommand(regmap::code16(sub::FetEnable)));
    case 1:  // FET_ENABLE sent: read FET_EN back
      return next(readFetEn());
    default:
      return finish(enabled ? Status::Ok : Status::VerifyFailed);
  }
}

[[gnu::always_inline]] inline void Monitor::runtimeSetupStep(Status r) {
  if (r != Status::Ok) return finish(r);
  const uint8_t* d = link_.data();
  const uint8_t step = state_->step++;
  // Step 0: SLEEP_DISABLE (SLEEP_ENABLE) has run (echo); its effect shows in Battery Status[SLEEP_EN]
  // (SLUUBY2B 7.3).
  if (step == 0) return next(link_.startRead(kBatteryStatus, 2));
#if FW_BQ769X_SLEEP
  if (step == 1) {
    if (((d[0] & facts().sleepEnMask) != 0) != state_->sleepAllowed) return finish(Status::VerifyFailed);
    if (state_->sleepOnly) return finish(Status::Ok);
  }
#else
  if (step == 1 && (d[0] & facts().sleepEnMask) != 0) return finish(Status::VerifyFailed);
#endif
  // Alarm Enable from the table: a table only exists where the configuration paths are built.
  if constexpr (kConfigPaths) {
    if (step == 2) return next(link_.startRead(kAlarmEnable, 2));  // written: read it back
    if (step == 3) return finish(bytes::loadLe16(d) == state_->tmp ? Status::Ok : Status::VerifyFailed);
    const std::span<const uint8_t> t = state_->settings.bytes();
    for (size_t at = 0; at < t.size(); at += kSettingHeader + t[at]) {
      const uint8_t* r = &t[at];
      if (bytes::loadLe16(r + 1) != facts().alarmMaskAddress) continue;
      state_->tmp = static_cast<uint16_t>(r[kSettingHeader] | (r[0] > 1 ? r[kSettingHeader + 1] << 8 : 0));
      uint8_t mask[2];
      bytes::storeLe16(mask, state_->tmp);
      return next(link_.startWrite(kAlarmEnable, mask));
    }
  }
  finish(Status::Ok);
}

inline void Monitor::balanceStep(Status r) {
  if (r != Status::Ok || state_->step++ != 0) return finish(r);
  // Written (with checksum and length). The read-back request: CB_ACTIVE_CELLS as a command-only subcommand,
  // whose result startBalanceCheck() fetches later; a FET command waiting goes first instead.
  if (state_->yield) return finish(Status::Aborted);
  next(link_.startSubcommand(regmap::code16(sub::CbActiveCells), false));
}

// The window as a subcommand read fetches it (link.cpp): echo, then length 4..36 covering the mask, then the
// checksum over the code and every reported buffer byte.
inline void Monitor::balanceCheckStep(Status r) {
  if (r != Status::Ok) return finish(r);
  const uint8_t* d = link_.data();
  const uint16_t code = regmap::code16(sub::CbActiveCells);
  if (bytes::loadLe16(d) != code) return finish(Status::EchoMismatch);
  const uint8_t cbBytes = facts().cbBytes;
  const uint8_t length = d[2 + kBufferBytes + 1];
  if (length < 4 + cbBytes || length > kBufferBytes + 4) return finish(Status::Length);
  if (transferChecksum(code, d + 2, length - 4U) != d[2 + kBufferBytes]) return finish(Status::Checksum);
  const auto read = static_cast<uint16_t>(d[2] | (cbBytes > 1 ? d[3] << 8 : 0));
  state_->cbRead = static_cast<uint16_t>(read >> facts().cbShift);
  finish(read == state_->cbWritten ? Status::Ok : Status::VerifyFailed);
}

// Steps of the CONFIG_UPDATE transaction.
enum : uint8_t { kCompare, kEnter, kEnterPoll, kWrite, kVerify, kExit, kExitPoll };

bool Monitor::matches() const {
  const uint8_t* r = row();
  const uint8_t* d = link_.data();
  for (uint8_t i = 0; i < r[0]; ++i) {
    if (d[i] != r[kSettingHeader + i]) return false;
  }
  return true;
}

// The current row's read, or its write: the value straight from the table.
Status Monitor::nextSetting(bool write) {
  const uint8_t* r = row();
  const uint16_t address = bytes::loadLe16(r + 1);
  if (!write) return link_.startSubcommandRead(address, r[0]);
  return link_.startSubcommandWrite(address, {r + kSettingHeader, r[0]});
}

void Monitor::nextRow() {
  state_->at = static_cast<uint16_t>(state_->at + kSettingHeader + row()[0]);
  ++state_->index;
}

inline void Monitor::configStep(Status r) {
  if (r != Status::Ok) {
    if (state_->step == kCompare) return finish(r);  // nothing was changed yet
    if (state_->step < kExit) {
      // Never leave the device in CONFIG_UPDATE (its protections and FETs are stopped there).
      state_->error = r;
      return exitUpdate();
    }
    return finish(state_->error != Status::Ok ? state_->error : r);
  }
  const bool flag = (link_.data()[0] & facts().cfgUpdateMask) != 0;
  switch (state_->step) {
    case kCompare:
      if (!matches()) state_->diff[state_->index >> 3] |= static_cast<uint8_t>(1U << (state_->index & 7));
      nextRow();
      if (state_->at < state_->settings.bytes().size()) return next(nextSetting(false));
      if (!differs()) return finish(Status::Ok);
      state_->step = kEnter;
      return next(link_.startSubcommand(regmap::code16(sub::SetCfgupdate)));
    case kEnter:
    case kExit:
      // The command was accepted; its effect shows in Battery Status[CFGUPDATE] (LibreSolar 73bda94: the
      // TRM's timing alone was not enough).
      state_->polls = 0;
      ++state_->step;
      return next(readStatus());
    case kEnterPoll:
      if (!flag) return pollStatus();
      state_->index = 0;
      state_->at = 0;
      return writeNext();
    case kWrite:
      ++state_->written;
      state_->step = kVerify;
      return next(nextSetting(false));
    case kVerify:
      if (!matches()) {
        state_->error = Status::VerifyFailed;
        return exitUpdate();
      }
      nextRow();
      return writeNext();
    default:  // kExitPoll
      if (flag) return pollStatus();
      return finish(state_->error);
  }
}

void Monitor::pollStatus() {
  if (++state_->polls < cfgPolls_) return next(readStatus());
  if (state_->error == Status::Ok) state_->error = Status::Timeout;
  if (state_->step == kEnterPoll) return exitUpdate();
  finish(state_->error);
}

bool Monitor::differs() const {
  uint8_t any = 0;
  for (uint8_t d : state_->diff)
    any |= d;
  return any != 0;
}

void Monitor::writeNext() {
  while (state_->at < state_->settings.bytes().size() &&
         (state_->diff[state_->index >> 3] & (1U << (state_->index & 7))) == 0)
    nextRow();
  if (state_->at == state_->settings.bytes().size()) return exitUpdate();
  state_->step = kWrite;
  next(nextSetting(true));
}

void Monitor::exitUpdate() {
  state_->step = kExit;
  next(link_.startSubcommand(regmap::code16(sub::ExitCfgupdate)));
}

void Monitor::finish(Status s) {
  state_->result = s;
  state_->op = Op::Idle;
}

}  // namespace fw::drivers::bq769x2
