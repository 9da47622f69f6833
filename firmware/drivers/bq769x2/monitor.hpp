// Monitor: a BQ769x2 (BQ76952, BQ76942, ...) or BQ7690x (BQ76905, BQ76907) battery monitor on I2C, as a
// non-blocking driver (drivers/operation.hpp) built on the shared protocol layer (link.hpp).
//
// One class serves both families; a Variant (kBq76952, kBq76907, kBq76905) holds what differs: the scan's
// direct commands, the plausibility checks, where CFGUPDATE and FET_EN are reported, how FETs are driven,
// the CB_ACTIVE_CELLS width and the cell count. The typed front ends Bq769x2 and Bq7690x add the
// family's measurement record.
//
// Operations (start*() returns Ok when started, Busy while another operation runs, InvalidArgument for a
// malformed request; then forward events to onEvent() until Progress::Done; result() is the final Status;
// nothing is written to an output unless the operation ends in Ok):
//   startProbe(id)        DEVICE_NUMBER and FW_VERSION through the subcommand window (echo, length and
//                         checksum checked). A NACK right after power-up is retried like any failure
//                         (E2E 1515940). With MonitorConfig::probeCrc the first attempt is made without CRC
//                         (a device with CRC on NACKs it cleanly at its missing CRC byte; a CRC-framed write
//                         to a device without CRC would land as data), and on DataNack, Crc, Checksum,
//                         Length or EchoMismatch the probe tries once more with CRC on. id.crc tells which
//                         mode answered; the link keeps it. BQ7695202 ships with CRC on (E2E 1049966).
//   startConfigure(set)   the CONFIG_UPDATE transaction (SLUUBY2B 13.1, SLUAA11B section 3): read every
//                         setting and compare; if all match, end Ok without entering CONFIG_UPDATE (it stops
//                         protections and FETs). Otherwise SET_CFGUPDATE (0x0090), poll Battery Status until
//                         CFGUPDATE is set (Timeout), write each setting that differed and read it back
//                         (VerifyFailed), EXIT_CFGUPDATE (0x0092), poll until CFGUPDATE is clear (Timeout).
//                         A failure after entering still exits CONFIG_UPDATE before the operation ends with
//                         the first failure. At most kMaxSettings (64) settings; written() counts the writes.
//                         `set` is a SettingsTable (the rows packed as the device takes them, below); an
//                         empty one is InvalidArgument.
//   startScan(m)          (typed front ends) the measurement set in 4 block reads: the `blocks:` of
//                         regmaps/bq769x2 (bq7690x) commands.yaml in their order (<family>::blocks).
//                         A read that needed a retry makes the whole scan start over once (a snapshot is
//                         never stitched across a disturbance). Reserved bits set or a negative stack voltage
//                         or temperature (what a released SDA reads: 0xFF) end it with Implausible. Alarm
//                         Status is latched and holds ALERT asserted until the host writes 1s to its bits
//                         (SLUUBY2B / SLUUCJ0 "Alarm Status"): a scan that read bits set writes exactly those
//                         back (one more transaction, S addr 62 lo hi P), so ALERT releases and the next
//                         event makes a new edge; the record is written after that write succeeded.
//                         yieldScan() makes a running scan end with Aborted instead of starting its next
//                         read (the record is not written): a FET command need not wait for a whole scan.
//                         The accumulated charge (kCharge), every other scan: one scan first writes the
//                         charge subcommand (BQ769x2 DASTATUS6, BQ7690x PASSQ: S addr 3E lo hi P, no echo
//                         poll), the next reads 0x3E..0x4B after its blocks in one transaction (at least
//                         Variant::chargeWaitUs after the write): the echo and the result's first 12 bytes.
//                         The echo naming the subcommand validates them (ChargeCounter::valid; a device still
//                         busy reads FF FF, and a command written in between, e.g. a FET subcommand, names
//                         itself: the charge is left out of that scan, the rest stands). So the BQ76952 scan
//                         is 6 transactions either way (7 after an alarm), within its budget of 6 and 3 ms;
//                         the request scans carry no charge (m.charge.valid false). The device's counter
//                         runs on, so a reading includes all charge since the one before. startScan(m,
//                         false) leaves the charge out (and drops a request made): the subcommand window
//                         then keeps what a command left in it (a balancing read-back waiting for
//                         startBalanceCheck()).
//                         Each read takes at most kScanReadBytes of a block (kScanReadBytesCrc in CRC
//                         mode), so the command waits at most one such read (0.7 ms at 400 kHz).
//   startFet(cmd)         host FET intent: AllOn, AllOff, DischargeOff, ChargeOff, each the whole state of
//                         both paths. BQ769x2: ALL_FETS_ON 0x0096 and ALL_FETS_OFF 0x0095; one path off is
//                         FET_CONTROL 0x0097 with that path's OFF bits (0x03 discharge, 0x0C charge), because
//                         DSG_PDSG_OFF / CHG_PCHG_OFF only add an off state: after ALL_FETS_OFF they would
//                         leave the other path off too (only ALL_FETS_ON or FET_CONTROL re-allow a FET,
//                         SLUUBY2B 5.2.3.2, SLUUCW9 FET_CONTROL). BQ7690x: FET Control written from the
//                         intent (CHG_OFF bit 3, DSG_OFF bit 2, SLUUCJ0; obeyed only with FET Options
//                         [HOST_FETOFF_EN], which the application's settings table sets). fetIntent() is the
//                         host's last accepted command, kept apart from the FET status the device reports
//                         (FET_CONTROL is documented wrongly in SLUUBY2B, E2E 1453973: the driver never
//                         writes a status back as a command).
//   startFetEnable()      leaves FET test mode: reads FET_EN (BQ769x2 MANUFACTURINGSTATUS bit 4, BQ7690x
//                         Battery Status bit 8) and only if it is 0 sends FET_ENABLE (0x0022, which
//                         toggles it) and checks it reads 1 (VerifyFailed). Never toggles it off.
//   startRuntimeSetup(set) what the start-up configuration needs beyond data memory (RAM state a reset
//                         loses, and Alarm Enable): SLEEP_DISABLE (0x009A, as TI's examples send it after
//                         start-up), Battery Status read back (VerifyFailed unless [SLEEP_EN] is clear);
//                         then, if `set` holds a Default Alarm Mask, Alarm Enable (0x66) written with it and
//                         read back (VerifyFailed). In SLEEP the device measures only every
//                         Power:Sleep:Voltage Time (default 5 s, SLUUBY2B 7.3): a 100 ms scan would republish
//                         old values. Alarm Enable: the BQ7690x reloads it from Default Alarm Mask at the
//                         exit of CONFIG_UPDATE (SLUUCJ0), but for the BQ769x2 no TI document found says so
//                         (regmaps/README.md): it is written directly. A reset allows SLEEP again, so Battery
//                         Status[SLEEP_EN] in a scan tells the application that the device lost its RAM
//                         configuration.
//   startSleep(allow)     pack storage (app/monitors/storage_mode.hpp): SLEEP_ENABLE (0x0099) or
//   SLEEP_DISABLE
//                         (0x009A), then Battery Status read back (VerifyFailed unless [SLEEP_EN] says
//                         `allow`). With SLEEP allowed the device enters SLEEP on its own while the CC1
//                         current stays below Power:Sleep:Sleep Current, measures only every Power:Sleep:
//                         Voltage Time there, and leaves it on current above that, a protection alert or
//                         SLEEP_DISABLE (SLUUBY2B 7.3 for the BQ769x2; SLUUCI8 "SLEEP Mode" for the
//                         BQ7690x, the same rules; TI's BQ769x2_protocol.h names both subcommands).
//   startBalance(cells)   CB_ACTIVE_CELLS (0x0083) = bit mask of cells (bit 0 = cell 1; the BQ7690x puts
//                         cell 1 at bit 1 on the wire and keeps bit 0 reserved, SLUAAM4 2.4 / SLUUCJ0
//                         CB_ACTIVE_CELLS), with the 0x60 checksum and 0x61 length the write needs (SLUAA81A,
//                         SLUAAM4 2.4), then CB_ACTIVE_CELLS sent again as a read request (S addr 3E 83 00
//                         P): three short transactions and no wait, so a FET command never waits behind a
//                         poll. yieldScan() ends it with Aborted after the write (the read request is
//                         skipped). Cells beyond the variant's count are InvalidArgument, and so are adjacent
//                         cells on the BQ769x2 unless MonitorConfig::allowAdjacentBalancing: the device
//                         itself never balances neighbours autonomously and two adjacent cells double the
//                         current through the shared input resistor (E2E 1505209). The BQ7690x balances
//                         neighbours (SLUAAP7 section 3: "Adjacent, as well as non-adjacent cells can be
//                         balanced"). 0 stops balancing. The device stops by itself when no write came for a
//                         while (BQ7690x 20 s, SLUAAP7 section 3; BQ769x2 "a few seconds", E2E 958310): the
//                         caller writes again every Variant::cbRefreshS.
//   startBalanceCheck()   the read-back of the last startBalance, at least a scan period later (so the result
//                         is ready: the BQ7690x's 2 ms, LinkConfig::firstPoll, without a wait): one read of
//                         0x3E..0x61. EchoMismatch when 0x3E/0x3F do not echo CB_ACTIVE_CELLS (another
//                         subcommand ran since: send startBalance again), Length / Checksum as a subcommand
//                         read; VerifyFailed when it differs from what was written; balanced() is what it
//                         read.
// A build without the link's configuration paths (FW_BQ769X_CONFIG_PATHS=0, config.hpp) has neither
// startConfigure() nor startBalance(): both return InvalidArgument; a build without balancing
// (FW_BQ769X_BALANCE=0) has no startBalance().
// The link (link()) may be used directly for raw operations while the monitor is idle (bmsctl, diagnostics);
// onEvent() forwards to it either way. The configuration is copied at construction; the settings table
// passed to startConfigure() and the output of a running operation must stay valid until it ends.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/assert.hpp"
#include "core/zeroed.hpp"
#include "drivers/bq769x2/link.hpp"
#include "drivers/bq769x2/measurement.hpp"
#include "hal/clock.hpp"
#include "regmap/descriptor.hpp"

