// Gauge: the BQ4050 gas gauge on SMBus (7-bit address 0x0B, 0x16/0x17 on the wire) as a non-blocking driver
// (drivers/operation.hpp).
//
// Every operation is a resumable state machine: start*() schedules its first transaction and returns Ok (or
// Busy while another operation runs or a lost bus completion is still outstanding, InvalidArgument for a bad
// request); the owning task forwards the driver's events to onEvent(), which does one short step per call and
// returns Progress::Done exactly once per started operation; result() then holds its Status. Outputs are
// written only when the operation ends Ok.
//
// Accesses (each one validated access may take several SMBus transactions; "retry" always restarts the
// whole transaction from its START, and a MAC read restarts from its command write):
//   word read      S 16 cmd Sr 17 [lo hi (pec)] P
//   word write     S 16 cmd lo hi (pec) P
//   block read     S 16 cmd Sr 17 [N d1..dN (pec)] P     N bounded by the buffer given (the bus refuses a
//                                                         larger count with Length: it is never trusted)
//   block write    S 16 cmd N d1..dN (pec) P
//   MAC read       S 16 44 02 lo hi (pec) P, then S 16 44 Sr 17 [N lo hi d1..d(N-2) (pec)] P: the echo must
//                  name the subcommand sent (EchoMismatch otherwise), buffers hold count + echo + 32 bytes
//   MAC data read  S 16 00 lo hi (pec) P, then S 16 23 Sr 17 [N d1..dN (pec)] P (ManufacturerData carries no
//                  echo: use it only where a controller cannot take the 35-byte 0x44 block)
//   MAC command    S 16 00 lo hi (pec) P (ManufacturerAccess word write; command-only subcommands)
//   (a MAC write with data, e.g. data flash, is a block write to 0x44 whose data starts with lo hi)
// Validation of every value read: with PEC the bus checks it (Pec otherwise); without PEC each value is read
// until two consecutive reads agree exactly (the confirming read of a MAC result re-reads 0x44 without
// resending the command). Words also pass plausibleWord() (limits.hpp) in both modes. A value that fails is
// never published and is counted (Stats).
//
// Failures and retries: an access absorbs up to config.retries failures (a failed transaction, a rejected
// value, a confirming read that disagreed) and then fails with the status of the last one. Before a retry
// the driver waits: timeoutBackoff after Timeout (the bus has already clocked its 9 recovery pulses; a gauge
// stretching past the limit is writing its flash), nackBackoff after an address Nack (the gauge is waking or
// busy), the pace otherwise; after BusStuck, and after a second transport failure in the same access, it
// calls I2cBus::recover() first. A MAC command is resent only after an address Nack: most are toggles (FET,
// LED...) that would undo themselves if a failure that looked ambiguous had in fact been executed;
// startFetControl() reads the state back instead.
//
// Pace: two transactions are never closer than config.pace (from the end of one to the start of the next,
// across operations too): TI gauges are reported to reset when polled too fast (Zephyr issue #116889,
// bq274xx). The wait is a scheduler timer, never a busy loop. Every bus transaction is also guarded by
// config.busGuard: a completion that never comes ends the operation with Timeout and the driver stays Busy
// until it arrives.
//
// Bus stretch limit (a board setting, SimI2cConfig::stretchLimit / MSPM0 TIMEOUT_CTL): 25 ms. The BQ4050
// may hold SCL low for up to tLOW:SEXT = 25 ms per message (SLUSC67A 6.33), and its own tTIMEOUT is 25..35
// ms; longer stretches (TI documents 40.08 ms for a gauge's data-flash page erase, SLUUCA6) end in Timeout,
// after which the driver waits timeoutBackoff (50 ms > 40.08 ms) and resends.
//
// PEC: config.pec On/Off forces it; Auto leaves it off until startProbe() has read SpecificationInfo (0x1A)
// and found Version = 3, "1.1 with optional PEC support" (SBS 1.1 SpecificationInfo()), as Linux sbs-battery
// does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

#include "core/status.hpp"
#include "core/time.hpp"
#include "core/zeroed.hpp"
#include "drivers/operation.hpp"
#include "hal/clock.hpp"
#include "hal/i2c_bus.hpp"
#include "regmap/bq4050.hpp"
#include "sched/timer.hpp"

