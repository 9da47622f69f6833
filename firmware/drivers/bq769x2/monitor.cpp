#include "drivers/bq769x2/monitor.hpp"

#include <cstring>

namespace fw::drivers::bq769x2 {

FW_MODULE(Module::DriverBq769x2);

namespace {

namespace sub = map::sub;
using map::bits::Alarm;
using map::bits::BatteryStatus;

// Bits the device always keeps clear (reserved) and sign bits of values that cannot be negative. A released
// SDA (device reset mid-transaction, SLUSE13B section 14) reads 0xFF, which sets them: without CRC this is
// the only way to tell such a tail from data.
constexpr uint8_t high(uint16_t v) {
  return static_cast<uint8_t>(v >> 8);
}
constexpr Check kChecks769x2[] = {
    {9, high(static_cast<uint16_t>(~BatteryStatus::fields_mask))},   // Battery Status bit 14
    {51, high(static_cast<uint16_t>(~Alarm::fields_mask))},          // Alarm Status bit 8
    {70, static_cast<uint8_t>(~map::bits::SafetyA::fields_mask)},    // Safety Alert A bits 1:0
    {71, static_cast<uint8_t>(~map::bits::SafetyA::fields_mask)},    // Safety Status A bits 1:0
    {76, static_cast<uint8_t>(~map::bits::FetStatus::fields_mask)},  // FET Status bit 7
    {43, 0x80},                                                      // Stack Voltage >= 0
    {57, 0x80},
    {59, 0x80},
    {61, 0x80},
    {63, 0x80},
    {65, 0x80},
    {67, 0x80},
    {69, 0x80},  // temperatures >= 0 K
};
constexpr Check kChecks7690x[] = {
    {0, static_cast<uint8_t>(~map7690x::bits::BatteryStatus::fields_mask)},         // Battery Status bit 0
    {1, high(static_cast<uint16_t>(~map7690x::bits::BatteryStatus::fields_mask))},  // bit 9
    {34, static_cast<uint8_t>(~map7690x::bits::SafetyA::fields_mask)},
    {35, static_cast<uint8_t>(~map7690x::bits::SafetyA::fields_mask)},
    {21, 0x80},  // Stack Voltage >= 0
};

constexpr uint8_t kBatteryStatus = map::cmd::BatteryStatus.address;
static_assert(kBatteryStatus == map7690x::cmd::BatteryStatus.address);
static_assert(sub::DeviceNumber.address == map7690x::sub::DeviceNumber.address &&
              sub::FwVersion.address == map7690x::sub::FwVersion.address &&
              sub::SetCfgupdate.address == map7690x::sub::SetCfgupdate.address &&
              sub::ExitCfgupdate.address == map7690x::sub::ExitCfgupdate.address &&
              sub::FetEnable.address == map7690x::sub::FetEnable.address &&
              sub::CbActiveCells.address == map7690x::sub::CbActiveCells.address);

// BQ769x2 host FET subcommands, indexed by FetCommand.
constexpr uint8_t kFetSubcommand[] = {sub::AllFetsOn.address, sub::AllFetsOff.address,
                                      sub::DsgPdsgOff.address, sub::ChgPchgOff.address};
static_assert(sub::AllFetsOn.address < 0x100 && sub::ChgPchgOff.address < 0x100);

// BQ7690x FET Control (SLUUCJ0, "FET Control"): a 1 forces the driver off.
constexpr uint8_t kFet7690xChgOff = 0x08;
constexpr uint8_t kFet7690xDsgOff = 0x04;

}  // namespace

const Variant kBq76952{{{0x0A, 50}, {0x62, 20}, {0x02, 6}, {0x7F, 1}},
                       kChecks769x2,
                       sizeof kChecks769x2 / sizeof kChecks769x2[0],
                       16,
                       BatteryStatus::cfgupdate_mask,
                       0,
                       map::bits::ManufacturingStatus::fet_en_mask,
                       sub::ManufacturingStatus.address,
                       0,
                       2,
                       0};
const Variant kBq76907{{{0x12, 26}, {0x62, 6}, {0x3A, 2}, {0x02, 4}},
                       kChecks7690x,
                       sizeof kChecks7690x / sizeof kChecks7690x[0],
                       7,
                       map7690x::bits::BatteryStatus::cfgupdate_mask,
                       1,
                       high(map7690x::bits::BatteryStatus::fet_en_mask),
                       0,
                       map7690x::cmd::FetControl.address,
                       1,
                       1};
const Variant kBq76905{{{0x12, 26}, {0x62, 6}, {0x3A, 2}, {0x02, 4}},
                       kChecks7690x,
                       sizeof kChecks7690x / sizeof kChecks7690x[0],
                       5,
                       map7690x::bits::BatteryStatus::cfgupdate_mask,
                       1,
                       high(map7690x::bits::BatteryStatus::fet_en_mask),
                       0,
                       map7690x::cmd::FetControl.address,
                       1,
                       1};

Monitor::Monitor(hal::I2cBus& bus, const hal::Clock& clock, const DriverContext& context,
                 const Variant& variant, const MonitorConfig& config)
    : cfgPolls_(config.cfgPolls),
      probeCrc_(config.probeCrc),
      allowAdjacent_(config.allowAdjacentBalancing),
      clock_(clock),
      variant_(variant),
      pollDelay_(config.link.pollInterval),
      link_(bus, context, config.link) {}

Status Monitor::begin(Op op, Status started) {
  if (started == Status::Ok) {
    op_ = op;
    step_ = 0;
  }
  return started;
}

Status Monitor::startProbe(Identity& out) {
  if (busy()) return Status::Busy;
  out_ = &out;
  restarted_ = false;
  if (probeCrc_) link_.setCrc(false);
  return begin(Op::Probe, link_.startSubcommandRead(sub::DeviceNumber.address, 2));
}

Status Monitor::startConfigure(std::span<const Setting> settings) {
  if (settings.empty() || settings.size() > 32) return Status::InvalidArgument;
  if (busy()) return Status::Busy;
  settings_ = settings;
  diff_ = 0;
  index_ = 0;
  written_ = 0;
  error_ = Status::Ok;
  return begin(Op::Configure, nextSetting(false));
}

Status Monitor::startScan(void* record, uint8_t bytes, Instant* takenAt) {
  if (busy()) return Status::Busy;
  uint8_t total = 0;
  for (const ScanBlock& b : variant_.blocks)
    total = static_cast<uint8_t>(total + b.len);
  FW_ASSERT(total <= bytes);
  out_ = record;
  takenAt_ = takenAt;
  bytes_ = 0;
  restarted_ = false;
  scanRetries_ = link_.stats().retries;
  return begin(Op::Scan, link_.startRead(variant_.blocks[0].cmd, variant_.blocks[0].len));
}

Status Monitor::startFet(FetCommand command) {
  if (busy()) return Status::Busy;
  command_ = command;
  return begin(Op::Fet, sendFet());
}

Status Monitor::startFetEnable() {
  if (busy()) return Status::Busy;
  return begin(Op::FetEnable, readFetEn());
}

Status Monitor::startBalance(uint16_t cells) {
  if ((cells >> variant_.cells) != 0 || (!allowAdjacent_ && (cells & (cells >> 1)) != 0))
    return Status::InvalidArgument;
  if (busy()) return Status::Busy;
  tmp_ = static_cast<uint16_t>(cells << variant_.cbShift);
  const uint8_t bytes[2] = {static_cast<uint8_t>(tmp_), static_cast<uint8_t>(tmp_ >> 8)};
  return begin(Op::Balance,
               link_.startSubcommandWrite(sub::CbActiveCells.address, {bytes, variant_.cbBytes}));
}

Progress Monitor::onEvent(sched::EventMask events) {
  const bool running = busy();
  if (link_.onEvent(events) == Progress::Done && busy()) step(link_.result());
  return running && !busy() ? Progress::Done : Progress::Running;
}

Status Monitor::readStatus() {
  return link_.startRead(kBatteryStatus, 2, 0, pollDelay_);
}

Status Monitor::readFetEn() {
  if (variant_.fetEnCode != 0) return link_.startSubcommandRead(variant_.fetEnCode, 2);
  return link_.startRead(kBatteryStatus, 2);
}

Status Monitor::sendFet() {
  if (variant_.fetControlCmd == 0)
    return link_.startSubcommand(kFetSubcommand[static_cast<uint8_t>(command_)]);
  // BQ7690x: the register is written from the intent alone (never from what the FETs report).
  const FetIntent next = nextIntent();
  const uint8_t value = static_cast<uint8_t>((next.chargeOff ? kFet7690xChgOff : 0) |
                                             (next.dischargeOff ? kFet7690xDsgOff : 0));
  return link_.startWrite(variant_.fetControlCmd, {&value, 1});
}

FetIntent Monitor::nextIntent() const {
  FetIntent next = intent_;
  switch (command_) {
    case FetCommand::AllOn:
      next = {};
      break;
    case FetCommand::AllOff:
      next = {true, true};
      break;
    case FetCommand::DischargeOff:
      next.dischargeOff = true;
      break;
    case FetCommand::ChargeOff:
      next.chargeOff = true;
      break;
  }
  return next;
}

void Monitor::step(Status r) {
  const uint8_t* d = link_.data();
  switch (op_) {
    case Op::Idle:
      return;
    case Op::Configure:
      return configStep(r);
    case Op::Probe:
      if (r != Status::Ok) {
        // The first attempt of a CRC probe was made without CRC; a device in CRC mode refuses it at its
        // first missing CRC byte (DataNack), a stale or misframed answer shows as one of the others.
        const bool framing = r == Status::DataNack || r == Status::Crc || r == Status::Checksum ||
                             r == Status::Length || r == Status::EchoMismatch;
        if (!probeCrc_ || step_ != 0 || restarted_ || !framing) return finish(r);
        restarted_ = true;
        link_.setCrc(!link_.crc());
        return (void)link_.startSubcommandRead(sub::DeviceNumber.address, 2);
      }
      if (step_++ == 0) {
        tmp_ = static_cast<uint16_t>(d[0] | (d[1] << 8));
        return (void)link_.startSubcommandRead(sub::FwVersion.address, 6);
      } else {
        Identity& id = *static_cast<Identity*>(out_);
        id.deviceNumber = tmp_;
        std::memcpy(id.fw, d, sizeof id.fw);
        id.crc = link_.crc();
        return finish(Status::Ok);
      }
    case Op::Scan: {
      if (r != Status::Ok) return finish(r);
      bytes_ = static_cast<uint8_t>(bytes_ + variant_.blocks[step_].len);
      if (++step_ < sizeof variant_.blocks / sizeof variant_.blocks[0]) {
        const ScanBlock& b = variant_.blocks[step_];
        return (void)link_.startRead(b.cmd, b.len, bytes_);
      }
      if (link_.stats().retries != scanRetries_ && !restarted_) {
        // A read of this scan had to be repeated: the device may have reset or the bus glitched between
        // reads, so the snapshot is taken again from its first read (once).
        restarted_ = true;
        bytes_ = 0;
        step_ = 0;
        return (void)link_.startRead(variant_.blocks[0].cmd, variant_.blocks[0].len);
      }
      const uint8_t* raw = link_.scratch();
      for (uint8_t i = 0; i < variant_.checkCount; ++i) {
        if ((raw[variant_.checks[i].offset] & variant_.checks[i].mask) != 0)
          return finish(Status::Implausible);
      }
      std::memcpy(out_, raw, bytes_);
      *takenAt_ = clock_.now();
      return finish(Status::Ok);
    }
    case Op::Fet:
      if (r == Status::Ok) intent_ = nextIntent();
      return finish(r);
    case Op::FetEnable: {
      if (r != Status::Ok) return finish(r);
      const bool enabled = (d[variant_.fetEnByte] & variant_.fetEnMask) != 0;
      switch (step_++) {
        case 0:  // FET_EN read: FET_ENABLE toggles it, so it is only sent when FET_EN is 0
          if (enabled) return finish(Status::Ok);
          return (void)link_.startSubcommand(sub::FetEnable.address);
        case 1:  // FET_ENABLE sent: read FET_EN back
          return (void)readFetEn();
        default:
          return finish(enabled ? Status::Ok : Status::VerifyFailed);
      }
    }
    case Op::Balance:
      if (r != Status::Ok) return finish(r);
      if (step_++ == 0) return (void)link_.startSubcommandRead(sub::CbActiveCells.address, variant_.cbBytes);
      return finish(static_cast<uint16_t>(d[0] | (variant_.cbBytes > 1 ? d[1] << 8 : 0)) == tmp_
                        ? Status::Ok
                        : Status::VerifyFailed);
  }
}

// Steps of the CONFIG_UPDATE transaction.
enum : uint8_t { kCompare, kEnter, kEnterPoll, kWrite, kVerify, kExit, kExitPoll };

bool Monitor::matches() const {
  const Setting& s = settings_[index_];
  const uint8_t* d = link_.data();
  for (uint8_t i = 0; i < s.size; ++i) {
    if (d[i] != static_cast<uint8_t>(s.value >> (8 * i))) return false;
  }
  return true;
}

Status Monitor::nextSetting(bool write) {
  const Setting& s = settings_[index_];
  if (!write) return link_.startSubcommandRead(s.address, s.size);
  uint8_t bytes[4];
  for (uint8_t i = 0; i < 4; ++i)
    bytes[i] = static_cast<uint8_t>(s.value >> (8 * i));
  return link_.startSubcommandWrite(s.address, {bytes, s.size});
}

void Monitor::configStep(Status r) {
  if (r != Status::Ok) {
    if (step_ == kCompare) return finish(r);  // nothing was changed yet
    if (step_ < kExit) {
      // Never leave the device in CONFIG_UPDATE (its protections and FETs are stopped there).
      error_ = r;
      return exitUpdate();
    }
    return finish(error_ != Status::Ok ? error_ : r);
  }
  const bool flag = (link_.data()[0] & variant_.cfgUpdateMask) != 0;
  switch (step_) {
    case kCompare:
      if (!matches()) diff_ |= 1UL << index_;
      if (++index_ < settings_.size()) return (void)nextSetting(false);
      if (diff_ == 0) return finish(Status::Ok);
      step_ = kEnter;
      return (void)link_.startSubcommand(sub::SetCfgupdate.address);
    case kEnter:
    case kExit:
      // The command was accepted; its effect shows in Battery Status[CFGUPDATE] (LibreSolar 73bda94: the
      // TRM's timing alone was not enough).
      polls_ = 0;
      ++step_;
      return (void)readStatus();
    case kEnterPoll:
      if (!flag) return pollStatus();
      index_ = 0;
      return writeNext();
    case kWrite:
      ++written_;
      step_ = kVerify;
      return (void)nextSetting(false);
    case kVerify:
      if (!matches()) {
        error_ = Status::VerifyFailed;
        return exitUpdate();
      }
      ++index_;
      return writeNext();
    default:  // kExitPoll
      if (flag) return pollStatus();
      return finish(error_);
  }
}

void Monitor::pollStatus() {
  if (++polls_ < cfgPolls_) return (void)readStatus();
  if (error_ == Status::Ok) error_ = Status::Timeout;
  if (step_ == kEnterPoll) return exitUpdate();
  finish(error_);
}

void Monitor::writeNext() {
  while (index_ < settings_.size() && (diff_ & (1UL << index_)) == 0)
    ++index_;
  if (index_ == settings_.size()) return exitUpdate();
  step_ = kWrite;
  (void)nextSetting(true);
}

void Monitor::exitUpdate() {
  step_ = kExit;
  (void)link_.startSubcommand(sub::ExitCfgupdate.address);
}

void Monitor::finish(Status s) {
  result_ = s;
  op_ = Op::Idle;
}

}  // namespace fw::drivers::bq769x2
