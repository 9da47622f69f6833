// BQ4050 SMBus driver (contract in gauge.hpp).
//
// One engine runs every access. An access is described by its first transaction's bytes (buffers_->tx), how
// many bytes its read takes (state_->readLen, 0 for a write) and flags; a two-phase access (a MAC read)
// writes its command first and reads in a second transaction. issue() builds a transaction, onTransaction()
// checks what came back and either completes the access, asks for another transaction (the read phase of a
// MAC read, a confirming re-read), or hands the failure to fail(), which decides between a retry (after the
// pace, a back-off or a bus recovery) and giving up. Operations (probe, scan, FET control) chain accesses in
// accessDone(). Protocol sources:
//   SMBus 2.0 5.5.4-5.5.7: read/write word, block read/write, the repeated start before the read, and the PEC
//   over every byte including the address bytes (computed and checked by the bus, hal/i2c_bus.hpp);
//   SBS 1.1: the commands and SpecificationInfo's PEC flag;
//   SLUUAQ3A ManufacturerBlockAccess(): a block write of the little-endian subcommand to 0x44, then a block
//   read of 0x44 returning count + the subcommand echo + data; ManufacturerAccess(): a word write to 0x00,
//   whose result ManufacturerData() (0x23) returns "not including the MAC command".
#include "drivers/bq4050/gauge.hpp"

#include <bit>
#include <cstddef>
#include <cstring>

#include "core/assert.hpp"
#include "core/bytes.hpp"
#include "drivers/bq4050/limits.hpp"

FW_MODULE(::fw::Module::DriverBq4050);

