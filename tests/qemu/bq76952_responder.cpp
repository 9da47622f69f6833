#include "bq76952_responder.hpp"

#include <cstring>

#include "drivers/bq769x2/link.hpp"
#include "regmap/bq769x2.hpp"

namespace qbench {
namespace {

namespace map = fw::regmap::bq769x2;
namespace link = fw::drivers::bq769x2;

constexpr uint8_t kAlarmStatus = map::cmd::AlarmStatus.address;
constexpr uint8_t kBatteryStatus = map::cmd::BatteryStatus.address;
constexpr uint8_t kLength = link::kCmdChecksum + 1;
constexpr uint16_t kDmBase = 0x9180;
constexpr uint16_t kDmSize = 0x200;

void storeLe16(uint8_t* at, uint16_t v) {
  at[0] = static_cast<uint8_t>(v);
  at[1] = static_cast<uint8_t>(v >> 8);
}

// 9 bit times per byte at 400 kHz is 22.5 us; start, repeated start and stop add about one byte.
uint32_t wireUsOf(const fw::hal::I2cTransaction& t) {
  const uint32_t bytes = 1 + static_cast<uint32_t>(t.write.size()) + (t.read.empty() ? 0 : 1 + t.read.size());
  return (bytes + 1) * 45 / 2;
}

}  // namespace

Bq76952Responder::Bq76952Responder(const fw::hal::Clock& clock) : regs_{}, dm_{}, clock_(clock) {
  // A healthy 16-cell pack at rest: 3.7 V cells, 59.2 V stack/pack/LD (10 mV units), 25 degC (0.1 K).
  for (uint8_t c = 0; c < 16; ++c)
    storeLe16(&regs_[map::cmd::Cell1Voltage.address + 2 * c], 3700);
  for (uint8_t cmd :
       {map::cmd::StackVoltage.address, map::cmd::PackPinVoltage.address, map::cmd::LdPinVoltage.address})
    storeLe16(&regs_[cmd], 5920);
  for (uint8_t cmd = map::cmd::IntTemperature.address; cmd <= map::cmd::Ts3Temperature.address; cmd += 2)
    storeLe16(&regs_[cmd], 2982);
  regs_[map::cmd::FetStatus.address] =
      map::bits::FetStatus::chg_fet_mask | map::bits::FetStatus::dsg_fet_mask;
}

fw::Status Bq76952Responder::doStart(std::span<fw::hal::I2cTransaction> list, const fw::hal::Notify& done) {
  if (pending_) return fw::Status::Busy;
  if (list.empty()) return fw::Status::InvalidArgument;
  list_ = list;
  done_ = done;
  dueAt_ = clock_.now().us;
  for (const auto& t : list)
    dueAt_ += wireUsOf(t);
  pending_ = true;
  return fw::Status::Ok;
}

void Bq76952Responder::complete() {
  if (!pending_) return;
  for (auto& t : list_) {
    ++transactions_;
    const uint8_t cmd = t.write.empty() ? 0 : t.write[0];
    if (t.write.size() > 1) write(cmd, t.write.subspan(1));
    for (size_t i = 0; i < t.read.size(); ++i)
      t.read[i] = regs_[(cmd + i) & 0x7F];  // reads auto-increment through the direct commands
    t.readCount = static_cast<uint8_t>(t.read.size());
    t.status = fw::Status::Ok;
  }
  pending_ = false;
  done_();
}

void Bq76952Responder::write(uint8_t cmd, std::span<const uint8_t> bytes) {
  if (cmd == kAlarmStatus) {
    for (size_t i = 0; i < bytes.size() && i < 2; ++i)
      regs_[kAlarmStatus + i] = static_cast<uint8_t>(regs_[kAlarmStatus + i] & ~bytes[i]);
    return;
  }
  for (size_t i = 0; i < bytes.size(); ++i)
    regs_[(cmd + i) & 0x7F] = bytes[i];
  const uint16_t code =
      static_cast<uint16_t>(regs_[link::kCmdSubcommand] | regs_[link::kCmdSubcommand + 1] << 8);
  if (cmd == link::kCmdSubcommand && bytes.size() == 2) runSubcommand(code);
  if (cmd == link::kCmdChecksum && bytes.size() == 2) commitWrite();
}

uint8_t Bq76952Responder::dm(uint16_t address) const {
  return address >= kDmBase && address < kDmBase + kDmSize ? dm_[address - kDmBase] : 0;
}

// The result of a subcommand (or data-memory read) in the transfer buffer, with its checksum and length.
void Bq76952Responder::runSubcommand(uint16_t code) {
  uint8_t* buffer = &regs_[link::kCmdBuffer];
  std::memset(buffer, 0, link::kBufferBytes);
  uint8_t n = 0;
  if (code >= kDmBase && code < kDmBase + kDmSize) {
    for (uint8_t i = 0; i < link::kBufferBytes; ++i)
      buffer[i] = dm(static_cast<uint16_t>(code + i));
    n = link::kBufferBytes;
  } else if (code == map::sub::DeviceNumber.address) {
    storeLe16(buffer, 0x7695);
    n = 2;
  } else if (code == map::sub::FwVersion.address) {
    const uint8_t fw[6] = {0x76, 0x95, 0x01, 0x00, 0x00, 0x35};
    std::memcpy(buffer, fw, sizeof fw);
    n = sizeof fw;
  } else if (code == map::sub::ManufacturingStatus.address) {
    storeLe16(buffer, fetEn_ ? map::bits::ManufacturingStatus::fet_en_mask : 0);
    n = 2;
  } else if (code == map::sub::FetEnable.address) {
    fetEn_ = !fetEn_;  // FET_ENABLE 0x0022 toggles FET_EN (SLUUBY2B, FET_ENABLE; SLUAAM4 2.2)
  } else if (code == map::sub::SetCfgupdate.address || code == map::sub::ExitCfgupdate.address) {
    cfgUpdate_ = code == map::sub::SetCfgupdate.address;
    regs_[kBatteryStatus] =
        static_cast<uint8_t>((regs_[kBatteryStatus] & ~map::bits::BatteryStatus::cfgupdate_mask) |
                             (cfgUpdate_ ? map::bits::BatteryStatus::cfgupdate_mask : 0));
  }
  regs_[link::kCmdChecksum] = link::transferChecksum(code, buffer, n);
  regs_[kLength] = static_cast<uint8_t>(n + 4);
}

// The 0x60/0x61 commit of a write with data: checksum over the code and data, length = data + 4.
void Bq76952Responder::commitWrite() {
  const uint16_t code =
      static_cast<uint16_t>(regs_[link::kCmdSubcommand] | regs_[link::kCmdSubcommand + 1] << 8);
  const uint8_t n = static_cast<uint8_t>(regs_[kLength] - 4);
  if (n == 0 || n > link::kBufferBytes ||
      regs_[link::kCmdChecksum] != link::transferChecksum(code, &regs_[link::kCmdBuffer], n))
    return;
  if (!cfgUpdate_ || code < kDmBase || code + n > kDmBase + kDmSize) return;
  std::memcpy(&dm_[code - kDmBase], &regs_[link::kCmdBuffer], n);
}

}  // namespace qbench
