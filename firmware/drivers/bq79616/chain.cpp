// BQ79616 daisy-chain driver (see chain.hpp for the contract).
//
// Every operation is a short script of Steps run by one interpreter: a step either starts something that
// completes later (a ping, a frame exchange, a timer) and the interpreter returns, or finishes at once and
// the next step runs. Scripts keep the TI sequences readable next to their sources and cost a few bytes per
// step instead of a function per state.
//
// Sources: SLUSE81E (BQ79616-Q1 datasheet) §6.6 timing, §9.3.6 communication and auto-addressing
// (table 9-19), §9.4 power modes and pings, §9.5.4 register map; SLUUC56B (TI bring-up procedure, wake
// timing); TI's MSPM0 SDK example as summarised in bq79616-protocol.md (§5, §6).
#include "drivers/bq79616/chain.hpp"

#include "core/assert.hpp"
#include "core/bytes.hpp"
#include "drivers/bq79616/registers.hpp"

FW_MODULE(fw::Module::DriverBq79616);

namespace fw::drivers::bq79616 {

enum class Op : uint8_t {
  Ping,   // kind: PingKind
  Delay,  // kind: DelayKind
  Write,  // kind: WriteKind; value: the byte; n: bytes (literal writes) or repetitions (WSeq)
  Read,   // kind: ReadKind; n: bytes per device; value: repetitions (RDiscard) or the ValidBits part (RScan)
  Drain,  // receive until the line is quiet
  Raw,    // the frame startRead()/startWrite() encoded
  Call,   // nested bring-up (recovery); kind: RecoveryLevel
  Phase,  // end of a bring-up phase when that phase was started alone
  End,
};

struct Chain::Step {
  Op op;
  uint8_t kind = 0;
  uint8_t value = 0;
  uint8_t n = 0;
  uint16_t reg = 0;
};

namespace {

using R = RequestType;

enum PingKind : uint8_t { kPingWake, kPingSleepToActive, kPingCommClear, kPingHwReset };
enum DelayKind : uint8_t {
  kWakeSetup,
  kStackWake,
  kAdcSettle,
  kRxMin,
  kStackSleepToActive,
  kHwResetTone,
  kHwReset,
};
enum WriteKind : uint8_t {
  kWBcast,       // broadcast write of `n` bytes of `value`
  kWBase,        // single write to the base (address 0)
  kWSeq,         // broadcast write of `value` to `n` consecutive registers, one frame each
  kWActiveCell,  // broadcast ACTIVE_CELL from the configuration
  kWAdcConf1,    // broadcast ADC_CONF1 from the configuration
  kWAddress,     // broadcast DIR0_ADDR = 0, 1, ... one per address slot
  kWTop,         // COMM_CTRL of base and top; value 0: as configured, 1: as discovered
  kWCrc,         // each device's CUST_CRC_RSLT (still in rx_ from kRCrc) to its CUST_CRC
};
enum ReadKind : uint8_t {
  kRDiscard,   // DLL-sync dummy: broadcast read of `value` consecutive registers, responses unused
  kRDiscover,  // single reads of DIR0_ADDR from address 0 up until a device does not answer
  kRVerify,    // broadcast read of DIR0_ADDR: every address, top first; a failure ends the operation
  kRProbe,     // the same as a recovery probe: success ends the ladder at rung `value`
  kRCrc,       // broadcast read of CUST_CRC_RSLT, for kWCrc
  kRFaults,    // broadcast read of FAULT_SUMMARY: every device clear
  kRScan,      // a scan part (`value` = ValidBits), with retry and per-device fallback
};

constexpr Duration kPingLow[] = {kWakePing, kSleepToActivePing, kCommClearPing, kHwResetPing};

// Waits: base + perDevice x configured devices (microseconds).
struct DelaySpec {
  uint32_t base;
  uint16_t perDevice;
};
constexpr DelaySpec kDelays[] = {
    {11000, 0},  // tSU(WAKE_SHUT): 10 ms max (SLUSE81E §6.6) + 10 %
    {0, 11600},  // WAKE tone ~1.6 ms + ACTIVE entry ~10 ms, per device (SLUUC56B §1.2)
    {0, 5},      // + config adcSettle: LPF settling, 5 us per device as TI's bring-up waits
    {100, 0},    // after COMM CLEAR, before the next frame (tUART(RXMIN), rounded up)
    {0, 1000},   // tSU(SLP2ACT) 230 us + the SLEEPtoACTIVE tone, per device (estimate, rounded up)
    {0, 2000},   // HW_RESET tone up the stack, per device (estimate)
    {83000, 0},  // tHWRST 75 ms (BQ75614-Q1 sibling table) + 10 %
};

// Wake, auto-address and configure, in that order; each phase ends at a Phase step.
constexpr Chain::Step kBringUp[] = {
    // Wake (SLUUC56B §1.2). Two WAKE pings: after a SHUTDOWN ping the COMH/COML receivers only come back
    // with the second one; a WAKE to an awake device just resets it, which bring-up does anyway.
    {Op::Ping, kPingWake},
    {Op::Delay, kWakeSetup},
    {Op::Ping, kPingWake},
    {Op::Delay, kWakeSetup},
    {Op::Write, kWBase, regs::kControl1SendWake, 1, regs::kControl1},
    {Op::Delay, kStackWake},
    {Op::Phase},
    // Auto-address (SLUSE81E table 9-19; protocol.md §6), then discovery and read-back.
    {Op::Write, kWSeq, 0x00, 8, regs::kOtpEccDatain1},
    {Op::Write, kWBcast, regs::kControl1AddrWr, 1, regs::kControl1},
    {Op::Write, kWAddress, 0, 1, regs::kDir0Addr},
    {Op::Write, kWBcast, regs::kCommStack, 1, regs::kCommCtrl},
    {Op::Write, kWTop, 0, 1, regs::kCommCtrl},
    {Op::Read, kRDiscard, 8, 1, regs::kOtpEccDatain1},
    {Op::Write, kWBcast, regs::kFaultRst2StartupComm, 1, regs::kFaultRst2},
    {Op::Read, kRDiscover, 0, 1, regs::kDir0Addr},
    {Op::Write, kWTop, 1, 1, regs::kCommCtrl},
    {Op::Read, kRVerify, 0, 1, regs::kDir0Addr},
    {Op::Phase},
    // Configure. NVM-shadow writes first, so the CRC refresh covers them (chain.hpp).
    {Op::Write, kWActiveCell, 0, 1, regs::kActiveCell},
    {Op::Write, kWAdcConf1, 0, 1, regs::kAdcConf1},
    {Op::Read, kRCrc, 0, 2, regs::kCustCrcRsltHi},
    {Op::Write, kWCrc, 0, 2, regs::kCustCrcHi},
    {Op::Write, kWBcast, 0xFF, 2, regs::kFaultRst1},
    {Op::Write, kWBcast, regs::kAdcCtrl1Continuous, 1, regs::kAdcCtrl1},
    {Op::Delay, kAdcSettle},
    {Op::End},
};
constexpr size_t kAddressPhase = 7;
constexpr size_t kConfigurePhase = 18;
static_assert(kBringUp[kAddressPhase - 1].op == Op::Phase && kBringUp[kConfigurePhase - 1].op == Op::Phase);

constexpr Chain::Step kScan[] = {
    {Op::Read, kRScan, kValidCells, 32, regs::kVcell16Hi},
    {Op::Read, kRScan, kValidDieTemp, 4, regs::kDietemp1Hi},
    {Op::Read, kRScan, kValidGpio, 16, regs::kGpio1Hi},
    {Op::Read, kRScan, kValidFaults, 1, regs::kFaultSummary},
    {Op::End},
};

constexpr Chain::Step kClearFaults[] = {
    {Op::Write, kWBcast, 0xFF, 2, regs::kFaultRst1},  // FAULT_RST1 and FAULT_RST2, base and stack
    {Op::Read, kRFaults, 0, 1, regs::kFaultSummary},
    {Op::End},
};

// The recovery ladder (LANDSCAPE.md, BQ79616 problem 3): drain before COMM CLEAR, because a COMM CLEAR
// while stack responses are still arriving makes the host receive stray frames (SLUSE81E §9.3.6.1.2.1.2).
constexpr Chain::Step kRecovery[] = {
    {Op::Drain},
    {Op::Ping, kPingCommClear},
    {Op::Delay, kRxMin},
    {Op::Read, kRProbe, static_cast<uint8_t>(RecoveryLevel::CommClear), 1, regs::kDir0Addr},
    {Op::Ping, kPingSleepToActive},
    {Op::Delay, kStackSleepToActive},
    {Op::Drain},
    {Op::Read, kRProbe, static_cast<uint8_t>(RecoveryLevel::SleepToActive), 1, regs::kDir0Addr},
    {Op::Call, static_cast<uint8_t>(RecoveryLevel::Rewake)},
    {Op::Write, kWBase, regs::kControl2SendHwReset, 1, regs::kControl2},
    {Op::Delay, kHwResetTone},
    {Op::Ping, kPingHwReset},
    {Op::Delay, kHwReset},
    {Op::Call, static_cast<uint8_t>(RecoveryLevel::HardwareReset)},
    {Op::End},
};
// After a COMM CLEAR or SLEEPtoACTIVE rung: those set FAULT_COMM1[COMMCLR_DET, STOP_DET] themselves.
constexpr Chain::Step kRecovered[] = {
    {Op::Write, kWBcast, regs::kFaultRst2AllComm, 1, regs::kFaultRst2},
    {Op::End},
};

constexpr Chain::Step kRaw[] = {{Op::Raw}, {Op::End}};

// First-byte timeout of a read: TI's bound for a chain read is 100 us + 2 x 3 us per device before the
// first byte (BQ79600-Q1 datasheet, tWAIT_READ_MAX); twice that, plus margin.
Duration firstByteTimeout(uint8_t devices) {
  return us(500 + 12U * devices);
}
constexpr Duration kGapTimeout = us(200);  // 20 byte times of silence inside a response

}  // namespace

Chain::Chain(hal::Uart& uart, const hal::Clock& clock, const DriverContext& context,
             const ChainConfig& config)
    : uart_(uart), clock_(clock), ctx_(context), config_(config) {
  FW_ASSERT(config.devices >= 1 && config.devices <= kMaxDevices);
  FW_ASSERT(config.activeCells >= regs::kActiveCellMin && config.activeCells <= kCellsPerDevice);
  FW_ASSERT(context.busEvent != 0 && context.timerEvent != 0 && (context.busEvent & context.timerEvent) == 0);
  // The guard timer below allows 40 us per byte: 10 bits at 250 kbaud or faster (the BQ79616 runs 1 Mbaud).
  FW_ASSERT(uart.baudRate() >= 250000);
}

void Chain::attachFaultLine(hal::EdgeInput& nfault, sched::EventMask event) {
  FW_ASSERT(event != 0 && (event & ctx_.events()) == 0);
  nfault_ = &nfault;
  faultEvent_ = event;
  nfault.enable(ctx_.scheduler.notifier(ctx_.task, event));
}

// --- operations
// ---------------------------------------------------------------------------------------------

Status Chain::begin(const Step* script, bool singlePhase) {
  if (active_) return Status::Busy;
  pc_ = script;
  ret_ = nullptr;
  loop_ = 0;
  attempt_ = 0;
  localising_ = false;
  singlePhase_ = singlePhase;
  active_ = true;
  finished_ = false;
  deferred_ = Status::Ok;
  result_ = Status::Ok;
  run();
  // Every script starts with something asynchronous; a synchronous end is a failure to start.
  FW_ASSERT(active_ || result_ != Status::Ok);
  return active_ ? Status::Ok : result_;
}

Status Chain::startWake() {
  return begin(kBringUp, true);
}
Status Chain::startAutoAddress() {
  return begin(kBringUp + kAddressPhase, true);
}
Status Chain::startConfigure() {
  if (active_) return Status::Busy;
  if (devices_ == 0) return Status::NotReady;
  return begin(kBringUp + kConfigurePhase, true);
}
Status Chain::startBringUp() {
  return begin(kBringUp, false);
}

Status Chain::startScan(std::span<DeviceRecord> records, ScanSummary& summary) {
  if (active_) return Status::Busy;
  if (devices_ == 0) return Status::NotReady;
  if (records.size() < config_.devices || config_.scanParts == 0) return Status::InvalidArgument;
  records_ = records;
  summary_ = &summary;
  parts_ = static_cast<uint8_t>(config_.scanParts | (faultPending_ ? kValidFaults : 0));
  broken_ = false;
  for (uint8_t d = 0; d < config_.devices; ++d)
    records_[d] = DeviceRecord{};
  summary = ScanSummary{};
  summary.started = clock_.now();
  return begin(kScan, false);
}

Status Chain::startClearFaults() {
  if (active_) return Status::Busy;
  if (devices_ == 0) return Status::NotReady;
  ++stats_.faultClears;
  return begin(kClearFaults, false);
}

Status Chain::startRecovery() {
  if (active_) return Status::Busy;
  ++stats_.recoveryAttempts;
  return begin(kRecovery, false);
}

Status Chain::startWrite(RequestType type, uint8_t device, uint16_t reg, std::span<const uint8_t> data) {
  if (active_) return Status::Busy;
  const size_t n = encodeWrite(type, device, reg, data, tx_);
  if (n == 0) return Status::InvalidArgument;
  txLen_ = static_cast<uint8_t>(n);
  userRx_ = {};
  return begin(kRaw, false);
}

Status Chain::startRead(RequestType type, uint8_t device, uint16_t reg, uint8_t count,
                        std::span<uint8_t> rx) {
  if (active_) return Status::Busy;
  size_t frames = 1;
  if (type != RequestType::SingleRead) {
    if (devices_ == 0) return Status::NotReady;
    frames = type == RequestType::StackRead ? devices_ - 1U : devices_;
  }
  const size_t n = encodeRead(type, device, reg, count, tx_);
  if (n == 0 || frames * responseSize(count) > rx.size()) return Status::InvalidArgument;
  txLen_ = static_cast<uint8_t>(n);
  userRx_ = rx.first(frames * responseSize(count));
  return begin(kRaw, false);
}

// --- the interpreter
// ----------------------------------------------------------------------------------------

Progress Chain::onEvent(sched::EventMask events) {
  finished_ = false;
  if ((events & faultEvent_) != 0) {
    ++stats_.faultLineEdges;
    faultPending_ = true;
  }
  if ((events & ctx_.busEvent) != 0 && waiting_ == Wait::Bus) {
    waiting_ = Wait::None;
    ctx_.scheduler.stopTimer(timer_);
    onBus();
    run();
  }
  // A timer event is current only if the timer is no longer armed: an expiry posted before the timer was
  // re-armed for a later wait must not end that wait early.
  if ((events & ctx_.timerEvent) != 0 && !timer_.armed() && waiting_ != Wait::None) {
    if (waiting_ == Wait::Bus) {
      // The UART never reported completion within its own bounds: take the line back.
      uart_.abort();
      waiting_ = Wait::None;
      count(Status::Timeout);
      fail(Status::Timeout, kNoDevice);
    } else {
      waiting_ = Wait::None;
      advance();
    }
    run();
  }
  return finished_ ? Progress::Done : Progress::Running;
}

void Chain::advance() {
  draining_ = false;
  ++pc_;
  loop_ = 0;
  attempt_ = 0;
  localising_ = false;
}

void Chain::finish(Status status) {
  ctx_.scheduler.stopTimer(timer_);
  summary_ = nullptr;
  waiting_ = Wait::None;
  active_ = false;
  finished_ = true;
  result_ = status;
}

void Chain::fail(Status status, uint8_t device) {
  lastFault_ = {status, device};
  if (ret_ == nullptr) return finish(status);
  deferred_ = status;
  resume();  // a nested bring-up failed: the recovery ladder goes on with its next rung
}

void Chain::resume() {
  pc_ = ret_ - 1;
  ret_ = nullptr;
  advance();
}

void Chain::count(Status status) {
  if (status != Status::Ok) ++stats_.errors[static_cast<uint8_t>(status)];
}

void Chain::wait(Wait what, Duration d) {
  waiting_ = what;
  ctx_.scheduler.startTimer(timer_, ctx_.task, ctx_.timerEvent, d);
}

void Chain::send(size_t txLen, std::span<uint8_t> rx) {
  exchange_.tx = {tx_, txLen};
  exchange_.rx = rx;
  exchange_.firstByteTimeout = firstByteTimeout(config_.devices);
  exchange_.gapTimeout = kGapTimeout;
  if (txLen != 0) ++stats_.commandFrames;
  const Status s = uart_.start(exchange_, ctx_.busNotify());
  if (s != Status::Ok) return fail(s, kNoDevice);
  // Guard: the first-byte wait plus the whole exchange at 40 us per byte (4 x the time at 1 Mbaud, so no
  // division by the baud rate is needed), with 20 ms to spare.
  wait(Wait::Bus, exchange_.firstByteTimeout + us(static_cast<uint32_t>(txLen + rx.size()) * 40U) + ms(20));
}

// Frame `index` of the last response (top of stack first), checked against the device that must send it.
Status Chain::frameAt(uint8_t index, uint8_t count, uint8_t expectDevice, ResponseFrame& f) {
  const size_t at = index * responseSize(count);
  if (at + responseSize(count) > exchange_.received) {
    // The UART ended early: its status says how (NoResponse, Truncated, CommFault).
    return exchange_.status != Status::Ok ? exchange_.status : Status::Truncated;
  }
  const Status s = parseResponse({rx_ + at, exchange_.received - at}, reg_, count, f);
  if (s == Status::Ok && f.device != expectDevice) return Status::DeviceId;
  return s;
}

uint8_t Chain::slots() const {
  // One address more than configured, so discovery can notice a device the configuration left out.
  return config_.devices < kMaxDevices ? static_cast<uint8_t>(config_.devices + 1) : kMaxDevices;
}

void Chain::run() {
  while (active_ && waiting_ == Wait::None) {
    const Step& s = *pc_;
    switch (s.op) {
      case Op::Ping: {
        const Status started = uart_.ping(kPingLow[s.kind], ctx_.busNotify());
        if (started != Status::Ok) {
          fail(started, kNoDevice);
        } else {
          wait(Wait::Bus, kPingLow[s.kind] + ms(20));
        }
        break;
      }
      case Op::Delay: {
        const DelaySpec& d = kDelays[s.kind];
        Duration t = us(d.base + static_cast<uint32_t>(d.perDevice) * config_.devices);
        if (s.kind == kAdcSettle) t = t + config_.adcSettle;
        wait(Wait::Timer, t);
        break;
      }
      case Op::Write:
        issueWrite(s);
        break;
      case Op::Read:
        if (draining_) {
          // After a failed read, let whatever the chain still sends go by before the next frame, or its tail
          // would land in the next response (a chain answering with more frames than expected, a late frame).
          send(0, {rx_, sizeof rx_});
        } else {
          issueRead(s);
        }
        break;
      case Op::Drain:
        // Receive whatever is still on the line; the exchange ends after a first-byte timeout of silence.
        send(0, {rx_, sizeof rx_});
        break;
      case Op::Raw:
        send(txLen_, userRx_);
        break;
      case Op::Call:
        ret_ = pc_ + 1;
        level_ = static_cast<RecoveryLevel>(s.kind);
        deferred_ = Status::Ok;
        pc_ = kBringUp;
        singlePhase_ = false;
        break;
      case Op::Phase:
        if (singlePhase_) {
          finish(deferred_);
        } else {
          advance();
        }
        break;
      case Op::End:
        if (ret_ == nullptr) {
          if (summary_ != nullptr) endScan();
          finish(deferred_);
        } else if (deferred_ == Status::Ok) {
          ++stats_.recoveries[static_cast<uint8_t>(level_)];
          finish(Status::Ok);
        } else {
          resume();  // the bring-up left the chain degraded: next rung
        }
        break;
    }
  }
}

void Chain::issueWrite(const Step& s) {
  uint8_t buf[2] = {s.value, s.value};
  const uint8_t* data = buf;
  uint8_t bytes = s.n;
  auto type = R::BroadcastWrite;
  uint8_t device = 0;
  uint16_t reg = s.reg;
  switch (s.kind) {
    case kWBase:
      type = R::SingleWrite;
      break;
    case kWSeq:
      reg = static_cast<uint16_t>(reg + loop_);
      bytes = 1;
      break;
    case kWActiveCell:
      buf[0] = static_cast<uint8_t>(config_.activeCells - regs::kActiveCellMin);
      break;
    case kWAdcConf1:
      buf[0] = config_.adcConf1;
      break;
    case kWAddress:
      buf[0] = loop_;
      break;
    case kWTop: {
      // Phase 0 (TI order): base = 0x00 and top = 0x03, or 0x01 for a chain of one. Phase 1: move the top to
      // the last device that answered if discovery found fewer than configured.
      const uint8_t n = s.value == 0 ? config_.devices : found_;
      const bool needed = s.value == 0 ? loop_ < (n == 1 ? 1 : 2) : (loop_ == 0 && found_ < config_.devices);
      if (!needed) return advance();
      const bool standalone = n == 1;
      const bool topWrite = s.value == 1 || loop_ == 1;
      type = R::SingleWrite;
      device = topWrite && !standalone ? static_cast<uint8_t>(n - 1) : 0;
      buf[0] = standalone ? regs::kCommStandalone : (topWrite ? regs::kCommTop : regs::kCommBase);
      break;
    }
    case kWCrc:
      // Frame loop_ of the CUST_CRC_RSLT response (still in rx_) belongs to device top - loop_.
      type = R::SingleWrite;
      device = static_cast<uint8_t>(devices_ - 1 - loop_);
      data = rx_ + loop_ * responseSize(2) + 4;
      break;
    default:  // kWBcast
      break;
  }
  const size_t len = encodeWrite(type, device, reg, {data, bytes}, tx_);
  FW_ASSERT(len != 0);
  send(len, {});
}

void Chain::issueRead(const Step& s) {
  auto type = R::BroadcastRead;
  uint8_t device = 0;
  uint8_t frames = devices_;
  reg_ = s.reg;
  switch (s.kind) {
    case kRDiscard:
      reg_ = static_cast<uint16_t>(reg_ + loop_);
      frames = config_.devices;
      break;
    case kRDiscover:
      if (loop_ == 0) found_ = 0;
      type = R::SingleRead;
      device = loop_;
      frames = 1;
      break;
    case kRProbe:
      // A probe passes only for the whole configured chain: a chain that came back short goes on to the rungs
      // that re-discover it.
      if (devices_ < config_.devices) return advance();
      break;
    case kRScan:
      if ((parts_ & s.value) == 0) return advance();
      if (localising_) {
        // Per-device fallback, from the base upward, for the devices this part has not validated yet.
        while (loop_ < devices_ && (records_[loop_].valid & s.value) != 0)
          ++loop_;
        if (loop_ >= devices_) return advance();
        type = R::SingleRead;
        device = loop_;
        frames = 1;
      }
      break;
    default:
      break;
  }
  if (frames == 0) return fail(Status::NotReady, kNoDevice);
  first_ = type == R::SingleRead ? device : static_cast<uint8_t>(frames - 1);
  frames_ = frames;
  faulted_ = kNoDevice;
  const size_t len = encodeRead(type, device, reg_, s.n, tx_);
  const size_t expect = frames * responseSize(s.n);
  FW_ASSERT(len != 0 && expect <= sizeof rx_);
  send(len, {rx_, expect});
}

void Chain::onBus() {
  const Step& s = *pc_;
  const Status st = exchange_.status;
  if (draining_) {
    // Quiet (NoResponse, Truncated): done. A full buffer means more is coming: drain once more.
    draining_ = st == Status::Ok && ++drained_ < 4;
    return;
  }
  switch (s.op) {
    case Op::Write:
      if (st != Status::Ok) {
        count(st);
        fail(st, kNoDevice);
        break;
      }
      ++loop_;
      if (s.kind == kWSeq       ? loop_ >= s.n
          : s.kind == kWAddress ? loop_ >= slots()
          : s.kind == kWCrc     ? loop_ >= devices_
                                : s.kind != kWTop) {
        advance();  // kWTop decides in issueWrite() whether another write is needed
      }
      break;
    case Op::Read:
      onRead(s);
      break;
    case Op::Drain:
      // Ok means the buffer filled while bytes kept coming: drain again, at most 4 buffers in all.
      if (st != Status::Ok || ++loop_ >= 4) advance();
      break;
    case Op::Raw:
      count(st);
      finish(st);
      break;
    default:  // Ping
      advance();
      break;
  }
}

// Checks one validated frame for the step's purpose and files its data.
Status Chain::onFrame(const Step& s, uint8_t device, const uint8_t* data) {
  switch (s.kind) {
    case kRDiscover:
    case kRVerify:
    case kRProbe:
      return (data[0] & kMaxAddress) == device ? Status::Ok : Status::VerifyFailed;
    case kRFaults:
      // The lowest stack device with a fault is named: the base's FCOMM_DET only echoes a stack fault.
      if (data[0] != 0 && (device != 0 || faulted_ == kNoDevice)) {
        faulted_ = device;
        faultBits_ = data[0];
      }
      return Status::Ok;
    case kRScan:
      store(s.value, device, data);
      return Status::Ok;
    default:  // kRDiscard, kRCrc
      return Status::Ok;
  }
}

void Chain::onRead(const Step& s) {
  Status r = Status::Ok;
  uint8_t bad = kNoDevice;
  for (uint8_t i = 0; i < frames_; ++i) {
    const auto dev = static_cast<uint8_t>(first_ - i);
    ResponseFrame f;
    r = frameAt(i, s.n, dev, f);
    if (r == Status::Ok) r = onFrame(s, dev, f.data.data());
    if (r != Status::Ok) {
      // Nothing after a bad frame can be trusted: the frames below it are not looked at.
      bad = dev;
      break;
    }
    ++stats_.responseFrames;
  }
  if (s.kind == kRDiscard) {  // DLL-sync dummies: TI ignores their responses, and so does the driver
    if (++loop_ >= s.value) advance();
    return;
  }
  if (r == Status::Ok) {
    attempt_ = 0;
    switch (s.kind) {
      case kRDiscover:
        found_ = static_cast<uint8_t>(loop_ + 1);
        if (++loop_ >= slots()) endDiscovery(r);
        return;
      case kRScan:
        if (localising_) {
          ++loop_;
        } else {
          advance();
        }
        return;
      case kRProbe:
        level_ = static_cast<RecoveryLevel>(s.value);
        ++stats_.recoveries[s.value];
        pc_ = kRecovered;
        loop_ = 0;
        return;
      case kRFaults:
        if (faulted_ != kNoDevice) {
          return fail((faultBits_ & regs::kSummaryFaultComm) != 0 ? Status::CommFault : Status::VerifyFailed,
                      faulted_);
        }
        return advance();
      default:  // kRVerify, kRCrc
        return advance();
    }
  }
  // Silence at the address above the configured count is the expected end of discovery, not an error.
  const bool expectedSilence = s.kind == kRDiscover && r == Status::NoResponse && loop_ >= config_.devices;
  if (!expectedSilence) count(r);
  if (r != Status::NoResponse) {
    draining_ = true;
    drained_ = 0;
  }
  // One retry of the whole transaction, except for silence in discovery (nothing is there) and for the
  // per-device reads of a scan (the chain read was retried already).
  const bool retry =
      s.kind == kRDiscover ? r != Status::NoResponse : !(s.kind == kRScan && (localising_ || broken_));
  if (attempt_ == 0 && retry) {
    attempt_ = 1;
    ++stats_.retries;
    return;  // run() sends the same step again
  }
  switch (s.kind) {
    case kRDiscover:
      return endDiscovery(r);
    case kRScan:
      if (!localising_) {
        ++stats_.localisations;
        localising_ = true;
        loop_ = 0;
        return;
      }
      markFailed(s.value, loop_, r);
      if (r == Status::NoResponse) {
        // Silence: the link ends below this device, so the ones above it cannot be reached either.
        for (uint8_t d = static_cast<uint8_t>(loop_ + 1); d < devices_; ++d) {
          if ((records_[d].valid & s.value) == 0) markFailed(s.value, d, Status::NoResponse);
        }
        loop_ = devices_;
      } else {
        ++loop_;
      }
      return;
    case kRProbe:
      lastFault_ = {r, bad};
      return advance();  // the probe failed: next rung of the ladder
    default:
      return fail(r, bad);
  }
}

void Chain::endDiscovery(Status r) {
  if (found_ == 0) return fail(r, 0);
  devices_ = found_ < config_.devices ? found_ : config_.devices;
  if (found_ < config_.devices) {
    deferred_ = Status::CommFault;
    lastFault_ = {r, found_};
  } else if (found_ > config_.devices) {
    deferred_ = Status::VerifyFailed;
    lastFault_ = {Status::VerifyFailed, config_.devices};
  }
  advance();
}

// --- scans
// --------------------------------------------------------------------------------------------------

void Chain::store(uint8_t part, uint8_t device, const uint8_t* p) {
  DeviceRecord& r = records_[device];
  if (part == kValidFaults) {
    r.faultSummary = p[0];
    faultPending_ = false;
  } else {
    // Big-endian 16-bit words; the cell block starts with VCELL16, so it fills the record backwards.
    int16_t* out = part == kValidCells  ? r.cellRaw + kCellsPerDevice - 1
                   : part == kValidGpio ? r.gpioRaw
                                        : r.dieTemp;
    const int step = part == kValidCells ? -1 : 1;
    const unsigned words = part == kValidCells ? kCellsPerDevice : part == kValidGpio ? kGpiosPerDevice : 2U;
    // A measurement that has not been converted (0x8000) is not a value: cells of the active range and die
    // temperatures make the part NotReady. GPIOs keep 0x8000, their usual value when not an ADC input.
    const unsigned checked = part == kValidCells ? config_.activeCells : part == kValidGpio ? 0U : 2U;
    for (unsigned i = 0; i < words; ++i) {
      const int16_t v = bytes::loadBeI16(p + 2 * i);
      if (v == regs::kNotReady && words - 1 - i < checked) return markFailed(part, device, Status::NotReady);
      out[static_cast<int>(i) * step] = part == kValidDieTemp ? dieTempDeciKelvin(v) : v;
    }
    if (part == kValidCells) r.takenAt = clock_.now();
  }
  r.valid = static_cast<uint8_t>(r.valid | part);
}

void Chain::markFailed(uint8_t part, uint8_t device, Status status) {
  DeviceRecord& r = records_[device];
  r.valid = static_cast<uint8_t>(r.valid & ~part);
  switch (part) {
    case kValidCells:
      for (int16_t& v : r.cellRaw)
        v = 0;
      break;
    case kValidDieTemp:
      r.dieTemp[0] = r.dieTemp[1] = 0;
      break;
    case kValidGpio:
      for (int16_t& v : r.gpioRaw)
        v = 0;
      break;
    default:
      r.faultSummary = 0;
      break;
  }
  if (r.status == Status::Ok) r.status = status;
  if (status == Status::NoResponse) broken_ = true;
}

void Chain::endScan() {
  ScanSummary& sum = *summary_;
  sum.devices = devices_;
  for (uint8_t d = 0; d < config_.devices; ++d) {
    DeviceRecord& r = records_[d];
    if (d >= devices_) r.status = Status::NoResponse;  // not in the chain since the last bring-up
    if (r.status == Status::Ok && (r.valid & parts_) == parts_) ++sum.validDevices;
    if (r.faultSummary != 0) ++sum.faultedDevices;
    if (r.status != Status::Ok && sum.firstError.device == kNoDevice) sum.firstError = {r.status, d};
  }
  sum.finished = clock_.now();
  if (sum.firstError.device != kNoDevice) {
    lastFault_ = sum.firstError;
    deferred_ = sum.firstError.status;
  }
}

}  // namespace fw::drivers::bq79616
