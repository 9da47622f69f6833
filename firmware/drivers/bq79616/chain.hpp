// Chain: the BQ79616 daisy chain behind one UART, as a non-blocking driver (drivers/operation.hpp).
//
// One Chain object owns the link to the base device (address 0) and the stack devices above it. Every
// operation is a resumable state machine: start*() starts it and returns at once; the owning task forwards
// the driver's events to onEvent(), which does one short step per call; onEvent() returns Progress::Done
// exactly once per started operation, and result() then holds its Status. Every wait is bounded: bus
// exchanges by the UART's first-byte and gap timeouts (plus a guard timer that aborts the UART if its
// completion never comes: Timeout), settling times by the driver's timer. After any read that failed other
// than by silence, the driver receives until the line is quiet before it sends the next frame, so the tail
// of a late or unexpected response never lands in the next one.
//
// Operations (each returns Ok when started, Busy while another runs, InvalidArgument or NotReady):
//   startWake()         WAKE ping 2.25 ms (inside tHLD_WAKE 2.0..2.5 ms with 10 % margin each side), wait
//                       tSU(WAKE_SHUT) max + 10 % = 11 ms, a second WAKE + wait (a chain shut down by a
//                       SHUTDOWN ping only listens after the second), single write CONTROL1[SEND_WAKE] to
//                       the base, then 12 ms per device (TI's example: 12 ms per board; SLUUC56B: 1.6 ms
//                       tone + 10 ms ACTIVE entry) for the configured devices and one more, so discovery
//                       can notice a device beyond the configured count: 36 ms for 2 devices.
//   startAutoAddress()  TI's sequence (SLUSE81E table 9-19): 8 DLL-sync dummy writes, CONTROL1[ADDR_WR],
//                       DIR0_ADDR = 0..N (one address more than configured; writes that reach no device in
//                       ADDR_WR mode are ignored), COMM_CTRL stack/base/top, 8 DLL-sync dummy reads,
//                       FAULT_RST2; then discovery: single reads of DIR0_ADDR from address 0 upward until a
//                       device does not answer, top of stack moved to the last device found, and one
//                       broadcast read of DIR0_ADDR that must return every address, top first.
//                       Result: Ok when the configured count answered; CommFault when fewer did (the chain
//                       then runs with those, lastFault() names the first missing device and its error);
//                       VerifyFailed when a device above the configured count answered (the chain runs
//                       with the configured count and lastFault() names the extra device);
//                       NoResponse/Crc/... when not even the base answered or an address read back wrong.
//   startConfigure()    4.4 ms after addressing (TI waits 4 ms for "AFE settling"), then TI's order for
//                       changing NVM shadow registers: FAULT_MSK2 = MSK_OTP_CRC (mask the
//                       customer CRC fault), ACTIVE_CELL, ADC_CONF1, then the CRC refresh: one DEV_STAT read
//                       to clear a CUST_CRC_DONE left from before the writes, DEV_STAT polled every 1 ms
//                       until every device reports CUST_CRC_DONE (at most 50 polls, then Timeout naming the
//                       device), a broadcast read of CUST_CRC_RSLT and each device's result written to its
//                       CUST_CRC, FAULT_RST1/2 = FF FF; then FAULT_MSK2 = 0 (unmask) and the same refresh
//                       again, because FAULT_MSK2 is inside the CRC itself; last ADC_CTRL1 continuous run
//                       with the cell LPF, and the LPF settling time before the first read.
//   startBringUp()      the three above in order; the result is the worst of them (CommFault with fewer
//                       devices still configures the devices found).
//   startScan(records, summary)
//                       one broadcast read per enabled part: all cells (VCELL16_HI..VCELL1_LO, 32 bytes per
//                       device), die temperatures, GPIO1..8, FAULT_SUMMARY (also read when an nFAULT edge
//                       arrived since the last fault read). Each response frame is checked (CRC, length,
//                       device id in top-first order, register). A failed chain read is retried once as a
//                       whole (not when a device of this scan was already silent); if it fails again the
//                       driver reads the devices that are still missing one by one from the base upward,
//                       stopping at the first device that does not answer (the ones above it are unreachable
//                       and marked NoResponse). So every record holds either validated values (its ValidBits
//                       say which) or zeros and the Status that named its failure; `summary` names the first
//                       failing device. records.size() must be at least the configured device count. Result:
//                       Ok if every configured device validated every part; otherwise the status of the
//                       lowest failing device. Unlike operation.hpp's default, records are written for the
//                       devices that validated even when the scan as a whole fails: a chain reports the
//                       devices that answer.
//   startClearFaults()  broadcast FAULT_RST1/2 = FF FF (base and stack), then reads FAULT_SUMMARY back:
//                       Ok when every device is clear, CommFault (a FAULT_COMM bit stayed) or VerifyFailed
//                       (another fault stayed) naming the device otherwise. Call it deliberately: clearing
//                       on every scan would hide a fault that keeps coming back.
//   startRecovery(from) the recovery ladder from rung `from` on, stopping at the first rung after which the
//                       chain works: (0) drain the line, COMM CLEAR, (1) SLEEPtoACTIVE, each followed by a
//                       probe, a broadcast read of DEV_STAT that passes when every configured device answers
//                       in order and reports DEV_STAT[MAIN_RUN] (a chain that answers but whose ADC stopped
//                       is not recovered: NotReady, next rung); (2) full bring-up (WAKE resets every
//                       register, so re-address and reconfigure), (3) HW_RESET tone up the stack and HW_RESET
//                       ping, then full bring-up. Rungs 0 and 1 end with FAULT_RST2 clearing the
//                       communication faults the recovery itself caused. A caller whose scans still fail
//                       after a recovery starts the next one a rung higher (the application does). Result:
//                       Ok, or the last bring-up's result (e.g. CommFault with fewer devices).
//   startWrite(type, device, reg, data) / startRead(type, device, reg, count, rx)
//                       one raw frame (tools, balancing, diagnostics): a read expects one response frame
//                       for a single read, devices()−1 for a stack read and devices() for a broadcast read;
//                       result() is the UART's status and received() the bytes stored in `rx`. The caller
//                       parses the frames with frame.hpp.
//   startPause(d)       a wait of `d` (at most 1 s) with the bus idle, for a diagnostic's settling time
//   between
//                       raw frames (open_wire.hpp); always Ok at its end.
//
// nFAULT: attachFaultLine() enables the pin's falling-edge notification as `event` to the owning task; the
// task forwards it with the others (events() includes it). An edge only counts in stats() and makes the next
// scan read FAULT_SUMMARY; it never ends an operation.
//
// Memory: the driver keeps one receive buffer for the largest read it makes itself, 64 devices x (32 + 6)
// bytes = 2432 bytes (TI's PrintAllFaults overflowed its buffer; this one is sized for the worst case and a
// read that would not fit is refused, never sent).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/status.hpp"
#include "core/time.hpp"
#include "drivers/bq79616/frame.hpp"
#include "drivers/bq79616/measurement.hpp"
#include "drivers/operation.hpp"
#include "hal/clock.hpp"
#include "hal/gpio.hpp"
#include "hal/uart.hpp"
#include "sched/timer.hpp"