namespace fw::drivers::bq4050 {

inline constexpr uint8_t kAddress = 0x0B;                     // 7-bit; 0x16 write / 0x17 read on the wire
inline constexpr uint16_t kDeviceType = 0x4050;               // MAC DeviceType (0x0001) of a BQ4050
inline constexpr size_t kMaxBlock = 32;                       // SMBus block data bytes
inline constexpr size_t kMacEcho = 2;                         // the subcommand echo in front of 0x44 data
inline constexpr size_t kRxBytes = 1 + kMacEcho + kMaxBlock;  // count + echo + 32 data: 35
inline constexpr size_t kMaxCells = 4;
inline constexpr size_t kFirmwareBytes = 11;  // FirmwareVersion: ddDDvvVVbbBBTTzzZZRREE (SLUUAQ3A)

enum class PecMode : uint8_t { Off, On, Auto };

struct GaugeConfig {
  PecMode pec = PecMode::Auto;
  uint8_t cells = 4;                 // series cells the gauge is configured for (1..4): the scan reads these
  uint8_t retries = 3;               // failures an access may absorb before it fails with the last status
  Duration pace = ms(1);             // bus-idle time between two transactions
  Duration timeoutBackoff = ms(50);  // wait after a Timeout before resending
  Duration nackBackoff = ms(5);      // wait after an address NACK
  Duration busGuard = ms(250);       // longest a bus transaction may take before it counts as lost
};

// One scan: every value below validated in the same startScan(), or the record is not written at all.
struct Measurement {
  Instant takenAt{};                // when startScan() was called: every value was read after it
  uint16_t voltageMv = 0;           // Voltage (0x09)
  int16_t currentMa = 0;            // Current (0x0A), positive = charging
  int16_t temperatureDeciK = 0;     // Temperature (0x08), 0.1 K
  uint8_t rsocPercent = 0;          // RelativeStateOfCharge (0x0D)
  uint8_t cellCount = 0;            // cells read (GaugeConfig::cells)
  uint16_t remainingCapacity = 0;   // RemainingCapacity (0x0F): mAh, or 10 mWh with BatteryMode[CAPM]
  uint16_t fullChargeCapacity = 0;  // FullChargeCapacity (0x10), same unit
  uint16_t timeToEmptyMin = 0;      // AverageTimeToEmpty (0x12); 65535 = not discharging
  uint16_t timeToFullMin = 0;       // AverageTimeToFull (0x13); 65535 = not charging
  regmap::bq4050::bits::BatteryStatus batteryStatus{};      // BatteryStatus (0x16)
  int16_t cellMv[kMaxCells] = {};                           // CellVoltage1..4 (0x3F..0x3C); unread cells 0
  regmap::bq4050::bits::SafetyStatus safetyStatus{};        // MAC 0x0051
  uint32_t pfStatus = 0;                                    // MAC 0x0053
  regmap::bq4050::bits::OperationStatus operationStatus{};  // MAC 0x0054 (FET state: CHG, DSG, PCHG)