namespace fw::drivers::bq769x2 {

// One data-memory setting of a configuration table, as tables are written (setting() builds one from a
// generated descriptor); the Monitor walks them packed (SettingsTable below).
struct Setting {
  uint16_t address;
  uint8_t size;  // 1..4 (data memory: 1, 2 or 4)
  uint32_t value;
};

// A setting from a data-memory descriptor and a value of its type; a value outside the TRM's min..max is a
// compile error in a constexpr table (and an assert at run time).
template <regmap::ConfigUpdateOnly D>
requires regmap::FixedSize<D> &&(D::size <= 4) constexpr Setting setting(D d, typename D::value_type value) {
  const auto bytes = regmap::encode(d, value);
  uint32_t raw = 0;
  for (size_t i = 0; i < D::size; ++i)
    raw |= static_cast<uint32_t>(bytes[i]) << (8 * i);
  if constexpr (std::is_integral_v<typename D::value_type>) {
    FW_ASSERT_MODULE(::fw::Module::DriverBq769x2, regmap::inRange(d, value));
  }
  return Setting{regmap::code16(d), static_cast<uint8_t>(D::size), raw};
}

// The settings table the Monitor walks (startConfigure, startRuntimeSetup): Setting rows packed back to back,
// each as its size, the address (low byte first) and the value's bytes as the device stores them
// (little-endian), which are the bytes a data-memory write sends after the address (SLUAA11B section 3): a
// row is compared and written straight from the table. 3 + size bytes a row: the BQ76952 image's 50 rows
// take 213 bytes where Setting rows take 400. Only PackedSettings makes one (packedSettings<rows> for a
// constant table, SettingsBuffer for rows made at run time), so a table is well formed by construction.
inline constexpr uint8_t kSettingHeader = 3;  // size, address low, address high

// The most settings a CONFIG_UPDATE table may hold.
inline constexpr uint8_t kMaxSettings = 64;

class SettingsTable {
 public:
  constexpr SettingsTable() = default;  // no settings
  constexpr std::span<const uint8_t> bytes() const { return {bytes_, size_}; }

