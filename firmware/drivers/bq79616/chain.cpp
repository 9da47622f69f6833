// BQ79616 daisy-chain driver (see chain.hpp for the contract).
//
// Every operation is a short script of Steps run by one interpreter: a step either starts something that
// completes later (a ping, a frame exchange, a timer) and the interpreter returns, or finishes at once and
// the next step runs. Scripts keep the TI sequences readable next to their sources and cost a few bytes per
// step instead of a function per state. Every frame a script sends goes through one path (issue()): the step
// says what to send, and how many times (a step repeats while `loop_` is below its repetition count, so
// "next device", "next address" and "done" are the same code for every kind of step).
//
// Sources: SLUSE81E (BQ79616-Q1 datasheet) §6.6 timing, §9.3.6 communication and auto-addressing
// (table 9-19), §9.4 power modes and pings, §9.5.4 register map; SLUUC56B (TI bring-up procedure, wake
// timing); TI's MSPM0 SDK 2.09 bq79616_uart_to_can example (main.c start-up, AutoAddress()).
#include "drivers/bq79616/chain.hpp"

#include <cstddef>
#include <cstring>
#include <type_traits>

#include "core/assert.hpp"
#include "core/bytes.hpp"
#include "drivers/bq79616/registers.hpp"

FW_MODULE(fw::Module::DriverBq79616);