  std::span<const int16_t> cells() const { return {cellMv, cellCount}; }
  std::span<const int16_t> temperatures() const { return {&temperatureDeciK, 1}; }
  // The gauge's own protection has tripped (or a permanent failure is latched).
  bool deviceFault() const { return safetyStatus.raw() != 0 || pfStatus != 0; }
};

struct DeviceInfo {
  regmap::bq4050::bits::SpecificationInfo specificationInfo{};  // 0x1A
  uint16_t deviceType = 0;                                      // MAC 0x0001: 0x4050
  uint8_t firmware[kFirmwareBytes] = {};                        // MAC 0x0002 as returned
  uint8_t firmwareLength = 0;
  bool pec = false;  // whether the driver now uses PEC
  // Device number and version, decoded with the first byte most significant. SLUUAQ3A's pattern "ddDD"
  // (device number "DDdd") and the BQ40Z50 TRM's "DDdd" disagree on the byte order, so the raw bytes are
  // kept and these two helpers are unverified on hardware.
  uint16_t deviceNumber() const { return static_cast<uint16_t>((firmware[0] << 8) | firmware[1]); }
  uint16_t firmwareVersion() const { return static_cast<uint16_t>((firmware[2] << 8) | firmware[3]); }
};

// FET control through MAC (SLUUAQ3A: FETControl 0x0022, CHGFET 0x001F, DSGFET 0x0020, PCHGFET 0x001E): with
// FET_EN = 1 the gauge's firmware drives CHG/DSG/PCHG (the normal state); with FET_EN = 0 (FET test mode)
// each FET follows its CHG_TEST/DSG_TEST/PCHG_TEST toggle and the gauge no longer opens them itself. All
// commands are toggles: the driver reads ManufacturingStatus (0x0057), toggles one bit that differs
// (FETControl 0x0022, then in test mode off-toggles before on-toggles, DSG before CHG), reads it back, and
// repeats; it ends by reading OperationStatus (0x0054) for the FETs' actual state, which must match a
// test-mode request (VerifyFailed otherwise: TI E2E 1445117 shows a CHG flag set while the FET stays off).
// Sealed gauges ignore these commands (VerifyFailed).
struct FetRequest {
  bool firmwareControl = true;  // FET_EN
  bool chg = false;             // test mode only
  bool dsg = false;
  bool pchg = false;
  static constexpr FetRequest firmware() { return {}; }
  static constexpr FetRequest allOff() { return {false, false, false, false}; }
  static constexpr FetRequest manual(bool chg, bool dsg, bool pchg = false) {
    return {false, chg, dsg, pchg};
  }
};
struct FetState {
  regmap::bq4050::bits::ManufacturingStatus manufacturingStatus{};
  regmap::bq4050::bits::OperationStatus operationStatus{};
  bool firmwareControl() const { return manufacturingStatus.fet_en(); }
  bool chg() const { return operationStatus.chg(); }
  bool dsg() const { return operationStatus.dsg(); }
  bool pchg() const { return operationStatus.pchg(); }
};

// Link statistics since construction.
struct Stats {
  uint32_t transactions;            // SMBus transactions completed (any status)
  uint32_t failures[kStatusCount];  // failed transactions and rejected values, per Status:
                                    // Implausible = a value outside limits.hpp, VerifyFailed = a
                                    // confirming read that differed (or a FET toggle the gauge ignored)
  uint32_t retries;                 // transactions resent after a failure
  uint32_t recoveries;              // I2cBus::recover() calls
  uint32_t scans;                   // scans started
  uint32_t published;               // scans that ended Ok (their record was written)

  uint32_t count(Status s) const { return failures[static_cast<uint8_t>(s)]; }
  uint32_t pecErrors() const { return count(Status::Pec); }
  uint32_t rejected() const { return count(Status::Implausible); }
  uint32_t disagreements() const { return count(Status::VerifyFailed); }
};
// Trivial, so the driver zeroes it with the rest of its state; value-initialise your own copy (Stats s{}).
static_assert(std::is_trivial_v<Stats>);

class Gauge {
 public:
  Gauge(hal::I2cBus& bus, const hal::Clock& clock, const DriverContext& context, const GaugeConfig& config);
  Gauge(const Gauge&) = delete;
  Gauge& operator=(const Gauge&) = delete;

  // SpecificationInfo (PEC detection with PecMode::Auto), DeviceType (DeviceId unless 0x4050),
  // FirmwareVersion.
  Status startProbe(DeviceInfo& out);
  // The measurement record; see Measurement. Result Ok, or the status of the first access that failed. The
  // three status words come through MAC 0x0051/0x0053/0x0054: whether a SEALED BQ4050 answers those is not
  // settled (SLUUAQ3A marks SBS 0x54 "not in SEALED"); a gauge that ignores them leaves an old result, which
  // the echo check (EchoMismatch) or the 4-byte size (Length) refuses.
  Status startScan(Measurement& out);
  // Raw accesses (bmsctl, diagnostics). Block and MAC reads fill out[0..length) and refuse (Length) a count
  // that would not fit `out` (at most 32 bytes are used); a MAC read's `length` excludes the echo.
  Status startReadWord(uint8_t cmd, uint16_t& out);
  Status startWriteWord(uint8_t cmd, uint16_t value);
  Status startReadBlock(uint8_t cmd, std::span<uint8_t> out, uint8_t& length);
  Status startWriteBlock(uint8_t cmd, std::span<const uint8_t> data);  // 1..32 bytes
  Status startReadMac(uint16_t subcommand, std::span<uint8_t> out, uint8_t& length);
  Status startReadMacData(uint16_t subcommand, std::span<uint8_t> out, uint8_t& length);
  Status startSendMac(uint16_t subcommand);
  Status startFetControl(const FetRequest& request, FetState& out);