namespace fw::drivers::bq4050 {

namespace {

namespace rm = regmap::bq4050;
namespace rb = rm::bits;
using Mfg = rb::ManufacturingStatus;

constexpr uint8_t kManufacturerAccess = regmap::code8(rm::sbs::ManufacturerAccess);  // 0x00
constexpr uint8_t kManufacturerData = regmap::code8(rm::sbs::ManufacturerData);      // 0x23
constexpr uint8_t kBlockAccess = regmap::code8(rm::sbs::ManufacturerBlockAccess);    // 0x44

// Access flags.
constexpr uint8_t kBlock = 0x01;     // the read is an SMBus block read (count first)
constexpr uint8_t kTwoPhase = 0x02;  // command write, then a separate read transaction
constexpr uint8_t kEcho = 0x04;      // the block starts with the 2-byte subcommand echo (0x44)
constexpr uint8_t kToggle = 0x08;    // resend only after an address NACK (MAC command)

// The scan: one entry per access, in order: the SBS words, the cells (CellVoltage1 is 0x3F, counting down),
// then three MAC status blocks (size 4). Averaged run times serve both directions: SBS has no instantaneous
// time to full, and the averages change least between the two reads that confirm a value without PEC.
struct ScanItem {
  uint8_t code;    // SBS command, or the MAC subcommand (all below 0x100)
  uint8_t offset;  // field of Measurement
  uint8_t size;    // 1, 2 (word) or 4 (MAC block)
};
constexpr ScanItem kScan[] = {
    {regmap::code8(rm::sbs::Voltage), offsetof(Measurement, voltageMv), 2},
    {regmap::code8(rm::sbs::Current), offsetof(Measurement, currentMa), 2},
    {regmap::code8(rm::sbs::Temperature), offsetof(Measurement, temperatureDeciK), 2},
    {regmap::code8(rm::sbs::RelativeStateOfCharge), offsetof(Measurement, rsocPercent), 1},
    {regmap::code8(rm::sbs::RemainingCapacity), offsetof(Measurement, remainingCapacity), 2},
    {regmap::code8(rm::sbs::FullChargeCapacity), offsetof(Measurement, fullChargeCapacity), 2},
    {regmap::code8(rm::sbs::AverageTimeToEmpty), offsetof(Measurement, timeToEmptyMin), 2},
    {regmap::code8(rm::sbs::AverageTimeToFull), offsetof(Measurement, timeToFullMin), 2},
    {regmap::code8(rm::sbs::BatteryStatus), offsetof(Measurement, batteryStatus), 2},
    {regmap::code8(rm::sbs::CellVoltage1), offsetof(Measurement, cellMv) + 0, 2},
    {regmap::code8(rm::sbs::CellVoltage2), offsetof(Measurement, cellMv) + 2, 2},
    {regmap::code8(rm::sbs::CellVoltage3), offsetof(Measurement, cellMv) + 4, 2},
    {regmap::code8(rm::sbs::CellVoltage4), offsetof(Measurement, cellMv) + 6, 2},
    {regmap::code8(rm::mac::SafetyStatus), offsetof(Measurement, safetyStatus), 4},
    {regmap::code8(rm::mac::PFStatus), offsetof(Measurement, pfStatus), 4},
    {regmap::code8(rm::mac::OperationStatus), offsetof(Measurement, operationStatus), 4},
};
constexpr uint8_t kFirstCell = 9;
static_assert(std::endian::native == std::endian::little, "scan fields are filled with the wire's LE bytes");
static_assert(std::is_standard_layout_v<Measurement> && std::is_trivially_copyable_v<Measurement>,
              "filled by offset and copied out as bytes");
constexpr uint8_t kScanSteps = sizeof(kScan) / sizeof(kScan[0]);

// FET toggles in the order they are tried (SLUUAQ3A MAC table): FET_EN first; then in test mode every FET
// that must go off before any that must go on, and DSG on before CHG (with DSG off and the pack above 16 V
// the BQ4050 sets the CHG flag without turning the FET on: TI E2E 1445117).
struct Toggle {
  uint8_t mask;  // ManufacturingStatus bit
  uint8_t code;  // MAC subcommand
  uint8_t when;  // kTurnOff, kTurnOn, or both
};
constexpr uint8_t kTurnOff = 1;
constexpr uint8_t kTurnOn = 2;
constexpr Toggle kToggles[] = {
    {Mfg::fet_en_mask, regmap::code8(rm::mac::FETControl), kTurnOff | kTurnOn},
    {Mfg::chg_test_mask, regmap::code8(rm::mac::ChgFet), kTurnOff},
    {Mfg::pchg_test_mask, regmap::code8(rm::mac::PchgFet), kTurnOff},
    {Mfg::dsg_test_mask, regmap::code8(rm::mac::DsgFet), kTurnOff},
    {Mfg::dsg_test_mask, regmap::code8(rm::mac::DsgFet), kTurnOn},
    {Mfg::chg_test_mask, regmap::code8(rm::mac::ChgFet), kTurnOn},
    {Mfg::pchg_test_mask, regmap::code8(rm::mac::PchgFet), kTurnOn},
};
constexpr uint8_t kMaxToggles = 8;        // four bits, each may need a resend after an ambiguous failure
static_assert(Mfg::fet_en_mask < 0x100);  // code8() already refuses MAC codes above 0xFF

}  // namespace

Gauge::Gauge(hal::I2cBus& bus, const hal::Clock& clock, const DriverContext& context,
             const GaugeConfig& config)
    : bus_(bus), clock_(clock), ctx_(context), config_(config), busDone_(context.busNotify()) {
  FW_ASSERT(config.cells >= 1 && config.cells <= kMaxCells);
  state_->pec = config.pec == PecMode::On;
  txn_.address = kAddress;
}

// --- operations --------------------------------------------------------------------------------------------

Status Gauge::begin(Op op) {
  if (busy()) return Status::Busy;
  state_->op = op;
  state_->step = 0;
  state_->done = false;
  return Status::Ok;
}

Status Gauge::startProbe(DeviceInfo& out) {
  const Status s = begin(Op::Probe);
  if (s != Status::Ok) return s;
  state_->out.info = &out;
  // With Auto, SpecificationInfo is read without PEC: until it says so, the gauge may not support it.
  if (config_.pec == PecMode::Auto) state_->pec = false;
  readWord(regmap::code8(rm::sbs::SpecificationInfo));
  return Status::Ok;
}

Status Gauge::startScan(Measurement& out) {
  const Status s = begin(Op::Scan);
  if (s != Status::Ok) return s;
  state_->out.measurement = &out;
  Measurement m;  // zero, then the two fields no access fills
  m.takenAt = clock_.now();
  m.cellCount = config_.cells;
  std::memcpy(buffers_->scan, &m, sizeof m);
  ++buffers_->stats.scans;
  nextScan();
  return Status::Ok;
}

Status Gauge::startReadWord(uint8_t cmd, uint16_t& out) {
  const Status s = begin(Op::Single);
  if (s != Status::Ok) return s;
  state_->out.word = &out;
  readWord(cmd);
  return Status::Ok;
}

Status Gauge::startWriteWord(uint8_t cmd, uint16_t value) {
  const Status s = begin(Op::Single);
  if (s != Status::Ok) return s;
  buffers_->tx[0] = cmd;
  bytes::storeLe16(buffers_->tx + 1, value);
  access(3, 0, 0);
  return Status::Ok;
}

Status Gauge::startWriteBlock(uint8_t cmd, std::span<const uint8_t> data) {
  if (busy()) return Status::Busy;
  if (data.empty() || data.size() > kMaxBlock) return Status::InvalidArgument;
  (void)begin(Op::Single);  // cannot fail: its only refusal (Busy) was checked above
  buffers_->tx[0] = cmd;
  buffers_->tx[1] = static_cast<uint8_t>(data.size());
  std::memcpy(buffers_->tx + 2, data.data(), data.size());
  access(static_cast<uint8_t>(2 + data.size()), 0, 0);
  return Status::Ok;
}

Status Gauge::startReadBlock(uint8_t cmd, std::span<uint8_t> out, uint8_t& length) {
  if (busy()) return Status::Busy;
  const uint8_t capacity = startRead(out, length);
  if (capacity == 0) return Status::InvalidArgument;
  buffers_->tx[0] = cmd;
  access(1, static_cast<uint8_t>(1 + capacity), kBlock);
  return Status::Ok;
}

Status Gauge::startReadMac(uint16_t subcommand, std::span<uint8_t> out, uint8_t& length) {
  if (busy()) return Status::Busy;
  const uint8_t capacity = startRead(out, length);
  if (capacity == 0) return Status::InvalidArgument;
  readMac(subcommand, capacity, 0);
  return Status::Ok;
}

Status Gauge::startReadMacData(uint16_t subcommand, std::span<uint8_t> out, uint8_t& length) {
  if (busy()) return Status::Busy;
  const uint8_t capacity = startRead(out, length);
  if (capacity == 0) return Status::InvalidArgument;
  state_->readCmd = kManufacturerData;
  macAccess(subcommand, static_cast<uint8_t>(1 + capacity), kBlock | kTwoPhase);
  return Status::Ok;
}

// The common start of the raw block reads: the read is sized from the caller's buffer (at most 32 data
// bytes), so a count the gauge reports beyond it is refused by the bus and nothing past `out` is written.
// Returns that capacity, or 0 (nothing started) for an empty buffer.
uint8_t Gauge::startRead(std::span<uint8_t> out, uint8_t& length) {
  if (out.empty()) return 0;
  (void)begin(Op::Single);  // cannot fail: every caller has checked busy(), its only refusal
  state_->out.block.bytes = out.data();
  state_->out.block.length = &length;
  return static_cast<uint8_t>(out.size() < kMaxBlock ? out.size() : kMaxBlock);
}

Status Gauge::startSendMac(uint16_t subcommand) {
  const Status s = begin(Op::Single);
  if (s != Status::Ok) return s;
  sendMac(subcommand);
  return Status::Ok;
}

Status Gauge::startFetControl(const FetRequest& request, FetState& out) {
  const Status s = begin(Op::Fet);
  if (s != Status::Ok) return s;
  state_->fetWant =
      static_cast<uint8_t>(request.firmwareControl ? Mfg::fet_en_mask
                                                   : (request.chg ? Mfg::chg_test_mask : 0) |
                                                         (request.dsg ? Mfg::dsg_test_mask : 0) |
                                                         (request.pchg ? Mfg::pchg_test_mask : 0));
  state_->out.fet = &out;
  state_->toggled = 0;
  readMac(regmap::code8(rm::mac::ManufacturingStatus), 2, 2);
  return Status::Ok;
}

// --- events ------------------------------------------------------------------------------------------------

Progress Gauge::onEvent(sched::EventMask events) {
  if ((events & ctx_.busEvent) != 0) {
    if (state_->busLost) {
      // The late completion of a transaction already given up: its buffers are free again.
      state_->busLost = false;
    } else if (state_->wait == Wait::Bus) {
      ctx_.scheduler.stopTimer(timer_);
      onTransaction();
    }
  }
  // A timer event counts only once the timer has expired: a stale one (the guard expiring as the bus
  // completed) finds the next wait's timer armed, or a due transaction to start, and does no harm.
  if ((events & ctx_.timerEvent) != 0 && !timer_.armed()) {
    if (state_->wait == Wait::Timer) {
      issue();
    } else if (state_->wait == Wait::Bus) {
      // The bus never reported back. Its transaction (and our buffers) may still be in use: stay busy until
      // the completion arrives, but end the operation now so the owner's wait is bounded.
      state_->busLost = true;
      countAndFinish(Status::Timeout);
    }
  }
  if (!state_->done) return Progress::Running;
  state_->done = false;
  return Progress::Done;
}

// --- the access engine -------------------------------------------------------------------------------------

void Gauge::access(uint8_t txLen, uint8_t readLen, uint8_t flags, uint16_t code, uint8_t exact) {
  state_->txLen = txLen;
  state_->readLen = readLen;
  state_->flags = flags;
  state_->code = code;
  state_->exact = exact;
  state_->phase = 0;
  state_->fails = 0;
  state_->candidate = false;
  schedule(config_.pace);
}

void Gauge::readWord(uint8_t command) {
  buffers_->tx[0] = command;
  access(1, 2, 0);
}

void Gauge::readMac(uint16_t subcommand, uint8_t capacity, uint8_t exact) {
  buffers_->tx[0] = kBlockAccess;
  buffers_->tx[1] = kMacEcho;
  bytes::storeLe16(buffers_->tx + 2, subcommand);
  state_->readCmd = kBlockAccess;
  access(4, static_cast<uint8_t>(1 + kMacEcho + capacity), kBlock | kTwoPhase | kEcho, subcommand, exact);
}

void Gauge::sendMac(uint16_t subcommand) {
  macAccess(subcommand, 0, kToggle);
}

// ManufacturerAccess: the subcommand written to 0x00 (a read then reads state_->readCmd). Inlined into its
// two callers, so sendMac (the path the images link) pays nothing for the read's parameters.
inline void Gauge::macAccess(uint16_t subcommand, uint8_t readLen, uint8_t flags) {
  buffers_->tx[0] = kManufacturerAccess;
  bytes::storeLe16(buffers_->tx + 1, subcommand);
  access(3, readLen, flags, subcommand);
}

// Starts the next transaction once the bus has been idle for `gap` (polling a TI gauge too fast
// can reset it: Zephyr issue #116889 on the bq274xx). Always goes through onEvent(), so a start*() call never
// completes an operation inside itself.
void Gauge::schedule(Duration gap) {
  state_->wait = Wait::Timer;
  const Instant now = clock_.now();
  const Instant due = state_->lastEnd + gap;
  if (!state_->busUsed || isDue(due, now)) {
    ctx_.scheduler.post(ctx_.task, ctx_.timerEvent);
  } else {
    ctx_.scheduler.startTimer(timer_, ctx_.task, ctx_.timerEvent, elapsed(now, due));
  }
}

void Gauge::issue() {
  const bool second = state_->phase != 0;
  // Address and status are the bus's business or fixed (constructor); the rest is set for every start.
  const bool read = second || (state_->flags & kTwoPhase) == 0;
  txn_.pec = state_->pec;
  txn_.write = second ? std::span<const uint8_t>{&state_->readCmd, 1}
                      : std::span<const uint8_t>{buffers_->tx, state_->txLen};
  txn_.read = {buffers_->rx[state_->cur], read ? state_->readLen : size_t{0}};
  txn_.blockRead = read && (state_->flags & kBlock) != 0;
  state_->wait = Wait::Bus;
  const Status s = bus_.start({&txn_, 1}, busDone_);
  if (s != Status::Ok) return fail(s, true);
  ctx_.scheduler.startTimer(timer_, ctx_.task, ctx_.timerEvent, config_.busGuard);
}

void Gauge::onTransaction() {
  state_->wait = Wait::None;
  ++buffers_->stats.transactions;
  state_->lastEnd = clock_.now();
  state_->busUsed = true;
  if (txn_.status != Status::Ok) return fail(txn_.status, true);
  if (state_->readLen == 0) return accessDone(Status::Ok);  // a write
  if (state_->phase == 0 && (state_->flags & kTwoPhase) != 0) {
    state_->phase = 1;  // the command is in: read its result
    return schedule(config_.pace);
  }

  const uint8_t* rx = buffers_->rx[state_->cur];
  size_t compare = 2;  // bytes two confirming reads must share
  if ((state_->flags & kBlock) == 0) {
    if (!plausibleWord(buffers_->tx[0], bytes::loadLe16(rx))) return fail(Status::Implausible, false);
  } else {
    // The count covers the echo; the echo must name the subcommand this access sent, or the gauge is
    // answering an earlier command (a write it dropped, a mode that streams other data).
    if ((state_->flags & kEcho) != 0) {
      if (rx[0] < kMacEcho) return fail(Status::Length, false);
      if (bytes::loadLe16(rx + 1) != state_->code) return fail(Status::EchoMismatch, false);
    }
    if (state_->exact != 0 && dataLength() != state_->exact) return fail(Status::Length, false);
    compare = 1 + rx[0];
  }
  if (!state_->pec) {
    // Without PEC nothing proves the bytes arrived as sent: publish only what two consecutive reads agree on
    // exactly. The gauge refreshes its values about once a second, so two reads a few milliseconds apart
    // rarely straddle a refresh, and when they do the next read confirms the new value.
    const uint8_t* prev = buffers_->rx[state_->cur ^ 1];
    bool same = state_->candidate;
    for (size_t i = 0; same && i < compare; ++i)
      same = prev[i] == rx[i];
    if (!same) {
      const bool disagreed = state_->candidate;
      state_->candidate = true;
      state_->cur ^= 1;
      if (disagreed) return fail(Status::VerifyFailed, false);
      return schedule(config_.pace);  // the confirming read (a MAC result is re-read without resending)
    }
  }
  accessDone(Status::Ok);
}

void Gauge::fail(Status status, bool transport) {
  ++buffers_->stats.failures[static_cast<uint8_t>(status)];
  // Most MAC commands are toggles: resent after an ambiguous failure one could undo itself. Only an address
  // NACK proves the gauge never saw it.
  const bool resendable = (state_->flags & kToggle) == 0 || status == Status::Nack;
  if (!resendable || ++state_->fails > config_.retries) return accessDone(status);
  ++buffers_->stats.retries;
  Duration gap = config_.pace;
  if (status == Status::Timeout) gap = config_.timeoutBackoff;  // the bus has already recovered itself
  if (status == Status::Nack) gap = config_.nackBackoff;
  if (status == Status::BusStuck || (transport && status != Status::Timeout && state_->fails >= 2)) {
    // A stuck line, or a second transport failure: the gauge may hold a half-finished transaction. Nine
    // clocks and a STOP return every SMBus target to idle (I2C UM10204 3.1.16, SMBus 2.0 4.3.3).
    ++buffers_->stats.recoveries;
    // A recovery that fails leaves the line stuck: the retry's access then fails again (BusStuck) and is
    // counted and retried like this one, so its status adds nothing here.
    (void)bus_.recover();
  }
  if (status != Status::VerifyFailed)
    state_->phase = 0;  // restart from the command; a disagreement only re-reads
  schedule(gap);
}

uint16_t Gauge::word() const {
  return bytes::loadLe16(buffers_->rx[state_->cur]);
}
const uint8_t* Gauge::data() const {
  return buffers_->rx[state_->cur] + ((state_->flags & kEcho) ? 1 + kMacEcho : 1);
}
uint8_t Gauge::dataLength() const {
  return static_cast<uint8_t>(buffers_->rx[state_->cur][0] - ((state_->flags & kEcho) ? kMacEcho : 0));
}

// --- what follows an access --------------------------------------------------------------------------------

void Gauge::accessDone(Status status) {
  if (state_->op == Op::Fet) return nextFet(status);
  if (status != Status::Ok) return finish(status);
  if (state_->op == Op::Single) {
    if (state_->readLen == 2 && (state_->flags & kBlock) == 0) {
      *state_->out.word = word();
    } else if (state_->readLen != 0) {
      // dataLength() fits the caller's buffer: the read was sized from it.
      std::memcpy(state_->out.block.bytes, data(), dataLength());
      *state_->out.block.length = dataLength();
    }
    return finish(Status::Ok);
  }
  if (state_->op == Op::Scan) {
    // The wire is little-endian like the targets' memory (asserted above): the bytes are the field.
    const ScanItem& item = kScan[state_->step];
    std::memcpy(buffers_->scan + item.offset, item.size == 4 ? data() : buffers_->rx[state_->cur], item.size);
    ++state_->step;
    return nextScan();
  }
  // Probe.
  if (state_->step == 0) {
    state_->probe[0] = word();  // SpecificationInfo
    if (config_.pec == PecMode::Auto)
      state_->pec = rb::SpecificationInfo::fromRaw(state_->probe[0]).version() == 3;
    ++state_->step;
    return readMac(regmap::code8(rm::mac::DeviceType), 2, 2);
  }
  if (state_->step == 1) {
    state_->probe[1] = bytes::loadLe16(data());
    if (state_->probe[1] != kDeviceType) return countAndFinish(Status::DeviceId);
    ++state_->step;
    return readMac(regmap::code8(rm::mac::FirmwareVersion), kMaxBlock, 0);
  }
  DeviceInfo& info = *state_->out.info;
  info = DeviceInfo{};
  info.specificationInfo = rb::SpecificationInfo::fromRaw(state_->probe[0]);
  info.deviceType = state_->probe[1];
  info.firmwareLength = dataLength() < kFirmwareBytes ? dataLength() : kFirmwareBytes;
  std::memcpy(info.firmware, data(), info.firmwareLength);
  info.pec = state_->pec;
  finish(Status::Ok);
}

void Gauge::nextScan() {
  if (state_->step == kFirstCell + config_.cells)
    state_->step = kFirstCell + kMaxCells;  // skip cells the pack lacks
  if (state_->step == kScanSteps) {
    // Every access validated: publish the record whole.
    std::memcpy(state_->out.measurement, buffers_->scan, sizeof(Measurement));
    ++buffers_->stats.published;
    return finish(Status::Ok);
  }
  const ScanItem& item = kScan[state_->step];
  if (item.size == 4) return readMac(item.code, 4, 4);
  readWord(item.code);
}

void Gauge::nextFet(Status status) {
  if ((state_->flags & kToggle) != 0) {
    // Whatever the toggle's fate, the state read back decides what comes next; only a gauge that never
    // acknowledged its address (after the retries) ends the operation.
    state_->toggled = status == Status::Ok ? state_->code : 0;
    if (status == Status::Nack) return finish(status);
    return readMac(regmap::code8(rm::mac::ManufacturingStatus), 2, 2);
  }
  if (status != Status::Ok) return finish(status);
  constexpr uint8_t kTestBits = Mfg::chg_test_mask | Mfg::dsg_test_mask | Mfg::pchg_test_mask;
  const uint8_t want = state_->fetWant;
  if (state_->code == regmap::code8(rm::mac::OperationStatus)) {
    // The FETs themselves, which must match a test-mode request (the flags alone can lie: E2E 1445117).
    const auto op = rb::OperationStatus::fromRaw(bytes::loadLe32(data()));
    const uint8_t actual =
        static_cast<uint8_t>((op.chg() ? Mfg::chg_test_mask : 0) | (op.dsg() ? Mfg::dsg_test_mask : 0) |
                             (op.pchg() ? Mfg::pchg_test_mask : 0));
    if ((want & Mfg::fet_en_mask) == 0 && actual != want) return countAndFinish(Status::VerifyFailed);
    FetState& out = *state_->out.fet;
    out.manufacturingStatus = Mfg::fromRaw(state_->probe[0]);
    out.operationStatus = op;
    return finish(Status::Ok);
  }

  // ManufacturingStatus: take the first toggle, in kToggles order, whose bit differs from the request.
  const uint16_t now = bytes::loadLe16(data());
  state_->probe[0] = now;
  const uint8_t relevant = (want & Mfg::fet_en_mask) != 0 ? Mfg::fet_en_mask : Mfg::fet_en_mask | kTestBits;
  const uint8_t differ = static_cast<uint8_t>((now ^ want) & relevant);
  uint8_t toggle = 0;
  for (const Toggle& t : kToggles) {
    if ((differ & t.mask) != 0 && (t.when & ((now & t.mask) != 0 ? kTurnOff : kTurnOn)) != 0) {
      toggle = t.code;
      break;
    }
  }
  if (toggle == 0) return readMac(regmap::code8(rm::mac::OperationStatus), 4, 4);
  // The same toggle again after it was accepted means the gauge ignored it (SEALED, or a FET it will not
  // drive); the step bound ends a gauge that keeps changing its mind.
  if (toggle == state_->toggled || ++state_->step > kMaxToggles) return countAndFinish(Status::VerifyFailed);
  sendMac(toggle);
}

// The operation fails with a status that no transaction reported (fail() counts those): counted here.
void Gauge::countAndFinish(Status status) {
  ++buffers_->stats.failures[static_cast<uint8_t>(status)];
  finish(status);
}

void Gauge::finish(Status status) {
  state_->result = status;
  state_->op = Op::None;
  state_->wait = Wait::None;
  state_->done = true;
}

}  // namespace fw::drivers::bq4050