 private:
  template <size_t>
  friend class PackedSettings;
  constexpr SettingsTable(const uint8_t* bytes, uint16_t size) : bytes_(bytes), size_(size) {}
  const uint8_t* bytes_ = nullptr;
  uint16_t size_ = 0;
};

constexpr size_t packedSize(std::span<const Setting> rows) {
  size_t n = 0;
  for (const Setting& r : rows)
    n += kSettingHeader + r.size;
  return n;
}

// Setting rows packed into at most Capacity bytes. More than kMaxSettings rows, a row that does not fit or
// one whose size is not 1..4 is a compile error in a constexpr table (an assert at run time).
template <size_t Capacity>
class PackedSettings {
 public:
  constexpr PackedSettings() = default;
  constexpr PackedSettings(std::span<const Setting> rows) {  // NOLINT: implicit, as the rows it packs
    FW_ASSERT_MODULE(::fw::Module::DriverBq769x2, rows.size() <= kMaxSettings);
    for (const Setting& r : rows) {
      FW_ASSERT_MODULE(::fw::Module::DriverBq769x2,
                       r.size >= 1 && r.size <= 4 && size_t{used_} + kSettingHeader + r.size <= Capacity);
      bytes_[used_++] = r.size;
      bytes_[used_++] = static_cast<uint8_t>(r.address);
      bytes_[used_++] = static_cast<uint8_t>(r.address >> 8);
      for (uint8_t i = 0; i < r.size; ++i)
        bytes_[used_++] = static_cast<uint8_t>(r.value >> (8 * i));
    }
  }
  constexpr operator SettingsTable() const { return {bytes_, used_}; }  // NOLINT: a view of it