namespace fw::drivers::bq79616 {

enum class Op : uint8_t {
  // The steps that use the bus come first: after a failed read, run() drains the line before any of them.
  Ping,   // arg: the low time in microseconds
  Frame,  // kind: Kind; value: the byte written, the ValidBits part of a scan or the ladder rung
  Drain,  // receive until the line is quiet
  Raw,    // the frame startRead()/startWrite() encoded
  Delay,  // kind: DelayKind; arg << value: microseconds
  Call,   // nested bring-up (recovery); kind: RecoveryLevel
  Phase,  // end of a bring-up phase when that phase was started alone
  End,
};

// Four bytes a step (two thirds of separate fields): the operation and its kind share a byte, and a frame's
// register bytes share a half-word with the register (BQ79616 registers are below 0x800).
struct detail::Step {
  uint8_t code;       // Op << 4 | kind
  uint8_t value = 0;  // see Op
  uint16_t arg = 0;   // Frame: register | (register bytes − 1) << 11; Ping, Delay: the time
};

namespace {

using R = RequestType;
using Step = Chain::Step;

constexpr uint8_t code(Op op, uint8_t kind = 0) {
  return static_cast<uint8_t>(static_cast<uint8_t>(op) << 4 | kind);
}
constexpr Op opOf(const Step& s) {
  return static_cast<Op>(s.code >> 4);
}

// kPerDevice and kAdcSettle scale with the configured device count, kPerDeviceAndOneMore with one more;
// kPause is startPause()'s wait.
enum DelayKind : uint8_t { kOnce, kPerDevice, kAdcSettle, kPerDeviceAndOneMore, kPause };

// Frame steps: writes first, then reads (kRDllSync and above).
enum Kind : uint8_t {
  kWBcast,       // broadcast write of `value` (to as many consecutive registers as the step's bytes)
  kWBase,        // single write of `value` to the base (address 0)
  kWDllSync,     // broadcast write of `value` to kDllSyncFrames consecutive registers, one frame each
  kWActiveCell,  // broadcast ACTIVE_CELL from the configuration
  kWAdcConf1,    // broadcast ADC_CONF1 from the configuration
  kWAddress,     // broadcast DIR0_ADDR = 0, 1, ... one per address slot
  kWTop,         // COMM_CTRL of base and top; value 0: as configured, 1: as discovered
  kWCrc,         // each device's CUST_CRC_RSLT (still in rx_ from kRCrc) to its CUST_CRC
  kRDllSync,   // DLL-sync dummies: broadcast reads of kDllSyncFrames consecutive registers, responses unused
  kRDiscover,  // single reads of DIR0_ADDR from address 0 up until a device does not answer
  kRVerify,    // broadcast read of DIR0_ADDR: every address, top first; a failure ends the operation
  kRProbe,     // broadcast read of DEV_STAT as a recovery probe: success ends the ladder at rung `value`
  kRCrcDone,   // broadcast reads of DEV_STAT until every device reported CUST_CRC_DONE (bounded)
  kRCrc,       // broadcast read of CUST_CRC_RSLT, for kWCrc
  kRFaults,    // broadcast read of FAULT_SUMMARY: every device clear
  kRScan,      // a scan part (`value` = ValidBits), with retry and per-device fallback
};

constexpr uint8_t kDllSyncFrames = 8;  // TI's table 9-19: 8 dummy writes, then 8 dummy reads

// Waiting for CUST_CRC_DONE: TI gives no time for a CRC pass, so the driver polls DEV_STAT every
// kCrcPollInterval, at most kCrcPolls times (about 50 ms plus the reads), then fails with Timeout.
constexpr uint8_t kCrcPolls = 50;
constexpr Duration kCrcPollInterval = ms(1);
// INIT bytes of the frames the scripts send (a write's data length − 1 goes into bits 2:0).
constexpr uint8_t kInitSingleRead = initByte(R::SingleRead, 0);
constexpr uint8_t kInitBroadcastRead = initByte(R::BroadcastRead, 0);
constexpr uint8_t kInitSingleWrite = initByte(R::SingleWrite, 1);
constexpr uint8_t kInitBroadcastWrite = initByte(R::BroadcastWrite, 1);

// Step builders, evaluated at compile time only: a step that does not fit its encoding calls
// stepOutOfRange(), which is not constexpr, so the script does not compile.
inline void stepOutOfRange() {}
constexpr uint16_t kRegMask = 0x07FF;
// `bytes`: registers written or read per device, 1..32 (also the last register of a DLL-sync run fits).
consteval Step frame(Kind kind, uint16_t reg, uint8_t value = 0, uint8_t bytes = 1) {
  if (reg + kDllSyncFrames > kRegMask || bytes < 1 || bytes > 32) stepOutOfRange();
  return {code(Op::Frame, kind), value, static_cast<uint16_t>(reg | (bytes - 1) << 11)};
}
consteval Step ping(Duration low) {
  if (low.us > 0xFFFF) stepOutOfRange();
  return {code(Op::Ping), 0, static_cast<uint16_t>(low.us)};
}
// `time` in microseconds, as a 16-bit value and a shift; it must be exact.
consteval Step delay(DelayKind kind, uint32_t time) {
  uint8_t shift = 0;
  while ((time >> shift) > 0xFFFF)
    ++shift;
  if (((time >> shift) << shift) != time) stepOutOfRange();
  return {code(Op::Delay, kind), shift, static_cast<uint16_t>(time >> shift)};
}
consteval Step call(RecoveryLevel level) {
  return {code(Op::Call, static_cast<uint8_t>(level))};
}
constexpr Step kPhase = {code(Op::Phase)};
constexpr Step kEnd = {code(Op::End)};

// Wake, auto-address and configure, in that order; each phase ends at a Phase step.
constexpr Step kBringUp[] = {
    // Wake (SLUUC56B §1.2). Two WAKE pings: after a SHUTDOWN ping the COMH/COML receivers only come back
    // with the second one; a WAKE to an awake device just resets it, which bring-up does anyway. Each is
    // followed by tSU(WAKE_SHUT): 10 ms max (SLUSE81E §6.6) + 10 %.
    ping(kWakePing),
    delay(kOnce, 11000),
    ping(kWakePing),
    delay(kOnce, 11000),
    frame(kWBase, regs::kControl1, regs::kControl1SendWake),
    // The WAKE tone up the stack: TI's example waits 12 ms per board (bq79616_uart_to_can), SLUUC56B gives
    // ~1.6 ms tone + ~10 ms ACTIVE entry per device; waited for the configured devices and one more, so
    // that discovery finds a device beyond the configured count awake and reports it.
    delay(kPerDeviceAndOneMore, 12000),
    kPhase,
    // Auto-address (SLUSE81E table 9-19; TI's bq79616_uart_to_can AutoAddress()), then discovery and
    // read-back.
    frame(kWDllSync, regs::kOtpEccDatain1, 0x00),
    frame(kWBcast, regs::kControl1, regs::kControl1AddrWr),
    frame(kWAddress, regs::kDir0Addr),
    frame(kWBcast, regs::kCommCtrl, regs::kCommStack),
    frame(kWTop, regs::kCommCtrl, 0),
    frame(kRDllSync, regs::kOtpEccDatain1),
    frame(kWBcast, regs::kFaultRst2, regs::kFaultRst2StartupComm),
    frame(kRDiscover, regs::kDir0Addr),
    frame(kWTop, regs::kCommCtrl, 1),
    frame(kRVerify, regs::kDir0Addr),
    kPhase,
    // Configure, in TI's order (its bq79616 example masks the CRC fault with FAULT_MSK2 = 0x40 before it
    // changes the NVM shadow registers): mask, write, wait until a CRC pass over the new contents has ended
    // (SLUSF21 DEV_STAT[CUST_CRC_DONE]), copy each device's CUST_CRC_RSLT to its CUST_CRC, clear, unmask.
    // FAULT_MSK2 is an NVM shadow register itself, inside the customer CRC (SLUSF21 register-map summary),
    // so unmasking changes the contents once more and the refresh is repeated over the final contents.
    delay(kOnce,
          4400),  // TI's example: 4 ms of "AFE settling" after addressing (no document gives one) + 10 %
    frame(kWBcast, regs::kFaultMsk2, regs::kFaultMsk2CustCrc),
    frame(kWActiveCell, regs::kActiveCell),
    frame(kWAdcConf1, regs::kAdcConf1),
    frame(kRCrcDone, regs::kDevStat),
    frame(kRCrc, regs::kCustCrcRsltHi, 0, 2),
    frame(kWCrc, regs::kCustCrcHi, 0, 2),
    frame(kWBcast, regs::kFaultRst1, 0xFF, 2),  // FAULT_RST1 and FAULT_RST2
    frame(kWBcast, regs::kFaultMsk2, 0x00),
    frame(kRCrcDone, regs::kDevStat),
    frame(kRCrc, regs::kCustCrcRsltHi, 0, 2),
    frame(kWCrc, regs::kCustCrcHi, 0, 2),
    frame(kWBcast, regs::kFaultRst1, 0xFF, 2),
    frame(kWBcast, regs::kAdcCtrl1, regs::kAdcCtrl1Continuous),
    delay(kAdcSettle, 5),  // + config adcSettle: LPF settling, 5 us per device as TI's bring-up waits
    kEnd,
};
constexpr size_t kAddressPhase = 7;
constexpr size_t kConfigurePhase = 18;
static_assert(kBringUp[kAddressPhase - 1].code == kPhase.code &&
              kBringUp[kConfigurePhase - 1].code == kPhase.code);

constexpr Step kScan[] = {
    frame(kRScan, regs::kVcell16Hi, kValidCells, 2 * kCellsPerDevice),
    frame(kRScan, regs::kDietemp1Hi, kValidDieTemp, 4),
    frame(kRScan, regs::kGpio1Hi, kValidGpio, 2 * kGpiosPerDevice),
    frame(kRScan, regs::kFaultSummary, kValidFaults, 1),
    kEnd,
};
// 64 devices x the largest read must fit the receive buffer: issue() relies on it without a check.
static_assert(kRxBufferBytes >= kMaxDevices * responseSize(32));

constexpr Step kClearFaults[] = {
    frame(kWBcast, regs::kFaultRst1, 0xFF, 2),  // FAULT_RST1 and FAULT_RST2, base and stack
    frame(kRFaults, regs::kFaultSummary),
    kEnd,
};

// The recovery ladder (BQ79600 data sheet, COMM CLEAR; TI E2E thread 1400830): drain before COMM CLEAR,
// because a COMM CLEAR while stack responses are still arriving makes the host receive stray frames (SLUSE81E
// §9.3.6.1.2.1.2).
constexpr Step kRecovery[] = {
    {code(Op::Drain)},
    ping(kCommClearPing),
    delay(kOnce, 100),  // tUART(RXMIN) after COMM CLEAR, before the next frame, rounded up
    frame(kRProbe, regs::kDevStat, static_cast<uint8_t>(RecoveryLevel::CommClear)),
    ping(kSleepToActivePing),
    delay(kPerDevice, 1000),  // tSU(SLP2ACT) 230 us + the SLEEPtoACTIVE tone per device (estimate)
    {code(Op::Drain)},
    frame(kRProbe, regs::kDevStat, static_cast<uint8_t>(RecoveryLevel::SleepToActive)),
    call(RecoveryLevel::Rewake),
    frame(kWBase, regs::kControl2, regs::kControl2SendHwReset),
    delay(kPerDevice, 2000),  // the HW_RESET tone up the stack, per device (estimate)
    ping(kHwResetPing),
    delay(kOnce, 83000),  // tHWRST 75 ms (BQ75614-Q1 sibling table) + 10 %
    call(RecoveryLevel::HardwareReset),
    kEnd,
};
// Where startRecovery(from) enters the ladder, by RecoveryLevel.
constexpr uint8_t kRungStart[] = {0, 4, 8, 9};
static_assert(opOf(kRecovery[kRungStart[1]]) == Op::Ping && opOf(kRecovery[kRungStart[2]]) == Op::Call &&
              kRecovery[kRungStart[3]].code == code(Op::Frame, kWBase));
// After a COMM CLEAR or SLEEPtoACTIVE rung: those set FAULT_COMM1[COMMCLR_DET, STOP_DET] themselves.
constexpr Step kRecovered[] = {
    frame(kWBcast, regs::kFaultRst2, regs::kFaultRst2AllComm),
    kEnd,
};

constexpr Step kRaw[] = {{code(Op::Raw)}, kEnd};
constexpr Step kPauseScript[] = {{code(Op::Delay, kPause)}, kEnd};

constexpr Duration kGapTimeout = us(200);  // 20 byte times of silence inside a response

// The constructor and startScan() clear these with memset (zero is each one's empty value); the state has no
// tail padding, so no member of Chain can sit inside the bytes the constructor clears.
static_assert(std::is_trivially_copyable_v<detail::ChainState> &&
              std::is_trivially_copyable_v<DeviceRecord> && std::is_trivially_copyable_v<ScanSummary> &&
              std::is_standard_layout_v<detail::ChainState> &&
              offsetof(detail::ChainState, timer_) + sizeof(sched::Timer) == sizeof(detail::ChainState));

}  // namespace

Chain::Chain(hal::Uart& uart, const hal::Clock& clock, const DriverContext& context,
             const ChainConfig& config)
    : uart_(uart), clock_(clock), ctx_(context) {
  // All of the state zero in one memset (every member is trivially copyable and zero is its empty value);
  // the member initialisers of its parts run before it and become dead stores.
  std::memset(static_cast<void*>(static_cast<detail::ChainState*>(this)), 0, sizeof(detail::ChainState));
  config_ = config;
  configured_ = config.devices;
  FW_ASSERT(config.devices >= 1 && config.devices <= kMaxDevices);
  FW_ASSERT(config.activeCells >= regs::kActiveCellMin && config.activeCells <= kCellsPerDevice);
  FW_ASSERT(context.busEvent != 0 && context.timerEvent != 0 && (context.busEvent & context.timerEvent) == 0);
  // The guard timer in started() allows 40 us per byte: 10 bits at 250 kbaud or faster (the BQ79616 runs
  // 1 Mbaud).
  FW_ASSERT(uart.baudRate() >= 250000);
  busDone_ = context.busNotify();
  lastFault_.device = kNoDevice;
  // One address more than configured, so discovery can notice a device the configuration left out.
  slots_ = config.devices < kMaxDevices ? static_cast<uint8_t>(config.devices + 1) : kMaxDevices;
  // First-byte timeout of a read: TI's bound for a chain read is 100 us + 2 x 3 us per device before the
  // first byte (BQ79600-Q1 datasheet, tWAIT_READ_MAX); twice that, plus margin.
  exchange_.firstByteTimeout = us(500 + 12U * config.devices);
  exchange_.gapTimeout = kGapTimeout;
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
  if (records.size() < configured_ || config_.scanParts == 0) return Status::InvalidArgument;
  records_ = records.data();
  summary_ = &summary;
  parts_ = static_cast<uint8_t>(config_.scanParts | (faultPending_ ? kValidFaults : 0));
  broken_ = false;
  // Zero is every record's empty value (DeviceRecord is trivially copyable): one memset for all of them.
  std::memset(static_cast<void*>(records_), 0, configured_ * sizeof(DeviceRecord));
  std::memset(static_cast<void*>(&summary), 0, sizeof summary);
  summary.firstError.device = kNoDevice;
  summary.started = clock_.now();
  return begin(kScan, false);
}

Status Chain::startClearFaults() {
  if (active_) return Status::Busy;
  if (devices_ == 0) return Status::NotReady;
  ++stats_.faultClears;
  return begin(kClearFaults, false);
}

Status Chain::startRecovery(RecoveryLevel from) {
  if (active_) return Status::Busy;
  ++stats_.recoveryAttempts;
  return begin(kRecovery + kRungStart[static_cast<uint8_t>(from)], false);
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

Status Chain::startPause(Duration d) {
  if (active_) return Status::Busy;
  if (d.us == 0 || d.us > 1000000) return Status::InvalidArgument;
  pause_ = d;
  return begin(kPauseScript, false);
}

// --- the interpreter
// ----------------------------------------------------------------------------------------

Progress Chain::onEvent(sched::EventMask events) {
  const bool wasActive = active_;
  if ((events & faultEvent_) != 0) {
    ++stats_.faultLineEdges;
    faultPending_ = true;
  }
  const Wait w = waiting_;
  if ((events & ctx_.busEvent) != 0 && w == Wait::Bus) {
    waiting_ = Wait::None;
    ctx_.scheduler.stopTimer(timer_);
    onBus();
  } else if ((events & ctx_.timerEvent) != 0 && !timer_.armed() && w != Wait::None) {
    // A timer event is current only if the timer is no longer armed: an expiry posted before the timer was
    // re-armed for a later wait must not end that wait early. (After a bus completion handled above, the
    // next step has either ended the operation or armed the timer again, so one branch is enough.)
    waiting_ = Wait::None;
    if (w == Wait::Bus) {
      // The UART never reported completion within its own bounds: take the line back.
      uart_.abort();
      count(Status::Timeout);
      fail(Status::Timeout);
    } else if (w == Wait::Timer) {
      advance();
    }  // Wait::Poll: run() sends the same step's next poll
  }
  run();  // returns at once unless a step above ended
  // Operations start only from start*(), never inside onEvent(): an operation that was running and is not
  // any more ended here.
  return wasActive && !active_ ? Progress::Done : Progress::Running;
}

void Chain::advance() {
  draining_ = false;
  pc_ = pc_ + 1;
  loop_ = 0;
  attempt_ = 0;
  localising_ = false;
}

// Nothing can be waiting here (every path to it has stopped the timer or seen it expire), so the timer is not
// touched.
void Chain::finish(Status status) {
  summary_ = nullptr;
  active_ = false;
  result_ = status;
}

void Chain::fail(Status status, uint8_t device) {
  lastFault_ = {status, device};
  unwind(status);
}

inline void Chain::unwind(Status status) {
  if (ret_ == nullptr) return finish(status);
  // A nested bring-up failed or left the chain degraded: the recovery ladder goes on with the rung after its
  // Call.
  deferred_ = status;
  pc_ = ret_ - 1;
  ret_ = nullptr;
  advance();
}

void Chain::count(Status status) {
  ++stats_.errors[static_cast<uint8_t>(status)];
}

void Chain::wait(Wait what, Duration d) {
  waiting_ = what;
  ctx_.scheduler.startTimer(timer_, ctx_.task, ctx_.timerEvent, d);
}

// A ping or an exchange was handed to the UART: wait for its completion, guarded by `guard`.
void Chain::started(Status status, Duration guard) {
  if (status != Status::Ok) return fail(status);
  wait(Wait::Bus, guard);
}

void Chain::send(size_t txLen, uint8_t* rx, size_t rxLen) {
  exchange_.tx = {tx_, txLen};
  exchange_.rx = {rx, rxLen};
  if (txLen != 0) ++stats_.commandFrames;
  // Guard: the first-byte wait plus the whole exchange at 40 us per byte (4 x the time at 1 Mbaud, so no
  // division by the baud rate is needed), with 20 ms to spare.
  started(uart_.start(exchange_, busDone_),
          exchange_.firstByteTimeout + us(static_cast<uint32_t>(txLen + rxLen) * 40U) + ms(20));
}

void Chain::run() {
  while (active_ && waiting_ == Wait::None) {
    const Step& s = *pc_;
    const Op op = opOf(s);
    if (draining_ && op <= Op::Raw) {
      // After a failed read, let whatever the chain still sends go by before the bus is used again, or its
      // tail would land in the next response (a chain answering with more frames than expected, a late
      // frame). This also holds across operations: one that ended on a failed read leaves it to the next.
      send(0, rx_, sizeof rx_);
      continue;
    }
    switch (op) {
      case Op::Ping:
        started(uart_.ping(us(s.arg), busDone_), us(s.arg) + ms(20));
        break;
      case Op::Frame:
        issue(s);
        break;
      case Op::Drain:
        // Receive whatever is still on the line; the exchange ends after a first-byte timeout of silence.
        send(0, rx_, sizeof rx_);
        break;
      case Op::Raw:
        send(txLen_, userRx_.data(), userRx_.size());
        break;
      case Op::Delay: {
        if (s.code == code(Op::Delay, kPause)) {
          wait(Wait::Timer, pause_);
          break;
        }
        uint32_t t = static_cast<uint32_t>(s.arg) << s.value;
        if (s.code >= code(Op::Delay, kPerDevice))
          t *= configured_ + (s.code == code(Op::Delay, kPerDeviceAndOneMore) ? 1U : 0U);
        Duration d = us(t);
        if (s.code == code(Op::Delay, kAdcSettle)) d = d + config_.adcSettle;
        wait(Wait::Timer, d);
        break;
      }
      case Op::Call:
        ret_ = pc_ + 1;
        level_ = static_cast<RecoveryLevel>(s.code & 0x0FU);
        deferred_ = Status::Ok;
        pc_ = kBringUp;
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
          unwind(deferred_);
        }
        break;
    }
  }
}

// Sends frame `loop_` of a Frame step, or moves on when the step has sent all of its frames.
void Chain::issue(const Step& s) {
  uint8_t data[2] = {s.value, s.value};
  const uint8_t* bytes = data;
  bool single = false;
  uint8_t device = 0;
  uint16_t reg = s.arg & kRegMask;
  uint8_t reps = 1;
  uint8_t frames = devices_;
  const auto n = static_cast<uint8_t>((s.arg >> 11) + 1);  // register bytes
  switch (s.code) {
    case code(Op::Frame, kWBase):
      single = true;
      break;
    case code(Op::Frame, kWDllSync):
    case code(Op::Frame, kRDllSync):
      reg = static_cast<uint16_t>(reg + loop_);
      reps = kDllSyncFrames;
      frames = configured_;  // before discovery: every configured device answers
      break;
    case code(Op::Frame, kWActiveCell):
      data[0] = static_cast<uint8_t>(config_.activeCells - regs::kActiveCellMin);
      break;
    case code(Op::Frame, kWAdcConf1):
      data[0] = config_.adcConf1;
      break;
    case code(Op::Frame, kWAddress):
      data[0] = loop_;
      reps = slots_;
      break;
    case code(Op::Frame, kWTop): {
      // Value 0 (TI order): base = 0x00, then top = 0x03; a chain of one is base and top at once (0x01).
      // Value 1: move the top to the last device that answered if discovery found fewer than configured.
      const uint8_t n = s.value != 0 ? found_ : configured_;
      reps = s.value != 0 ? (found_ < configured_ ? 1 : 0) : (n == 1 ? 1 : 2);
      single = true;
      if (loop_ + s.value != 0) device = static_cast<uint8_t>(n - 1);
      data[0] = n == 1 ? regs::kCommStandalone : device == 0 ? regs::kCommBase : regs::kCommTop;
      break;
    }
    case code(Op::Frame, kWCrc):
      // Frame loop_ of the CUST_CRC_RSLT response (still in rx_) belongs to device top - loop_.
      single = true;
      device = static_cast<uint8_t>(devices_ - 1 - loop_);
      bytes = rx_ + loop_ * responseSize(2) + 4;
      reps = devices_;
      break;
    case code(Op::Frame, kRDiscover):
      if (loop_ == 0) found_ = 0;
      single = true;
      device = loop_;
      reps = slots_;
      break;
    case code(Op::Frame, kRProbe):
      // A probe passes only for the whole configured chain: a chain that came back short goes on to the rungs
      // that re-discover it.
      if (devices_ < configured_) reps = 0;
      break;
    case code(Op::Frame, kRCrcDone):
      if (loop_ == 0) crcDone_[0] = crcDone_[1] = 0;
      reps = kCrcPolls + 1;  // onRead() ends the step: all done, or Timeout after the last poll
      break;
    case code(Op::Frame, kRScan):
      if ((parts_ & s.value) == 0) {
        reps = 0;
      } else if (localising_) {
        // Per-device fallback, from the base upward, for the devices this part has not validated yet.
        while (loop_ < devices_ && (records_[loop_].valid & s.value) != 0)
          ++loop_;
        single = true;
        device = loop_;
        reps = devices_;
      }
      break;
    default:  // kWBcast, kRVerify, kRCrc, kRFaults
      break;
  }
  if (loop_ >= reps) return s.code == code(Op::Frame, kRDiscover) ? endDiscovery(Status::Ok) : advance();
  uint8_t init;
  size_t rxLen = 0;
  size_t len = n;  // bytes after the register: the data of a write, the byte count of a read
  if (s.code >= code(Op::Frame, kRDllSync)) {
    // frames is never 0: the reads of devices_ run only once discovery found at least one device
    // (startScan(), startClearFaults() and startConfigure() check it, a probe runs only for the whole
    // configured chain).
    if (single) frames = 1;
    reg_ = reg;
    count_ = n;
    frames_ = frames;
    first_ = single ? device : static_cast<uint8_t>(frames - 1);
    faulted_ = kNoDevice;
    rxLen = frames * responseSize(n);
    data[0] = static_cast<uint8_t>(n - 1);
    len = 1;
    init = single ? kInitSingleRead : kInitBroadcastRead;
  } else {
    init = static_cast<uint8_t>((single ? kInitSingleWrite : kInitBroadcastWrite) | (n - 1));
  }
  send(encodeFrame(init, device, reg, bytes, len, tx_), rx_, rxLen);
}

inline void Chain::onBus() {
  const Step& s = *pc_;
  const Status st = exchange_.status;
  if (draining_) {
    // Quiet (NoResponse, Truncated): done. A full buffer means more is coming: drain once more.
    draining_ = st == Status::Ok && ++drained_ < 4;
    return;
  }
  switch (opOf(s)) {
    case Op::Frame:
      if (s.code >= code(Op::Frame, kRDllSync)) return onRead(s);
      if (st != Status::Ok) {
        count(st);
        return fail(st);
      }
      ++loop_;
      return;
    case Op::Drain:
      // Ok means the buffer filled while bytes kept coming: drain again, at most 4 buffers in all.
      if (st != Status::Ok || ++loop_ >= 4) advance();
      return;
    case Op::Raw:
      if (st != Status::Ok) count(st);
      return finish(st);
    default:  // Ping
      return advance();
  }
}

inline void Chain::onRead(const Step& s) {
  Status r = Status::Ok;
  uint8_t dev = first_;
  const size_t size = responseSize(count_);
  size_t left = exchange_.received;
  const uint8_t* f = rx_;
  // The end of the exchange, for the records of a scan's cells: read once, not once a device.
  const Instant exchangeEnd =
      s.code == code(Op::Frame, kRScan) && s.value == kValidCells ? clock_.now() : Instant{};
  uint8_t i = 0;
  for (; i < frames_; ++i, --dev, f += size, left -= size) {
    // Frame i of the response (top of stack first), checked against the device that must send it.
    if (left < size) {
      // The UART ended early: its status says how (NoResponse, Truncated, CommFault).
      r = exchange_.status != Status::Ok ? exchange_.status : Status::Truncated;
    } else {
      r = checkResponse(f, left, reg_, count_);
      if (r == Status::Ok && f[1] != dev) r = Status::DeviceId;
    }
    if (r == Status::Ok && s.code == code(Op::Frame, kRScan)) {
      // Ahead of the switch: a scan's frames are nearly all the frames read, and the switch's table lookup
      // cost each of them a call (twin profile, 64 devices).
      store(s.value, dev, f + 4, exchangeEnd);
    } else if (r == Status::Ok) {
      const uint8_t v = f[4];
      switch (s.code) {
        case code(Op::Frame, kRDiscover):
        case code(Op::Frame, kRVerify):
          if ((v & kMaxAddress) != dev) r = Status::VerifyFailed;
          break;
        case code(Op::Frame, kRProbe):
          // The device answered with its own address (checked above); a chain only counts as recovered if
          // its main ADC still runs (a WAKE or reset in between stops it: scans would never validate).
          if ((v & regs::kDevStatMainRun) == 0) r = Status::NotReady;
          break;
        case code(Op::Frame, kRCrcDone):
          // The first read only clears a CUST_CRC_DONE left from a pass over the old contents (the flag is
          // cleared on read); from the second on, a device that reports it is done.
          if (loop_ != 0 && (v & regs::kDevStatCustCrcDone) != 0) crcDone_[dev >> 5] |= 1U << (dev & 31U);
          break;
        case code(Op::Frame, kRFaults):
          // The lowest stack device with a fault is named: the base's FCOMM_DET only echoes a stack fault.
          if (v != 0 && (dev != 0 || faulted_ == kNoDevice)) {
            faulted_ = dev;
            faultBits_ = v;
          }
          break;
        default:  // kRDllSync, kRCrc
          break;
      }
    }
    // Nothing after a bad frame can be trusted: the frames below it are not looked at.
    if (r != Status::Ok) break;
  }
  stats_.responseFrames += i;  // the frames before the first bad one
  // DLL-sync dummies: TI ignores their responses, and so does the driver.
  if (s.code == code(Op::Frame, kRDllSync)) r = Status::Ok;
  if (r == Status::Ok) {
    attempt_ = 0;
    if (s.code == code(Op::Frame, kRProbe)) {
      level_ = static_cast<RecoveryLevel>(s.value);
      ++stats_.recoveries[s.value];
      pc_ = kRecovered;
      loop_ = 0;
      return;
    }
    if (s.code == code(Op::Frame, kRFaults) && faulted_ != kNoDevice) {
      return fail((faultBits_ & regs::kSummaryFaultComm) != 0 ? Status::CommFault : Status::VerifyFailed,
                  faulted_);
    }
    if (s.code == code(Op::Frame, kRCrcDone)) return crcPolled();
    ++loop_;
    if (s.code == code(Op::Frame, kRDiscover)) found_ = loop_;
    return;  // issue() sends the next frame of the step or moves on
  }
  const bool silent = r == Status::NoResponse;
  // Silence at the address above the configured count is the expected end of discovery, not an error.
  if (!(s.code == code(Op::Frame, kRDiscover) && silent && loop_ >= configured_)) count(r);
  if (!silent) {
    draining_ = true;
    drained_ = 0;
  }
  // One retry of the whole transaction, except for silence in discovery (nothing is there) and for the
  // per-device reads of a scan (the chain read was retried already).
  const bool retry = s.code == code(Op::Frame, kRDiscover)
                         ? !silent
                         : !(s.code == code(Op::Frame, kRScan) && (localising_ || broken_));
  if (attempt_ == 0 && retry) {
    attempt_ = 1;
    ++stats_.retries;
    return;  // run() sends the same frame again
  }
  switch (s.code) {
    case code(Op::Frame, kRDiscover):
      return endDiscovery(r);
    case code(Op::Frame, kRScan):
      if (!localising_) {
        ++stats_.localisations;
        localising_ = true;
        loop_ = 0;
        return;
      }
      markFailed(loop_, r);
      if (silent) {
        // Silence: the link ends below this device, so the ones above it cannot be reached either.
        while (++loop_ < devices_) {
          if ((records_[loop_].valid & s.value) == 0) markFailed(loop_, Status::NoResponse);
        }
      } else {
        ++loop_;
      }
      return;
    case code(Op::Frame, kRProbe):
      lastFault_ = {r, dev};
      return advance();  // the probe failed: next rung of the ladder
    default:
      return fail(r, dev);
  }
}

// A DEV_STAT read of the CRC wait validated: go on once every device has reported CUST_CRC_DONE; otherwise
// poll again after kCrcPollInterval, or, after the last poll, fail with Timeout naming the first device that
// never reported it (not a link error: the stats do not count it).
void Chain::crcPolled() {
  uint8_t d = 0;
  while (d < devices_ && ((crcDone_[d >> 5] >> (d & 31U)) & 1U) != 0)
    ++d;
  if (d == devices_) return advance();
  if (loop_ >= kCrcPolls) return fail(Status::Timeout, d);
  ++loop_;
  wait(Wait::Poll, kCrcPollInterval);
}

void Chain::endDiscovery(Status r) {
  if (found_ == 0) return fail(r, 0);
  const bool fewer = found_ < configured_;
  devices_ = fewer ? found_ : configured_;
  if (found_ != configured_) {
    // Fewer: the chain runs with those, the first missing device (devices_) is named with its error. More:
    // it runs with the configured count, and the first extra device (devices_ again) is named.
    deferred_ = fewer ? Status::CommFault : Status::VerifyFailed;
    lastFault_ = {fewer ? r : Status::VerifyFailed, devices_};
  }
  advance();
}

// --- scans
// --------------------------------------------------------------------------------------------------

namespace {
// Copies `words` (at least 1) big-endian words from `in`, stepping `stride` bytes, to `out`; false if one of
// the first `checked` is not converted (0x8000). Its own function: inside onRead()'s frame loop the compiler
// ran out of registers and took about 40 cycles a word (twin profile, 64 devices). The copy and the check are
// two loops, each with its test at the bottom: in one loop the check's bound and the stride did not fit the
// registers either (31 cycles a word; now 14 for the copy and 8 for the check).
[[gnu::noinline]] bool copyWords(int16_t* out, const uint8_t* in, unsigned words, int stride,
                                 unsigned checked) {
  const uint8_t* const first = in;
  const int16_t* const end = out + words;
  do {
    *out = bytes::loadBeI16(in);
    in += stride;
  } while (++out != end);
  if (checked == 0) return true;
  // 0x8000 tested in the frame's bytes (0x80, then 0x00), compared with immediates: as a halfword GCC loaded
  // the constant again every word.
  static_assert(static_cast<uint16_t>(regs::kNotReady) == 0x8000);
  in = first;
  do {
    if (in[0] == 0x80 && in[1] == 0) return false;
    in += stride;
  } while (--checked != 0);
  return true;
}
}  // namespace

void Chain::store(uint8_t part, uint8_t device, const uint8_t* p, Instant exchangeEnd) {
  DeviceRecord& r = records_[device];
  if (part == kValidFaults) {
    r.faultSummary = p[0];
    faultPending_ = false;
  } else {
    // Big-endian 16-bit words, count_ bytes of them; the cell block starts with VCELL16, so it is read
    // backwards into the record. A measurement that has not been converted (0x8000) is not a value: cells of
    // the active range and die temperatures make the part NotReady. GPIOs keep 0x8000, their usual value
    // when not an ADC input.
    const bool cells = part == kValidCells;
    int16_t* out = cells ? r.cellRaw : part == kValidGpio ? r.gpioRaw : r.dieTemp;
    const unsigned checked = cells ? config_.activeCells : part == kValidGpio ? 0U : 2U;
    const unsigned words = count_ / 2U;
    const int stride = cells ? -2 : 2;
    const uint8_t* in = cells ? p + count_ - 2 : p;
    const bool ready = copyWords(out, in, words, stride, checked);
    if (part == kValidDieTemp) {
      for (unsigned k = 0; k < words; ++k)
        out[k] = dieTempDeciKelvin(out[k]);
    }
    if (!ready) {
      // Left (or, after a retry, made) all zeros.
      std::memset(out, 0, words * sizeof *out);
      r.valid = static_cast<uint8_t>(r.valid & ~part);
      return markFailed(device, Status::NotReady);
    }
    if (cells) r.takenAt = exchangeEnd;
  }
  r.valid = static_cast<uint8_t>(r.valid | part);
}

// A device's part did not validate. Its values are zero already: a record starts the scan zeroed and a part
// is written only when it validates (store()), so only the status is left to set.
void Chain::markFailed(uint8_t device, Status status) {
  DeviceRecord& r = records_[device];
  if (r.status == Status::Ok) r.status = status;
  if (status == Status::NoResponse) broken_ = true;
}

inline void Chain::endScan() {
  ScanSummary& sum = *summary_;
  sum.devices = devices_;
  for (uint8_t d = 0; d < configured_; ++d) {
    DeviceRecord& r = records_[d];
    if (d >= devices_) r.status = Status::NoResponse;  // not in the chain since the last bring-up
    if (r.faultSummary != 0) ++sum.faultedDevices;
    // Every part of the scan either validated for a device or gave it a non-Ok status (issue() and onRead()
    // visit every device below devices_ in each part), so Ok means every part is valid.
    if (r.status == Status::Ok) {
      ++sum.validDevices;
    } else if (sum.firstError.device == kNoDevice) {
      sum.firstError.status = r.status;
      sum.firstError.device = d;
      lastFault_.status = deferred_ = r.status;
      lastFault_.device = d;
    }
  }
  sum.finished = clock_.now();
}

}  // namespace fw::drivers::bq79616