namespace fw::drivers::bq79616 {

struct ChainConfig {
  uint8_t devices = 1;          // devices the pack is built with, 1..64 (discovered and checked at bring-up)
  uint8_t activeCells = 16;     // cells per device, 6..16 (ACTIVE_CELL)
  uint8_t adcConf1 = 0x02;      // ADC_CONF1: LPF_VCELL = 26 Hz as in TI's bring-up
  Duration adcSettle = ms(38);  // LPF settling before the first read (38 ms at 26 Hz, TI)
  uint8_t scanParts = kValidCells | kValidDieTemp | kValidGpio | kValidFaults;  // what startScan reads
};

enum class RecoveryLevel : uint8_t { CommClear = 0, SleepToActive = 1, Rewake = 2, HardwareReset = 3 };

// Ping low times and waits (SLUSE81E §6.6; each chosen inside its window with margin).
inline constexpr Duration kWakePing = us(2250);          // tHLD_WAKE 2.0..2.5 ms
inline constexpr Duration kSleepToActivePing = us(275);  // tUART(StA) 250..300 us
inline constexpr Duration kHwResetPing = ms(40);         // tHLD_HWRST >= 36 ms
inline constexpr Duration kCommClearPing = us(18);       // tUART(CLR) 15..20 bit periods at 1 Mbaud
inline constexpr size_t kRxBufferBytes = kMaxDevices * responseSize(32);

namespace detail {

enum class Wait : uint8_t { None, Bus, Timer, Poll };  // Poll: a timer, then the same step again
struct Step;  // one instruction of a bring-up/scan/recovery script (chain.cpp)

// Chain's state: an implementation detail of chain.cpp, not part of the interface. It is a base class of
// trivially copyable members so that Chain's constructor clears all of it with one memset instead of code per
// member. The state the interpreter touches on every step comes first: on Cortex-M0+ a byte load reaches only
// 31 bytes past its base register and a word load 124.
struct ChainState {
  // Bytes 0..31.
  uint8_t loop_;        // progress inside the step (address, device, register, repetition)
  uint8_t attempt_;     // 0 = first try, 1 = the retry
  bool localising_;     // a scan part reads the devices still missing one by one
  bool broken_;         // a device of this scan did not answer at all: no whole-chain retries
  bool draining_;       // a read failed: receive until the line is quiet before the next bus step
  uint8_t drained_;     // receive buffers drained so far
  bool active_;         // an operation runs
  Wait waiting_;        // what the running operation waits for
  uint8_t devices_;     // devices in use (0 before bring-up)
  uint8_t configured_;  // config_.devices
  uint8_t slots_;       // addresses to assign: one more than configured (at most 64)
  uint8_t parts_;       // ValidBits this scan reads
  uint8_t first_;       // device of the first response frame expected (top of stack first)
  uint8_t frames_;      // response frames expected
  uint8_t count_;       // register bytes per response frame of the read in flight
  Status deferred_;     // a non-fatal failure reported when the operation ends
  bool singlePhase_;    // startWake()/startAutoAddress()/startConfigure(): end at the phase's end
  bool faultPending_;   // an nFAULT edge since FAULT_SUMMARY was last read
  uint8_t faulted_;     // FAULT_SUMMARY read of startClearFaults(): the device named
  uint8_t faultBits_;   // and its FAULT_SUMMARY
  uint8_t found_;       // devices that answered discovery
  RecoveryLevel level_;
  Status result_;
  uint8_t txLen_;  // length of the frame startRead()/startWrite() encoded
  FaultReport lastFault_;
  uint16_t reg_;  // register of the read in flight
  // Words.
  const Step* pc_;   // the step running
  const Step* ret_;  // where a nested bring-up returns to (recovery)
  DeviceRecord* records_;
  ScanSummary* summary_;
  uint32_t crcDone_[2];  // devices that reported CUST_CRC_DONE in the CRC wait, one bit each
  std::span<uint8_t> userRx_;
  Duration pause_;  // startPause()'s wait
  hal::EdgeInput* nfault_;
  sched::EventMask faultEvent_;
  hal::UartExchange exchange_;
  hal::Notify busDone_;  // the driver context's busNotify(), made once
  ChainConfig config_;
  LinkStats stats_;
  sched::Timer timer_;
};

}  // namespace detail

class Chain : private detail::ChainState {
 public:
  // Preconditions (FW_ASSERT): config.devices 1..64, config.activeCells 6..16, distinct non-zero bus and
  // timer events, a UART of at least 250 kbaud. `uart`, `clock` and the scheduler must outlive the driver.
  Chain(hal::Uart& uart, const hal::Clock& clock, const DriverContext& context, const ChainConfig& config);
  Chain(const Chain&) = delete;
  Chain& operator=(const Chain&) = delete;