 private:
  uint8_t bytes_[Capacity]{};
  uint16_t used_ = 0;
};
// A constant table packed to its exact size (an image's: the rows themselves stay out of the image).
template <const auto& Rows>
inline constexpr PackedSettings<packedSize(Rows)> packedSettings{Rows};
// Room for any table the Monitor accepts (host tools and tests).
using SettingsBuffer = PackedSettings<kMaxSettings*(kSettingHeader + 4)>;

struct ScanBlock {
  uint8_t cmd;
  uint8_t len;
};
struct Check {
  uint8_t offset;  // byte of the record
  uint8_t mask;    // bits that must read 0
};

struct Variant {
  ScanBlock blocks[4];
  const Check* checks;
  uint8_t checkCount;
  uint8_t cells;
  uint8_t cfgUpdateMask;  // in Battery Status low byte
  uint8_t fetEnByte;      // FET_EN: byte and mask of ...
  uint8_t fetEnMask;
  uint16_t fetEnCode;         // ... this subcommand's result, or of Battery Status when 0
  uint8_t fetControlCmd;      // BQ7690x FET Control direct command; 0: BQ769x2 FET subcommands
  uint8_t cbBytes;            // CB_ACTIVE_CELLS width
  uint8_t cbShift;            // CB_ACTIVE_CELLS bit of cell 1 (BQ7690x: bit 1, E2E 1572792)
  uint8_t sleepEnMask;        // Battery Status[SLEEP_EN] in its low byte
  uint8_t alarmOffset;        // Alarm Status in the scan record
  uint16_t alarmMaskAddress;  // data memory Default Alarm Mask
  uint16_t firstPollUs;       // LinkConfig::firstPoll at least this (BQ7690x: the echo is not documented)
  uint16_t chargeCode;        // the accumulated-charge subcommand (DASTATUS6, PASSQ)
  uint16_t chargeWaitUs;      // its result is read no earlier than this after the request
  bool cbAdjacent;            // the device balances neighbouring cells (BQ7690x, SLUAAP7 section 3)
  uint8_t cbRefreshS;         // CB_ACTIVE_CELLS is written again at least this often (see startBalance)
};

namespace variant_detail {
constexpr uint8_t high(uint16_t v) {
  return static_cast<uint8_t>(v >> 8);
}
// The scan's blocks, generated (regmaps/bq769x2, bq7690x commands.yaml). A byte of the record is a block's
// first byte in it (`record`) plus the member's place in the block; +1 is the high byte of a little-endian
// value.
using V2 = map::blocks::PfStatusAndVoltages;
using T2 = map::blocks::AlarmsAndTemperatures;
using S2 = map::blocks::Safety;
using F2 = map::blocks::Fets;
using V0 = map7690x::blocks::StatusAndVoltages;
using A0 = map7690x::blocks::Alarms;
using C0 = map7690x::blocks::Current;
using S0 = map7690x::blocks::Safety;
// Bits the device always keeps clear (reserved) and sign bits of values that cannot be negative. A released
// SDA (device reset mid-transaction, SLUSE13B section 14) reads 0xFF, which sets them: without CRC this is
// the only way to tell such a tail from data.
inline constexpr Check kChecks769x2[] = {
    {V2::record + V2::offsetBatteryStatus + 1,
     high(static_cast<uint16_t>(~map::bits::BatteryStatus::fields_mask))},
    {T2::record + T2::offsetAlarmStatus + 1, high(static_cast<uint16_t>(~map::bits::Alarm::fields_mask))},
    {S2::record + S2::offsetSafetyAlertA, static_cast<uint8_t>(~map::bits::SafetyA::fields_mask)},
    {S2::record + S2::offsetSafetyStatusA, static_cast<uint8_t>(~map::bits::SafetyA::fields_mask)},
    {F2::record + F2::offsetFetStatus, static_cast<uint8_t>(~map::bits::FetStatus::fields_mask)},
    {V2::record + V2::offsetStackVoltage + 1, 0x80},    // Stack Voltage >= 0
    {T2::record + T2::offsetIntTemperature + 1, 0x80},  // temperatures >= 0 K: Int, CFETOFF ... TS3
    {T2::record + T2::offsetCfetoffTemperature + 1, 0x80},
    {T2::record + T2::offsetDfetoffTemperature + 1, 0x80},
    {T2::record + T2::offsetAlertTemperature + 1, 0x80},
    {T2::record + T2::offsetTs1Temperature + 1, 0x80},
    {T2::record + T2::offsetTs2Temperature + 1, 0x80},
    {T2::record + T2::offsetTs3Temperature + 1, 0x80},
};
// Safety Status A and B and Safety Alert B have no reserved bit (SLUUCJ0: Status A bits 1:0 are CURLATCH and
// REGOUT, real faults); only Safety Alert A keeps bits 1:0 clear (SLUUCI8).
inline constexpr Check kChecks7690x[] = {
    {V0::record + V0::offsetBatteryStatus, static_cast<uint8_t>(~map7690x::bits::BatteryStatus::fields_mask)},
    {V0::record + V0::offsetBatteryStatus + 1,
     high(static_cast<uint16_t>(~map7690x::bits::BatteryStatus::fields_mask))},  // bits 0 and 9
    {S0::record + S0::offsetSafetyAlertA, static_cast<uint8_t>(~map7690x::bits::SafetyAlertA::fields_mask)},
    {V0::record + V0::offsetStackVoltage + 1, 0x80},  // Stack Voltage >= 0
};
static_assert(map7690x::bits::SafetyStatusA::fields_mask == 0xFF &&
              map7690x::bits::SafetyB::fields_mask == 0xFF);
constexpr Variant bq7690x(uint8_t cells) {
  return {.blocks = {{V0::address, V0::size},
                     {A0::address, A0::size},
                     {C0::address, C0::size},
                     {S0::address, S0::size}},
          .checks = kChecks7690x,
          .checkCount = sizeof kChecks7690x / sizeof kChecks7690x[0],
          .cells = cells,
          .cfgUpdateMask = map7690x::bits::BatteryStatus::cfgupdate_mask,
          .fetEnByte = 1,
          .fetEnMask = high(map7690x::bits::BatteryStatus::fet_en_mask),
          .fetEnCode = 0,
          .fetControlCmd = regmap::code8(map7690x::cmd::FetControl),
          .cbBytes = 1,
          .cbShift = 1,
          .sleepEnMask = map7690x::bits::BatteryStatus::sleep_en_mask,
          .alarmOffset = A0::record + A0::offsetAlarmStatus,
          .alarmMaskAddress = regmap::code16(map7690x::dm::DefaultAlarmMask),
          .firstPollUs = 2000,  // 2 ms, as TI's examples wait
          .chargeCode = regmap::code16(map7690x::sub::Passq),
          .chargeWaitUs = 2000,  // as firstPollUs: no TI document gives PASSQ's time
          .cbAdjacent = true,
          .cbRefreshS = 10};  // half the 20 s the device balances after a write (SLUAAP7 section 3)
}
static_assert(map7690x::bits::BatteryStatus::sleep_en_mask < 0x100 &&
              map::bits::BatteryStatus::sleep_en_mask < 0x100);
}  // namespace variant_detail

// Also BQ76942/BQ769142/BQ76922/BQ76972 (set cells via the record).
inline constexpr Variant kBq76952{
    .blocks = {{variant_detail::V2::address, variant_detail::V2::size},
               {variant_detail::T2::address, variant_detail::T2::size},
               {variant_detail::S2::address, variant_detail::S2::size},
               {variant_detail::F2::address, variant_detail::F2::size}},
    .checks = variant_detail::kChecks769x2,
    .checkCount = sizeof variant_detail::kChecks769x2 / sizeof variant_detail::kChecks769x2[0],
    .cells = 16,
    .cfgUpdateMask = map::bits::BatteryStatus::cfgupdate_mask,
    .fetEnByte = 0,
    .fetEnMask = map::bits::ManufacturingStatus::fet_en_mask,
    .fetEnCode = regmap::code16(map::sub::ManufacturingStatus),
    .fetControlCmd = 0,
    .cbBytes = 2,
    .cbShift = 0,
    .sleepEnMask = map::bits::BatteryStatus::sleep_en_mask,
    .alarmOffset = variant_detail::T2::record + variant_detail::T2::offsetAlarmStatus,
    .alarmMaskAddress = regmap::code16(map::dm::DefaultAlarmMask),
    .firstPollUs = 0,
    .chargeCode = regmap::code16(map::sub::Dastatus6),
    .chargeWaitUs = 0,  // the echo says when it is ready (FF FF while it runs)
    .cbAdjacent = false,
    .cbRefreshS =
        1};  // host balancing "only runs a few seconds by default" (E2E 958310; no TRM figure found)
inline constexpr Variant kBq76907 = variant_detail::bq7690x(7);
inline constexpr Variant kBq76905 = variant_detail::bq7690x(5);

// The longest read of a scan, in data bytes, without and with CRC (whose wire carries a CRC byte after each
// data byte): 26 bytes are 30 bytes on the wire with the address and command bytes, 0.68 ms at 400 kHz.
// Even, so a block's parts never split a 16-bit value. The BQ7690x's blocks fit in one read each.
inline constexpr uint8_t kScanReadBytes = 26;
inline constexpr uint8_t kScanReadBytesCrc = 12;

// The family this build's Monitor serves and the CRC-mode probe: drivers/bq769x2/config.hpp.
inline constexpr uint8_t kFamily = FW_BQ769X_FAMILY;
inline constexpr bool kProbeCrc = FW_BQ769X_PROBE_CRC != 0;

struct MonitorConfig {
  LinkConfig link{};
  bool probeCrc = false;                // startProbe tries both CRC modes
  bool allowAdjacentBalancing = false;  // see startBalance
  uint8_t cfgPolls = 40;                // Battery Status polls for CFGUPDATE, one per link pollInterval
};

struct Identity {
  uint16_t deviceNumber = 0;  // DEVICE_NUMBER: 0x7695 BQ76952, 0x7694 BQ76942, 0x7605 BQ76905, 0x7607 ...
  uint8_t fw[6] = {};         // FW_VERSION as read: three big-endian words (SLUUBY2B, SLUUCJ0)
  bool crc = false;           // the CRC mode the device answered in
  uint16_t fwDevice() const { return static_cast<uint16_t>((fw[0] << 8) | fw[1]); }
  uint16_t fwVersion() const { return static_cast<uint16_t>((fw[2] << 8) | fw[3]); }
  uint16_t fwBuild() const { return static_cast<uint16_t>((fw[4] << 8) | fw[5]); }
};

// The state both paths are to be in: DischargeOff is "charge allowed, discharge off", ChargeOff the reverse.
enum class FetCommand : uint8_t { AllOn, AllOff, DischargeOff, ChargeOff };

struct FetIntent {
  bool chargeOff = false;     // the host asked for CHG (and PCHG) off
  bool dischargeOff = false;  // the host asked for DSG (and PDSG) off
};

class Monitor {
 public:
  // The host's FET intent as bits, those of the BQ7690x FET Control (CHG_OFF bit 3, DSG_OFF bit 2, SLUUCJ0),
  // which that family writes as they are.
  static constexpr uint8_t kChargePathOff = 0x08;
  static constexpr uint8_t kDischargePathOff = 0x04;
  static constexpr uint8_t kBothPathsOff = kChargePathOff | kDischargePathOff;

