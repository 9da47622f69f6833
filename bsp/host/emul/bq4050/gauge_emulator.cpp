#include "bq4050/gauge_emulator.hpp"

#include <algorithm>

#include <functional>
#include <optional>

#include "regmap/bq4050.hpp"
#include "regmap/bq4050_table.hpp"

namespace bsp::host {

namespace {

namespace rm = fw::regmap::bq4050;

constexpr uint8_t kWriteAddress = Bq4050Emulator::kAddress << 1;  // 0x16
constexpr uint8_t kReadAddress = kWriteAddress | 1;               // 0x17
constexpr uint8_t kManufacturerAccess = 0x00;
constexpr uint8_t kManufacturerData = 0x23;
constexpr uint8_t kBlockAccess = 0x44;

// ManufacturingStatus / OperationStatus bits (regmap bits:: masks).
constexpr uint16_t kFetEn = rm::bits::ManufacturingStatus::fet_en_mask;
constexpr uint16_t kChgTest = rm::bits::ManufacturingStatus::chg_test_mask;
constexpr uint16_t kDsgTest = rm::bits::ManufacturingStatus::dsg_test_mask;
constexpr uint16_t kPchgTest = rm::bits::ManufacturingStatus::pchg_test_mask;
using Op = rm::bits::OperationStatus;

// CRC-8 table for polynomial 0x07, built once (the emulator's own PEC, not fw::crc).
struct PecTable {
  uint8_t t[256];
  PecTable() {
    for (int n = 0; n < 256; ++n) {
      uint8_t c = static_cast<uint8_t>(n);
      for (int b = 0; b < 8; ++b)
        c = static_cast<uint8_t>((c & 0x80) ? (c << 1) ^ 0x07 : c << 1);
      t[n] = c;
    }
  }
};
const PecTable& pecTable() {
  static const PecTable table;
  return table;
}

const fw::regmap::EntryInfo* sbsEntry(uint8_t command) {
  return fw::regmap::findByAddress(rm::entries, fw::regmap::Kind::Sbs, command);
}

void putLe16(std::vector<uint8_t>& v, uint16_t x) {
  v.push_back(static_cast<uint8_t>(x));
  v.push_back(static_cast<uint8_t>(x >> 8));
}
void putLe32(std::vector<uint8_t>& v, uint32_t x) {
  putLe16(v, static_cast<uint16_t>(x));
  putLe16(v, static_cast<uint16_t>(x >> 16));
}

}  // namespace

uint8_t Bq4050Emulator::pec(const uint8_t* data, size_t length, uint8_t crc) {
  for (size_t i = 0; i < length; ++i)
    crc = pecTable().t[crc ^ data[i]];
  return crc;
}

Bq4050Emulator::Bq4050Emulator() {
  // A healthy 4-cell pack at rest (values in SBS units).
  words_[0x08] = 2982;  // 25.0 degC
  words_[0x09] = 15000;
  words_[0x0A] = 0;
  words_[0x0D] = 80;
  words_[0x0F] = 3200;
  words_[0x10] = 4000;
  words_[0x11] = 0xFFFF;
  words_[0x12] = 0xFFFF;  // not discharging
  words_[0x13] = 0xFFFF;  // not charging
  words_[0x16] = 0x00C0;  // INIT | DSG
  words_[0x17] = 12;
  words_[0x18] = 4400;
  words_[0x19] = 14400;
  words_[0x1A] = 0x0031;  // SBS 1.1 with PEC (Version 3), revision 1
  setCells({3750, 3750, 3750, 3750});
  auto text = [](const char* s) {
    std::vector<uint8_t> v;
    for (; *s != 0; ++s)
      v.push_back(static_cast<uint8_t>(*s));
    return v;
  };
  blocks_[0x20] = text("Texas Inst.");
  blocks_[0x21] = text("bq4050");
  blocks_[0x22] = text("LION");
}

void Bq4050Emulator::attachClock(const SimClock& clock) {
  clock_ = &clock;
  countedUs_ = clock.nowUs();
  residue_ = 0;
}

// Coulomb counting (SLUUAQ3A SBS commands, units in the header): the charge Current() moved since the last
// count, in whole units of RemainingCapacity() (mAh = 3.6e9 mA x us; 10 mWh = 36 J = 3.6e13 mV x mA x us),
// the remainder kept for the next count.
void Bq4050Emulator::count() {
  if (clock_ == nullptr) return;
  const uint64_t now = clock_->nowUs();
  const auto dt = static_cast<int64_t>(now - countedUs_);
  countedUs_ = now;
  if (dt == 0) return;
  const bool energy = (words_[0x03] & 0x8000U) != 0;  // BatteryMode()[CAPM]: 10 mWh instead of mAh
  const auto currentMa = static_cast<int64_t>(static_cast<int16_t>(words_[0x0A]));
  residue_ += currentMa * dt * (energy ? static_cast<int64_t>(words_[0x09]) : 1);
  const int64_t unit = energy ? 36000000000000LL : 3600000000LL;
  const int64_t whole = residue_ / unit;  // toward zero: the remainder keeps its sign
  if (whole == 0) return;
  residue_ -= whole * unit;
  const int64_t full = words_[0x10];
  const int64_t remaining = std::clamp<int64_t>(static_cast<int64_t>(words_[0x0F]) + whole, 0, full);
  words_[0x0F] = static_cast<uint16_t>(remaining);
  if (full > 0) words_[0x0D] = static_cast<uint16_t>((remaining * 100 + full - 1) / full);  // rounded up
}

void Bq4050Emulator::setCell(int cell, uint16_t mv) {
  words_[static_cast<uint8_t>(0x40 - cell)] = mv;  // CellVoltage1 = 0x3F ... CellVoltage4 = 0x3C
}
void Bq4050Emulator::setCells(const std::array<uint16_t, 4>& mv) {
  for (int i = 0; i < 4; ++i)
    setCell(i + 1, mv[static_cast<size_t>(i)]);
}
void Bq4050Emulator::setMacResult(uint16_t subcommand, std::vector<uint8_t> data) {
  macResults_[subcommand] = std::move(data);
}

bool Bq4050Emulator::known(uint8_t command) const {
  return sbsEntry(command) != nullptr;
}
bool Bq4050Emulator::isWord(uint8_t command) const {
  const auto* e = sbsEntry(command);
  return e != nullptr && e->size == 2 && !e->variable;
}

bool Bq4050Emulator::chgFet() const {
  if ((manufacturing_ & kFetEn) != 0) return firmwareChg_;
  // TI E2E 1445117: in test mode the CHG FET does not turn on while DSG is off and the pack is above 16 V.
  return (manufacturing_ & kChgTest) != 0 && !((manufacturing_ & kDsgTest) == 0 && words_[0x09] > 16000);
}
bool Bq4050Emulator::dsgFet() const {
  return (manufacturing_ & kFetEn) != 0 ? firmwareDsg_ : (manufacturing_ & kDsgTest) != 0;
}
bool Bq4050Emulator::pchgFet() const {
  return (manufacturing_ & kFetEn) == 0 && (manufacturing_ & kPchgTest) != 0;
}

uint32_t Bq4050Emulator::operationStatus() const {
  uint32_t v = operationFlags_ & ~(Op::chg_mask | Op::dsg_mask | Op::pchg_mask | Op::sec_mask | Op::cal_mask);
  if (chgFet()) v |= Op::chg_mask;
  if (dsgFet()) v |= Op::dsg_mask;
  if (pchgFet()) v |= Op::pchg_mask;
  v |= (sealed_ ? 3U : 2U) << 8;  // SEC: 3 SEALED, 2 UNSEALED
  if (calibration_) v |= Op::cal_mask;
  return v;
}

// --- faults ----------------------------------------------------------------------------------------------

namespace {

// Which faults act in which phase of a transaction.
bool atAddress(Bq4050Emulator::FaultKind k) {
  return k == Bq4050Emulator::FaultKind::AddressNack;
}
bool atCommand(const Bq4050Emulator::Fault& f) {
  return f.kind == Bq4050Emulator::FaultKind::DataNack ||
         (f.kind == Bq4050Emulator::FaultKind::Stretch && !f.onRead);
}
bool atRead(const Bq4050Emulator::Fault& f) {
  using K = Bq4050Emulator::FaultKind;
  return (f.kind == K::Stretch && f.onRead) || f.kind == K::CorruptByte || f.kind == K::TopBitStuck ||
         f.kind == K::AllOnes || f.kind == K::Asleep || f.kind == K::BlockCount;
}

// Takes the first pending fault that `accept`s and matches `command` (-1 matches any).
bool take(std::deque<Bq4050Emulator::Fault>& faults, int command,
          const std::function<bool(const Bq4050Emulator::Fault&)>& accept, Bq4050Emulator::Fault& out) {
  for (auto it = faults.begin(); it != faults.end(); ++it) {
    if (!accept(*it)) continue;
    if (it->command >= 0 && it->command != command) continue;
    out = *it;
    if (--it->times <= 0) faults.erase(it);
    return true;
  }
  return false;
}

}  // namespace

// --- bus face --------------------------------------------------------------------------------------------

I2cReply Bq4050Emulator::onStart(bool read) {
  if (!read || phase_ == Phase::Idle) {
    // A new transaction (a START, or a read without a write phase).
    ++counters_.transactions;
    written_.clear();
    response_.clear();
    readIndex_ = 0;
    writeRefused_ = false;
    hadPec_ = false;
    hasActive_ = false;
    Fault f;
    if (take(
            faults_, -1, [](const Fault& x) { return atAddress(x.kind); }, f)) {
      phase_ = Phase::Idle;
      return {false, {}};
    }
  }
  if (!read) {
    phase_ = Phase::Writing;
    return {true, {}};
  }
  // Repeated START with the read address: the answer to the command just written.
  ++counters_.reads;
  const int command = written_.empty() ? -1 : written_[0];
  hasActive_ = take(faults_, command, atRead, active_);
  buildResponse();
  phase_ = Phase::Reading;
  return {true, {}};
}

size_t Bq4050Emulator::expectedWriteLength() const {
  if (written_.empty()) return SIZE_MAX;
  const uint8_t command = written_[0];
  if (isWord(command)) return 3;
  if (written_.size() < 2) return SIZE_MAX;  // a block write: the count decides
  return 2 + static_cast<size_t>(written_[1]);
}

I2cReply Bq4050Emulator::onWrite(uint8_t byte) {
  if (phase_ != Phase::Writing || writeRefused_) return {false, {}};
  const size_t index = written_.size();
  written_.push_back(byte);
  I2cReply reply{true, {}};
  if (index == 0) {
    if (!known(byte)) {
      ++counters_.refused;
      writeRefused_ = true;
      return {false, {}};
    }
    hasActive_ = take(faults_, byte, atCommand, active_);
  }
  if (hasActive_ && active_.kind == FaultKind::DataNack && active_.index == index) {
    writeRefused_ = true;
    return {false, {}};
  }
  if (hasActive_ && active_.kind == FaultKind::Stretch && !active_.onRead && active_.index == index) {
    reply.stretch = active_.stretch;
  }
  const size_t expected = expectedWriteLength();
  if (expected != SIZE_MAX && index == expected) {
    // The byte after the data: a PEC over the address byte and everything written (SMBus 2.0 5.4.1.2).
    uint8_t crc = pec(&kWriteAddress, 1);
    crc = pec(written_.data(), expected, crc);
    if (crc != byte) {
      ++counters_.badPec;
      writeRefused_ = true;
      return {false, reply.stretch};
    }
    hadPec_ = true;
  } else if (expected != SIZE_MAX && index > expected) {
    writeRefused_ = true;  // more than the protocol allows
    return {false, reply.stretch};
  }
  return reply;
}

uint8_t Bq4050Emulator::onRead(fw::Duration& stretch) {
  if (phase_ != Phase::Reading) return 0xFF;
  const size_t index = readIndex_++;
  if (hasActive_ && active_.kind == FaultKind::Stretch && active_.onRead && active_.index == index) {
    stretch = active_.stretch;
  }
  return index < response_.size() ? response_[index] : 0xFF;  // past the PEC the line floats high
}

void Bq4050Emulator::onStop() {
  if (phase_ == Phase::Writing && !writeRefused_) execute();
  phase_ = Phase::Idle;
}

void Bq4050Emulator::reset() {
  macCode_ = 0;
  macResult_.clear();
  calibration_ = false;
  manufacturing_ = 0x0018;  // GAUGE_EN | FET_EN, as constructed
  firmwareChg_ = firmwareDsg_ = true;
  phase_ = Phase::Idle;
  written_.clear();
  hasActive_ = false;
}

void Bq4050Emulator::onBusRecovery() {
  ++counters_.recoveries;
  phase_ = Phase::Idle;  // a half-done transaction is abandoned, never executed
}

// --- the gauge -------------------------------------------------------------------------------------------

void Bq4050Emulator::buildResponse() {
  count();  // every word a read returns is that of now
  std::vector<uint8_t> data;
  if (!written_.empty()) {
    const uint8_t command = written_[0];
    if (command == kBlockAccess) {
      data.push_back(static_cast<uint8_t>(2 + macResult_.size()));
      putLe16(data, macCode_);
      data.insert(data.end(), macResult_.begin(), macResult_.end());
    } else if (command == kManufacturerData) {
      data.push_back(static_cast<uint8_t>(macResult_.size()));
      data.insert(data.end(), macResult_.begin(), macResult_.end());
    } else if (isWord(command)) {
      putLe16(data, words_[command]);
    } else {
      std::vector<uint8_t> block;
      if (command >= 0x50 && command <= 0x58) {
        block = macData(static_cast<uint16_t>(command)).value_or(std::vector<uint8_t>{});
      } else if (auto it = blocks_.find(command); it != blocks_.end()) {
        block = it->second;
      }
      data.push_back(static_cast<uint8_t>(block.size()));
      data.insert(data.end(), block.begin(), block.end());
    }
    const uint8_t head[3] = {kWriteAddress, command, kReadAddress};
    const uint8_t crc = pec(data.data(), data.size(), pec(head, 3));
    response_ = data;
    response_.push_back(crc);
  }
  if (!hasActive_) return;
  switch (active_.kind) {
    case FaultKind::CorruptByte:
      if (active_.index < response_.size()) response_[active_.index] ^= active_.value;
      break;
    case FaultKind::TopBitStuck:
      if (response_.size() > 1) response_[1] |= 0x80;
      break;
    case FaultKind::AllOnes:
      if (response_.size() > 1) response_[0] = response_[1] = 0xFF;
      break;
    case FaultKind::Asleep:
      for (auto& b : response_)
        b = 0xFF;
      break;
    case FaultKind::BlockCount:
      if (!response_.empty()) response_[0] = active_.value;
      break;
    default:
      break;
  }
}

void Bq4050Emulator::execute() {
  const size_t expected = expectedWriteLength();
  if (expected == SIZE_MAX || written_.size() < expected) return;  // a command byte alone, a short write
  ++counters_.writes;
  const uint8_t command = written_[0];
  if (command == kManufacturerAccess || command == kBlockAccess) {
    Fault f;
    if (take(
            faults_, command, [](const Fault& x) { return x.kind == FaultKind::DropMacCommand; }, f))
      return;
    if (command == kManufacturerAccess) {
      runMac(static_cast<uint16_t>(written_[1] | (written_[2] << 8)), {});
    } else if (written_[1] >= 2) {
      runMac(static_cast<uint16_t>(written_[2] | (written_[3] << 8)),
             std::vector<uint8_t>(written_.begin() + 4, written_.begin() + static_cast<long>(expected)));
    }
    return;
  }
  const auto* e = sbsEntry(command);
  if (e == nullptr || !fw::regmap::isWritable(e->access)) return;
  if (isWord(command)) {
    words_[command] = static_cast<uint16_t>(written_[1] | (written_[2] << 8));
  } else {
    blocks_[command].assign(written_.begin() + 2, written_.begin() + static_cast<long>(expected));
  }
}

std::optional<std::vector<uint8_t>> Bq4050Emulator::macData(uint16_t subcommand) const {
  if (auto it = macResults_.find(subcommand); it != macResults_.end()) return it->second;
  std::vector<uint8_t> v;
  switch (subcommand) {
    case 0x0001:
      putLe16(v, deviceType_);
      return v;
    case 0x0002:  // ddDDvvVVbbBBTTzzZZRREE: device 0x4050, version 1.03, build 0x002B, CEDV type, ...
      return std::vector<uint8_t>{0x40, 0x50, 0x01, 0x03, 0x00, 0x2B, 0x00, 0x03, 0x85, 0x00, 0x00};
    case 0x0003:
      putLe16(v, 0x0011);
      return v;
    case 0x0006:
      putLe16(v, 0x0100);
      return v;
    case 0x0050:
      putLe32(v, safetyAlert_);
      return v;
    case 0x0051:
      putLe32(v, safetyStatus_);
      return v;
    case 0x0052:
      putLe32(v, 0);
      return v;
    case 0x0053:
      putLe32(v, pfStatus_);
      return v;
    case 0x0054:
      putLe32(v, operationStatus());
      return v;
    case 0x0055:  // ChargingStatus, GaugingStatus: 3 bytes here (fact table: "block 3/4")
    case 0x0056:
      return std::vector<uint8_t>{0, 0, 0};
    case 0x0057:
      putLe16(v, manufacturing_);
      return v;
    case 0x0058:
      return std::vector<uint8_t>(11, 0);
    case 0x0071: {  // DAStatus1: 16 words, 32 bytes (the 34-byte 0x44 case)
      for (int cell = 1; cell <= 4; ++cell)
        putLe16(v, words_[static_cast<uint8_t>(0x40 - cell)]);
      putLe16(v, words_[0x09]);  // BAT
      putLe16(v, words_[0x09]);  // PACK
      for (int i = 0; i < 4; ++i)
        putLe16(v, words_[0x0A]);  // cell currents
      for (int i = 0; i < 6; ++i)
        putLe16(v, 0);  // cell powers, power, average power
      return v;
    }
    case 0x0072:  // DAStatus2: seven 0.1 K temperatures
      for (int i = 0; i < 7; ++i)
        putLe16(v, words_[0x08]);
      return v;
    default:
      return std::nullopt;
  }
}

void Bq4050Emulator::runMac(uint16_t subcommand, const std::vector<uint8_t>& data) {
  (void)data;  // data-flash and key writes are accepted and ignored
  macLog_.push_back(subcommand);
  ++counters_.macCommands;
  auto setEc = [this](uint16_t ec) { words_[0x16] = static_cast<uint16_t>((words_[0x16] & ~0x000F) | ec); };
  if (calibration_ && subcommand != 0xF080) return;  // streaming raw data: nothing else runs
  switch (subcommand) {
    case 0xF081:
      calibration_ = true;
      macCode_ = 0xF081;
      macResult_ = {0x01, 0x00, 0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66};
      setEc(0);
      return;
    case 0xF080:
      calibration_ = false;
      setEc(0);
      return;
    case 0x0022:  // FETControl
      if (sealed_) return setEc(4);
      manufacturing_ ^= kFetEn;
      if ((manufacturing_ & kFetEn) == 0)
        manufacturing_ &= static_cast<uint16_t>(~(kChgTest | kDsgTest | kPchgTest));
      return setEc(0);
    case 0x001E:
    case 0x001F:
    case 0x0020: {
      if (sealed_) return setEc(4);
      if ((manufacturing_ & kFetEn) != 0) return setEc(4);  // only in FET test mode (FET_EN = 0)
      const uint16_t bit = subcommand == 0x001E ? kPchgTest : subcommand == 0x001F ? kChgTest : kDsgTest;
      manufacturing_ ^= bit;
      return setEc(0);
    }
    case 0x0041:  // DeviceReset: test toggles cleared, FET_EN kept (SLUUAQ3A FETControl note)
      manufacturing_ &= static_cast<uint16_t>(~(kChgTest | kDsgTest | kPchgTest));
      return setEc(0);
    case 0x0030:
      sealed_ = true;
      return setEc(0);
    default:
      break;
  }
  if (auto result = macData(subcommand)) {
    macCode_ = subcommand;
    macResult_ = *result;
    return setEc(0);
  }
  setEc(3);  // unsupported command
}

}  // namespace bsp::host