  void attachFaultLine(hal::EdgeInput& nfault, sched::EventMask event);

  Status startWake();
  Status startAutoAddress();
  Status startConfigure();
  Status startBringUp();
  Status startScan(std::span<DeviceRecord> records, ScanSummary& summary);
  Status startClearFaults();
  Status startRecovery(RecoveryLevel from = RecoveryLevel::CommClear);
  Status startWrite(RequestType type, uint8_t device, uint16_t reg, std::span<const uint8_t> data);
  Status startRead(RequestType type, uint8_t device, uint16_t reg, uint8_t count, std::span<uint8_t> rx);
  Status startPause(Duration d);
  // The chain's own receive buffer (kRxBufferBytes), lent to a caller's startRead() while no scan or
  // bring-up runs: the next scan overwrites it, so the caller reads its answer as soon as the read ends.
  std::span<uint8_t> receiveBuffer() { return rx_; }

  sched::EventMask events() const { return ctx_.events() | faultEvent_; }
  Progress onEvent(sched::EventMask events);

  bool busy() const { return active_; }
  Status result() const { return result_; }
  size_t received() const { return exchange_.received; }
  uint8_t devices() const { return devices_; }           // devices in use (0 before bring-up)
  uint8_t discovered() const { return found_; }          // devices that answered discovery
  FaultReport lastFault() const { return lastFault_; }   // the device and error behind the last failure
  RecoveryLevel lastRecovery() const { return level_; }  // the rung the last startRecovery() reached
  bool faultLineActive() const { return nfault_ != nullptr && !nfault_->level(); }
  const LinkStats& stats() const { return stats_; }
  const ChainConfig& config() const { return config_; }

  using Step = detail::Step;

 private:
  using Wait = detail::Wait;

  Status begin(const Step* script, bool singlePhase);
  void run();
  void advance();
  void finish(Status status);
  void fail(Status status, uint8_t device = kNoDevice);
  void unwind(Status status);
  void count(Status status);
  void wait(Wait what, Duration d);
  void started(Status status, Duration guard);
  void send(size_t txLen, uint8_t* rx, size_t rxLen);
  void issue(const Step& s);
  void onBus();
  void onRead(const Step& s);
  void endDiscovery(Status r);
  void crcPolled();
  void store(uint8_t part, uint8_t device, const uint8_t* data, Instant exchangeEnd);
  void markFailed(uint8_t device, Status status);
  void endScan();

  hal::Uart& uart_;
  const hal::Clock& clock_;
  DriverContext ctx_;

  // Left uninitialised on purpose: written before every use (a static object's are zero anyway), which
  // keeps 2.4 KB of zeroing out of the constructor.
  uint8_t tx_[kMaxCommandBytes];
  uint8_t rx_[kRxBufferBytes];
};

}  // namespace fw::drivers::bq79616