  // Inline: an image constructs it once, and the constructor is then stores only.
  Monitor(hal::I2cBus& bus, const hal::Clock& clock, const DriverContext& context, const Variant& variant,
          const MonitorConfig& config)
      : cfgPolls_(config.cfgPolls),
        probeCrc_(config.probeCrc),
        allowAdjacent_(config.allowAdjacentBalancing),
        clock_(clock),
        variant_(variant),
        link_(bus, context, config.link, us(variant.firstPollUs)) {}
  Monitor(const Monitor&) = delete;
  Monitor& operator=(const Monitor&) = delete;

  Status startProbe(Identity& out);
  Status startConfigure(SettingsTable settings);
  Status startFet(FetCommand command);
  Status startFetEnable();
  Status startRuntimeSetup(SettingsTable settings);
  Status startSleep(bool allow);
  Status startBalance(uint16_t cells);
  Status startBalanceCheck();

  sched::EventMask events() const { return link_.events(); }
  Progress onEvent(sched::EventMask events);

  bool busy() const { return state_->op != Op::Idle; }
  // Task context. A running scan ends (Aborted) when its current read completes; otherwise nothing.
  void yieldScan() { state_->yield = true; }
  Status result() const { return state_->result; }
  FetIntent fetIntent() const {
    return {(state_->intentOff & kChargePathOff) != 0, (state_->intentOff & kDischargePathOff) != 0};
  }
  uint8_t written() const { return state_->written; }   // settings the last startConfigure wrote
  uint16_t balanced() const { return state_->cbRead; }  // CB_ACTIVE_CELLS as startBalanceCheck read it
  Link& link() { return link_; }
  const LinkStats& stats() const { return link_.stats(); }
  // The variant; in a BQ769x2-family build the constant its front end passes (facts()).
  const Variant& variant() const { return kFamily == 1 ? kBq76952 : variant_; }