  sched::EventMask events() const { return ctx_.events(); }
  Progress onEvent(sched::EventMask events);

  bool busy() const { return state_->op != Op::None || state_->busLost; }
  Status result() const { return state_->result; }
  bool pecEnabled() const { return state_->pec; }
  const Stats& stats() const { return buffers_->stats; }
  const GaugeConfig& config() const { return config_; }

 private:
  enum class Op : uint8_t { None, Single, Probe, Scan, Fet };
  enum class Wait : uint8_t { None, Bus, Timer };

  Status begin(Op op);
  uint8_t startRead(std::span<uint8_t> out, uint8_t& length);
  void access(uint8_t txLen, uint8_t readLen, uint8_t flags, uint16_t code = 0, uint8_t exact = 0);
  void readWord(uint8_t command);
  void readMac(uint16_t subcommand, uint8_t capacity, uint8_t exact);
  void sendMac(uint16_t subcommand);
  void macAccess(uint16_t subcommand, uint8_t readLen, uint8_t flags);
  void schedule(Duration gap);
  void issue();
  void onTransaction();
  void fail(Status status, bool transport);
  void accessDone(Status status);
  void nextScan();
  void nextFet(Status status);
  void countAndFinish(Status status);
  void finish(Status status);
  uint16_t word() const;
  const uint8_t* data() const;
  uint8_t dataLength() const;

  // Where an operation's result goes: the member its start function names (state_->op tells which).
  union Output {
    DeviceInfo* info;          // startProbe
    Measurement* measurement;  // startScan
    uint16_t* word;            // startReadWord
    FetState* fet;             // startFetControl
    struct {
      uint8_t* bytes;
      uint8_t* length;
    } block;  // startReadBlock, startReadMac, startReadMacData
  };

  // Everything that changes, in two blocks zeroed at construction. The byte-sized state every step touches
  // comes first: a Cortex-M0+ byte load reaches only 31 bytes past its base register.
  struct State {
    Op op;
    Wait wait;
    bool done;
    bool busLost;
    bool pec;
    bool busUsed;  // a transaction has ended (lastEnd is the pace's reference)
    Status result;
    uint8_t step;  // probe/scan/FET progress
    // The access: its first transaction writes tx[0..txLen); a two-phase access (MAC read) then writes
    // readCmd and reads readLen bytes into rx[cur].
    uint8_t flags;
    uint8_t txLen;
    uint8_t readLen;
    uint8_t readCmd;
    uint8_t exact;  // data bytes a result must have (0: any)
    uint8_t phase;
    uint8_t fails;
    uint8_t cur;        // rx half holding the latest read
    bool candidate;     // without PEC: rx[cur ^ 1] holds an unconfirmed read
    uint8_t fetWant;    // the ManufacturingStatus FET bits requested (FET_EN, or the test bits)
    uint16_t code;      // MAC subcommand of the access
    uint16_t toggled;   // the FET toggle last sent successfully (0: none)
    uint16_t probe[2];  // SpecificationInfo and DeviceType until the probe ends; ManufacturingStatus
    Instant lastEnd;
    Output out;  // the caller's output, written only when the operation ends Ok
  };
  // The large parts, after the members the code reaches by small offsets.
  struct Buffers {
    Stats stats;
    uint8_t scan[sizeof(Measurement)];  // the record being filled (by field offset); copied out whole
    uint8_t tx[2 + kMaxBlock];
    uint8_t rx[2][kRxBytes];
  };

  Zeroed<State> state_;
  hal::I2cBus& bus_;
  const hal::Clock& clock_;
  DriverContext ctx_;
  GaugeConfig config_;
  sched::Timer timer_;
  hal::I2cTransaction txn_;
  hal::Notify busDone_;  // posts ctx_.busEvent to the owning task
  Zeroed<Buffers> buffers_;
};

}  // namespace fw::drivers::bq4050