 protected:
  // `measurement`: a record that is the time stamp followed by `bytes` bytes of registers; `charge`: where
  // the accumulated charge goes, asked for or read (every other scan) when `askCharge`.
  Status startScan(Instant* measurement, uint8_t bytes, ChargeCounter* charge, bool askCharge);
  static constexpr uint8_t scanBytes(const Variant& v) {
    uint8_t total = 0;
    for (const ScanBlock& b : v.blocks)
      total = static_cast<uint8_t>(total + b.len);
    return total;
  }
  // Every read of the scan fits the link's scratch where scanStep() gathers it: after the blocks before it,
  // with a CRC byte after each byte.
  static constexpr bool scanFits(const Variant& v) {
    unsigned at = 0;
    for (const ScanBlock& b : v.blocks) {
      if (b.len > kMaxReadBytes || at + 2u * b.len > kScratchBytes) return false;
      at += b.len;
    }
    return at + 2u * kChargeReadBytes <= kScratchBytes;
  }

 private:
  // Each operation is a step function that runs on every link completion until it calls finish(). The
  // configure and balance operations exist only where the link has the writes they need (kConfigPaths).
  enum class Op : uint8_t {
    Idle,
    Probe,
    Configure,
    Scan,
    Fet,
    FetEnable,
    RuntimeSetup,
    Balance,
    BalanceCheck
  };
  // The variant's facts: constants when the build serves one family (kFamily).
  const Variant& facts() const {
    if constexpr (kFamily == 1) return kBq76952;
    if constexpr (kFamily == 2)
      return kBq76907;  // differs from kBq76905 only in cells: read variant_ for those
    return variant_;
  }
  Status begin(Op op, Status started);
  void step(Status r);
  // The steps of step(), one per operation.
  inline void probeStep(Status r);
  inline void configStep(Status r);
  inline void scanStep(Status r);
  void scanEnd();
  inline void fetStep(Status r);
  inline void fetEnableStep(Status r);
  inline void runtimeSetupStep(Status r);
  inline void balanceStep(Status r);
  inline void balanceCheckStep(Status r);
  const uint8_t* row() const { return state_->settings.bytes().data() + state_->at; }
  void nextRow();
  bool matches() const;
  bool differs() const;
  Status nextSetting(bool write);
  void writeNext();
  void exitUpdate();
  void pollStatus();
  Status readStatus();
  Status readFetEn();
  Status sendFet();
  Status startScanFromTop();
  Status startScanRead();
  void publish();
  void finish(Status s);

  // The operation in progress, zero at construction (one block, no per-member start-up code). Small fields
  // first: Cortex-M0+ byte loads reach only 31 bytes past the object's base register.
  struct State {
    Op op;
    Status result;
    Status error;  // a configure failure kept while CONFIG_UPDATE is being left
    uint8_t step;
    uint8_t index;  // configure: the setting; scan: bytes of the current block read so far
    uint8_t polls;
    uint8_t bytes;
    uint8_t written;
    uint8_t pendingOff;  // the paths the FET command in flight turns off (k*PathOff bits)
    uint8_t intentOff;   // ... and those of the last accepted one: fetIntent()
    bool restarted;
    bool yield;            // the scan ends at its next read boundary
    bool requestCharge;    // this scan asks for the accumulated charge ...
    bool readCharge;       // ... or reads what the previous one asked for
    bool chargeRequested;  // the last scan asked for it (kept between scans)
    bool requesting;       // the charge request is the transaction in flight (at step 0, before block 0)
#if FW_BQ769X_SLEEP
    bool sleepAllowed;  // runtime set-up or startSleep(): the SLEEP_EN the read-back must show
    bool sleepOnly;     // startSleep(): the read-back ends it
#endif
    uint16_t tmp;  // DEVICE_NUMBER while FW_VERSION is read; Alarm Enable while it is verified; the length
                   // of the scan's read in progress
    SettingsTable settings;
    uint16_t at;  // configure: the byte of the current setting's row (state_->index counts the rows)
    union {
      Identity* identity;  // startProbe
      Instant* record;     // startScan: the time stamp, followed by the registers (the front ends' layout)
    } out;
    ChargeCounter* charge;           // startScan
    Instant chargeAsked;             // when a scan asked for the charge
    uint8_t diff[kMaxSettings / 8];  // bit i: setting i differs from the table
    uint32_t scanRetries;
    uint16_t cbRead;     // CB_ACTIVE_CELLS read back by startBalanceCheck (bit 0 = cell 1)
    uint16_t cbWritten;  // CB_ACTIVE_CELLS as the last startBalance wrote it (the wire's layout)
  };

  uint8_t cfgPolls_;
  bool probeCrc_;
  bool allowAdjacent_;
  Zeroed<State> state_;
  const hal::Clock& clock_;
  const Variant& variant_;
  Link link_;  // with its buffers: last
};

// BQ769x2 front end (BQ76952 and its 3..10-cell siblings).
class Bq769x2 : public Monitor {
 public:
  template <uint8_t F = kFamily>
  requires(F != 2)  // not in a build for the BQ7690x family
      Bq769x2(hal::I2cBus& bus, const hal::Clock& clock, const DriverContext& context,
              const MonitorConfig& config = {})
      : Monitor(bus, clock, context, kBq76952, config) {}
  Status startScan(Bq769x2Measurement& out, bool askCharge = true) {
    static_assert(offsetof(Bq769x2Measurement, reg) == sizeof(Instant));
    static_assert(scanBytes(kBq76952) == map::blocks::kRecordSize && scanFits(kBq76952));
    return Monitor::startScan(&out.takenAt, sizeof(Bq769x2Registers), &out.charge, askCharge);
  }
};

// BQ7690x front end: variant kBq76907 (7 cells) or kBq76905 (5 cells).
class Bq7690x : public Monitor {
 public:
  template <uint8_t F = kFamily>
  requires(F != 1)  // not in a build for the BQ769x2 family
      Bq7690x(hal::I2cBus& bus, const hal::Clock& clock, const DriverContext& context, const Variant& variant,
              const MonitorConfig& config = {})
      : Monitor(bus, clock, context, variant, config) {}
  Status startScan(Bq7690xMeasurement& out, bool askCharge = true) {
    static_assert(offsetof(Bq7690xMeasurement, reg) == sizeof(Instant));
    static_assert(scanBytes(kBq76907) == map7690x::blocks::kRecordSize && scanFits(kBq76907));
    return Monitor::startScan(&out.takenAt, sizeof(Bq7690xRegisters), &out.charge, askCharge);
  }
};

}  // namespace fw::drivers::bq769x2
