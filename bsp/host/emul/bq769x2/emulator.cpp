#include "bq769x2/emulator.hpp"

#include <algorithm>
#include <span>

#include "core/bytes.hpp"
#include "core/crc.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq7690x_table.hpp"
#include "regmap/bq769x2.hpp"
#include "regmap/bq769x2_table.hpp"

namespace bsp::host {

namespace {

namespace m2 = fw::regmap::bq769x2;
namespace m7 = fw::regmap::bq7690x;

constexpr uint8_t kAddressW = 0x10;  // the emulator answers at 7-bit 0x08
constexpr uint8_t kSub = 0x3E;
constexpr uint8_t kBuf = 0x40;
constexpr uint8_t kChecksum = 0x60;
constexpr uint8_t kLength = 0x61;

uint8_t crc8(uint8_t crc, uint8_t byte) {
  return fw::crc::crc8Update(crc, byte);
}

int16_t clamp16(int64_t v) {
  return static_cast<int16_t>(std::clamp<int64_t>(v, INT16_MIN, INT16_MAX));
}

// The 0x60 checksum of a subcommand transfer (SLUUBY2B section 13.1): the inverted 8-bit sum of the code's
// two bytes and the data.
uint8_t transferChecksum(uint16_t code, std::span<const uint8_t> data) {
  uint8_t sum = static_cast<uint8_t>(code + (code >> 8));
  for (uint8_t b : data)
    sum = static_cast<uint8_t>(sum + b);
  return static_cast<uint8_t>(~sum);
}

}  // namespace

Bq769xEmulator::Bq769xEmulator(SimClock& clock, Model model, Timing timing)
    : clock_(clock), model_(model), timing_(timing) {
  loadDefaults();
  // The seeds' example readings: SLUAA11B (Cell 1 = 0x0E74 = 3700 mV, internal 298.2 K, CC2 7 mA) and
  // SLAAEB3 (TS1 297.3 K, TS3 297.0 K); SLUAAM4's script output for the BQ7690x (cells 3089/3082/3093 mV,
  // 29 degC, 45 mA).
  if (bq7690x()) {
    const int16_t example[7] = {3089, 3082, 3093, 3089, 3089, 3089, 3089};
    std::copy(example, example + 7, cells_.begin());
    intTemp_ = 29;
    currentMa_ = 45;
    ts_ = {1200, 0, 0};
    deviceNumber_ = model == Model::Bq76907 ? 0x7607 : 0x7605;
  } else {
    cells_.fill(3700);
    intTemp_ = 2982;
    currentMa_ = 7;
    ts_ = {2973, 0, 2970};
    deviceNumber_ = 0x7695;
  }
  powerOn();
}

uint8_t Bq769xEmulator::cellCount() const {
  return model_ == Model::Bq76952 ? 16 : model_ == Model::Bq76907 ? 7 : 5;
}

// --- data memory -------------------------------------------------------------------------------------------

void Bq769xEmulator::loadDefaults() {
  const std::span<const fw::regmap::EntryInfo> table = bq7690x() ? m7::entries : m2::entries;
  uint32_t lo = UINT32_MAX;
  uint32_t hi = 0;
  for (const auto& e : table) {
    if (e.kind != fw::regmap::Kind::DataMemory) continue;
    lo = std::min(lo, e.address);
    hi = std::max(hi, e.address + e.size);
  }
  dmBase_ = static_cast<uint16_t>(lo);
  dm_.assign(hi - lo, 0);
  for (const auto& e : table) {
    if (e.kind != fw::regmap::Kind::DataMemory || !e.hasDefault) continue;
    fw::regmap::encodeRaw(e, e.dflt, std::span<uint8_t>(dm_).subspan(e.address - lo));
  }
  if (bq7690x()) {
    // The BQ7690x Power:Sleep values have no default in the map: the assumed ones (Timing).
    fw::bytes::storeLe16(&dm_[m7::dm::SleepCurrent.address - lo],
                         static_cast<uint16_t>(timing_.sleepCurrent7690xMa));
    dm_[m7::dm::VoltageTime.address - lo] = timing_.sleepVoltageTime7690xS;
  }
  dmDefaults_ = dm_;
}

bool Bq769xEmulator::dmValid(uint16_t address) const {
  return address >= dmBase_ && address < dmBase_ + dm_.size();
}

uint32_t Bq769xEmulator::dataMemory(uint16_t address, uint8_t size) const {
  uint32_t v = 0;
  for (uint8_t i = 0; i < size; ++i) {
    const uint16_t a = static_cast<uint16_t>(address + i);
    if (dmValid(a)) v |= static_cast<uint32_t>(dm_[a - dmBase_]) << (8 * i);
  }
  return v;
}

void Bq769xEmulator::setDataMemory(uint16_t address, uint32_t value, uint8_t size) {
  for (uint8_t i = 0; i < size; ++i) {
    const uint16_t a = static_cast<uint16_t>(address + i);
    if (dmValid(a)) dm_[a - dmBase_] = static_cast<uint8_t>(value >> (8 * i));
  }
  update();
}

// --- power, reset ------------------------------------------------------------------------------------------

void Bq769xEmulator::initRegisters() {
  dm_ = dmDefaults_;
  regs_.fill(0);
  if (commandEvent_ != 0) clock_.cancel(commandEvent_);
  if (bufferEvent_ != 0) clock_.cancel(bufferEvent_);
  if (protectionEvent_ != 0) clock_.cancel(protectionEvent_);
  commandEvent_ = bufferEvent_ = protectionEvent_ = 0;
  running_ = 0;
  writePending_ = false;
  cfgUpdate_ = false;
  por_ = true;
  stopBalancing();  // a reset ends balancing (what it took from the cells stays taken)
  alarmStatus_ = 0;
  alarmRaw_ = 0;
  safetyAlertA_ = 0;
  safetyStatusA_ = 0;
  safetyAlertB_ = 0;
  safetyStatusB_ = 0;
  safetyAlertC_ = 0;
  safetyStatusC_ = 0;
  covSince_ = cuvSince_ = UINT64_MAX;
  occSince_ = ocd1Since_ = ocd2Since_ = scdSince_ = UINT64_MAX;
  occRecoverSince_ = ocdRecoverSince_ = scdlRecoverSince_ = UINT64_MAX;
  scdTrippedAt_ = 0;
  scdlCounter_ = 0;
  lastCommUs_ = clock_.nowUs();
  fetControl_ = 0;
  // SLEEP is allowed after a reset (Power Config[SLEEP], set by default: SLUUBY2B 7.3); the device wakes
  // into NORMAL mode.
  if (sleepEvent_ != 0) clock_.cancel(sleepEvent_);
  sleepEvent_ = 0;
  sleepAllowed_ = true;
  sleeping_ = false;
  relaxSince_ = UINT64_MAX;
  if (bq7690x()) {
    // Alarm Enable and Battery Status[FET_EN] load from Default Alarm Mask and FET Options[FET_EN] (default
    // 0: no autonomous FET control) at reset (SLUUCJ0 Default Alarm Mask, SLUUCI8 Battery Status).
    alarmEnable_ = static_cast<uint16_t>(dataMemory(m7::dm::DefaultAlarmMask.address, 2));
    fetEn_ = (dataMemory(m7::dm::FetOptions.address, 1) & m7::bits::FetOptions::fet_en_mask) != 0;
    hostChgOff_ = hostDsgOff_ = false;
  } else {
    alarmEnable_ = static_cast<uint16_t>(dataMemory(m2::dm::DefaultAlarmMask.address, 2));
    // Manufacturing Status loads from Mfg Status Init (default 0x0040: FET_EN = 0, FET test mode).
    fetEn_ = (dataMemory(m2::dm::MfgStatusInit.address, 2) & m2::bits::ManufacturingStatus::fet_en_mask) != 0;
    const bool initOff =
        (dataMemory(m2::dm::FetOptions.address, 1) & m2::bits::FetOptions::fet_init_off_mask) != 0;
    hostChgOff_ = hostDsgOff_ = initOff;
  }
}

void Bq769xEmulator::powerOn() {
  initRegisters();
  resetCharge();
  nackFirst_ = timing_.nackFirstAfterPowerUp;
  bootUntil_ = clock_.nowUs();
  update();
}

void Bq769xEmulator::reset() {
  ++resets_;
  initRegisters();
  resetCharge();
  bootUntil_ = clock_.nowUs() + timing_.boot.us;
  update();
}

// --- bus face ----------------------------------------------------------------------------------------------

I2cReply Bq769xEmulator::onStart(bool read) {
  I2cReply reply;
  reply.stretch = timing_.ackStretch + stretchOnce_;
  stretchOnce_ = {};
  const bool fresh = !addressed_;
  if (fresh) {
    pending_.clear();
    dropped_ = false;
    dead_ = false;
    haveCommand_ = false;
    expectCrc_ = false;
    dataIndex_ = 0;
  }
  // Not acknowledged: while booting after a reset, while muted, the injected NACKs, and for the rest of a
  // transaction in which the device reset.
  if (clock_.nowUs() < bootUntil_ || dead_ || muted_) {
    reply.ack = false;
    return reply;
  }
  if (nackFirst_ || nackCount_ > 0) {
    if (nackFirst_) {
      nackFirst_ = false;
    } else {
      --nackCount_;
    }
    reply.ack = false;
    return reply;
  }
  if (resetIfDue()) {
    reply.ack = false;
    return reply;
  }
  addressed_ = true;
  reading_ = read;
  // Communication the host watchdog counts (SLUUBY2B 5.2 / SLUUCJ0 6.15: it recovers when communication is
  // received): a transaction the device acknowledged.
  lastCommUs_ = clock_.nowUs();
  const bool hwd = bq7690x() ? (safetyStatusB_ & m7::bits::SafetyB::hwd_mask) != 0
                             : (safetyStatusC_ & m2::bits::SafetyC::hwdf_mask) != 0;
  if (hwd) update();
  if (read) {
    refresh();
    readIndex_ = 0;
    corruptThis_ = corruptIndex_ >= 0 && corruptSkip_ == 0;
    if (corruptSkip_ > 0) --corruptSkip_;
    // The first read CRC covers addr+W, the command, addr+R and the data byte (SLUAA11B section 4).
    crcAcc_ = haveCommand_ ? crc8(crc8(crc8(0, kAddressW), cmd_), kAddressW | 1) : crc8(0, kAddressW | 1);
  }
  return reply;
}

I2cReply Bq769xEmulator::onWrite(uint8_t byte) {
  I2cReply reply;
  reply.stretch = stretchOnce_;
  stretchOnce_ = {};
  // A device that resets while the controller is sending does not acknowledge the byte.
  if (dead_ || resetIfDue()) return {false, reply.stretch};
  if (!haveCommand_) {
    haveCommand_ = true;
    cmd_ = ptr_ = byte;
    crcAcc_ = crc8(crc8(0, kAddressW), byte);
    dataIndex_ = 0;
    return reply;
  }
  if (crc_) {
    if (!expectCrc_) {
      lastData_ = byte;
      expectCrc_ = true;
      return reply;
    }
    expectCrc_ = false;
    const uint8_t expected = crc8(dataIndex_ == 0 ? crcAcc_ : 0, lastData_);
    if (byte != expected) {
      // A wrong CRC: the byte is refused and nothing of this transaction takes effect.
      dropped_ = true;
      reply.ack = false;
      return reply;
    }
    byte = lastData_;
  }
  ++dataIndex_;
  pending_.push_back({ptr_, byte});
  ptr_ = static_cast<uint8_t>((ptr_ + 1) & 0x7F);
  return reply;
}

uint8_t Bq769xEmulator::onRead(fw::Duration& stretch) {
  stretch = stretchOnce_;
  stretchOnce_ = {};
  const int index = readIndex_++;
  uint8_t byte = 0xFF;  // a released SDA
  if (!dead_ && !resetIfDue()) {
    if (!crc_ || index % 2 == 0) {
      byte = readData_ = regs_[ptr_];
      if (straddleEcho_ && ptr_ == kSub && commandEvent_ != 0) {
        straddleEcho_ = false;
        clock_.cancel(commandEvent_);
        commandEvent_ = 0;
        complete(running_);
      }
      ptr_ = static_cast<uint8_t>((ptr_ + 1) & 0x7F);
    } else {
      byte = crc8(index == 1 ? crcAcc_ : 0, readData_);
    }
  }
  if (corruptThis_ && index == corruptIndex_) {
    byte ^= 0x01;
    corruptIndex_ = -1;
  }
  return byte;
}

// Counts one bus byte towards an injected resetAfterBytes(); at the last one the device resets and ignores
// the rest of the transaction. Returns whether it reset.
bool Bq769xEmulator::resetIfDue() {
  if (resetAfter_ <= 0 || --resetAfter_ != 0) return false;
  resetAfter_ = -1;
  reset();
  dead_ = true;
  return true;
}

void Bq769xEmulator::onStop() {
  if (addressed_ && !dropped_ && !dead_ && !pending_.empty()) commit();
  pending_.clear();
  addressed_ = false;
}

void Bq769xEmulator::onBusRecovery() {
  // The controller gave up mid-transaction: nothing it sent is committed.
  pending_.clear();
  addressed_ = false;
}

// --- register writes ---------------------------------------------------------------------------------------

void Bq769xEmulator::commit() {
  bool wroteCode = false;
  bool wroteLength = false;
  std::vector<uint8_t> buffer;
  for (const Pending& p : pending_) {
    const uint8_t a = p.addr;
    if (a == kSub || a == kSub + 1) {
      regs_[a] = p.value;
      if (a == kSub + 1) wroteCode = true;
    } else if (a >= kBuf && a < kChecksum) {
      regs_[a] = p.value;
      buffer.push_back(p.value);
    } else if (a == kChecksum) {
      regs_[a] = p.value;
    } else if (a == kLength) {
      regs_[a] = p.value;
      wroteLength = true;
    } else if (a == 0x62 || a == 0x63) {
      // Alarm Status: writing a 1 clears that latched bit.
      alarmStatus_ &= static_cast<uint16_t>(~(p.value << (a == 0x63 ? 8 : 0)));
    } else if (a == 0x66 || a == 0x67) {
      alarmEnable_ = a == 0x66 ? static_cast<uint16_t>((alarmEnable_ & 0xFF00) | p.value)
                               : static_cast<uint16_t>((alarmEnable_ & 0x00FF) | (p.value << 8));
    } else if (bq7690x() && a == m7::cmd::FetControl.address) {
      // BQ7690x FET Control (SLUUCJ0): kept as written; update() applies the bits FET Options lets act.
      regs_[a] = p.value;
      fetControl_ = p.value;
    }
    // Other direct commands are read-only: a write has no effect.
  }
  if (wroteCode) {
    const uint16_t code = static_cast<uint16_t>(regs_[kSub] | (regs_[kSub + 1] << 8));
    if (buffer.empty()) {
      writePending_ = false;
      startCommand(code);
    } else {
      writeCode_ = code;
      writeData_ = buffer;
      writePending_ = true;
    }
  }
  if (wroteLength && writePending_) executeWrite();
  update();
}

// The 0x60/0x61 commit of a subcommand or data-memory write (SLUUBY2B section 13.1): checksum over the code
// and data, length = data + 4. A wrong one is ignored, as is a data-memory write outside CONFIG_UPDATE.
void Bq769xEmulator::executeWrite() {
  writePending_ = false;
  if (regs_[kChecksum] != transferChecksum(writeCode_, writeData_) ||
      regs_[kLength] != writeData_.size() + 4) {
    ++rejectedWrites_;
    return;
  }
  const uint16_t code = writeCode_;
  executed_.push_back(code);
  uint32_t value = 0;
  for (size_t i = 0; i < writeData_.size() && i < 4; ++i)
    value |= static_cast<uint32_t>(writeData_[i]) << (8 * i);
  if (dmValid(code)) {
    if (!cfgUpdate_) {
      ++rejectedWrites_;
      return;
    }
    for (size_t i = 0; i < writeData_.size(); ++i) {
      if (dmValid(static_cast<uint16_t>(code + i))) dm_[code + i - dmBase_] = writeData_[i];
    }
  } else if (code == m2::sub::CbActiveCells.address) {
    // BQ769x2: bit 0 = cell 1; BQ7690x: bit 1 = cell 1 (SLUAAM4 section 2.4, SLUUCJ0). The rules:
    // balancing.cpp.
    writeBalancing(static_cast<uint16_t>(value));
  } else if (!bq7690x() && code == m2::sub::FetControl.address &&
             (dataMemory(m2::dm::FetOptions.address, 1) & m2::bits::FetOptions::host_fet_en_mask) != 0) {
    // FET_CONTROL (SLUUCW9, E2E 1453973, regmaps/README.md deviation 1): sets every host-off state at once,
    // bit 2 CHG_OFF, bit 0 DSG_OFF (a 0 re-allows the FET); obeyed with FET Options[HOST_FET_EN] as the
    // other host FET commands.
    hostChgOff_ = (value & m2::bits::FetControl::chg_off_mask) != 0;
    hostDsgOff_ = (value & m2::bits::FetControl::dsg_off_mask) != 0;
  }
}

// --- subcommands -------------------------------------------------------------------------------------------

fw::Duration Bq769xEmulator::latencyOf(uint16_t code) const {
  if (latencyOverride_.first == code && latencyOverride_.second.us != 0) return latencyOverride_.second;
  if (!bq7690x() && code == m2::sub::IromSig.address) return timing_.iromSig;
  if (dmValid(code)) return timing_.dataMemory;
  return timing_.subcommand;
}

void Bq769xEmulator::startCommand(uint16_t code) {
  if (commandEvent_ != 0) clock_.cancel(commandEvent_);
  if (bufferEvent_ != 0) clock_.cancel(bufferEvent_);
  bufferEvent_ = 0;
  running_ = code;
  regs_[kSub] = regs_[kSub + 1] = 0xFF;  // busy until the result is in the buffer
  commandEvent_ = clock_.scheduleIn(latencyOf(code), [this, code] {
    commandEvent_ = 0;
    complete(code);
  });
}

void Bq769xEmulator::fillResult(uint16_t code, const uint8_t* data, uint8_t n, uint8_t reportedLen) {
  for (uint8_t i = 0; i < n && i < 32; ++i)
    regs_[kBuf + i] = data[i];
  const size_t covered = reportedLen > 4 ? std::min<size_t>(reportedLen - 4, 32) : 0;
  regs_[kChecksum] = transferChecksum(code, std::span<const uint8_t>(regs_).subspan(kBuf, covered));
  regs_[kLength] = reportedLen;
  if (wrongChecksum_) {
    regs_[kChecksum] ^= 0x5A;
    wrongChecksum_ = false;
  }
  if (wrongLength_ >= 0) {
    regs_[kLength] = static_cast<uint8_t>(wrongLength_);
    wrongLength_ = -1;
  }
}

void Bq769xEmulator::complete(uint16_t code) {
  running_ = 0;
  executed_.push_back(code);
  uint8_t data[32] = {};
  uint8_t n = 0;
  uint8_t reported = 4;
  // Results (SLUUBY2B chapter 4, SLUUCJ0): little-endian words unless noted.
  if (dmValid(code)) {
    for (uint8_t i = 0; i < 32; ++i)
      data[i] = static_cast<uint8_t>(dataMemory(static_cast<uint16_t>(code + i), 1));
    n = 32;
    reported = 36;  // a data-memory read always fills the whole buffer (SLUUBY2B section 13.1: 0x24)
  } else if (code == m2::sub::DeviceNumber.address) {
    fw::bytes::storeLe16(data, deviceNumber_);
    n = 2;
    reported = 6;
  } else if (code == m2::sub::FwVersion.address) {
    // Device number, firmware version, build: three big-endian words. The BQ769x2 reports 11 bytes of
    // which 6 carry data (E2E 1010048).
    const uint8_t fw[7] = {static_cast<uint8_t>(deviceNumber_ >> 8),
                           static_cast<uint8_t>(deviceNumber_),
                           0x01,
                           0x00,
                           0x00,
                           0x35,
                           0x00};
    std::copy(fw, fw + 7, data);
    n = 7;
    reported = bq7690x() ? 10 : 11;
  } else if (code == m2::sub::HwVersion.address) {
    data[0] = 0x00;
    data[1] = 0x02;
    n = 2;
    reported = 6;
  } else if (!bq7690x() && code == m2::sub::IromSig.address) {
    data[0] = 0x3C;
    data[1] = 0xA5;
    n = 2;
    reported = 6;
  } else if (!bq7690x() && code == m2::sub::ManufacturingStatus.address) {
    const uint16_t status = static_cast<uint16_t>(
        (fetEn_ ? m2::bits::ManufacturingStatus::fet_en_mask : 0) |
        (dataMemory(m2::dm::MfgStatusInit.address, 2) & m2::bits::ManufacturingStatus::pf_en_mask));
    fw::bytes::storeLe16(data, status);
    n = 2;
    reported = 6;
  } else if (code == m2::sub::CbActiveCells.address) {
    fw::bytes::storeLe16(data, cbActive_);
    n = bq7690x() ? 1 : 2;
    reported = static_cast<uint8_t>(n + 4);
  } else if (code == (bq7690x() ? m7::sub::Passq.address : m2::sub::Dastatus6.address)) {
    n = fillCharge(data);  // charge.cpp
    reported = static_cast<uint8_t>(n + 4);
  } else if (code == (bq7690x() ? m7::sub::ResetPassq.address : m2::sub::ResetPassq.address)) {
    resetCharge();
  }

  // Command effects.
  if (code == m2::sub::SetCfgupdate.address || code == m2::sub::ExitCfgupdate.address) {
    const bool enter = code == m2::sub::SetCfgupdate.address;
    clock_.scheduleIn(timing_.configUpdate, [this, enter] {
      cfgUpdate_ = enter;
      // EXIT_CFGUPDATE clears Battery Status[POR] (SLUAA11B table 3-2, SLUAAM4 table 3-2); the new settings
      // take effect now (update() reads them). BQ7690x: Alarm Enable reloads from Default Alarm Mask and
      // Battery Status[FET_EN] from FET Options[FET_EN] (SLUUCJ0 Default Alarm Mask, SLUUCI8 Battery
      // Status). BQ769x2: no TI document found says Alarm Enable reloads here; it keeps its value (the safe
      // side: the firmware writes Alarm Enable itself, regmaps/README.md).
      if (!enter) {
        por_ = false;
        if (bq7690x()) {
          alarmEnable_ = static_cast<uint16_t>(dataMemory(m7::dm::DefaultAlarmMask.address, 2));
          fetEn_ = (dataMemory(m7::dm::FetOptions.address, 1) & m7::bits::FetOptions::fet_en_mask) != 0;
        }
      }
      update();
    });
  } else if (code == m2::sub::FetEnable.address) {
    fetEn_ = !fetEn_;  // FET_ENABLE toggles FET_EN
  } else if (code == m2::sub::Reset.address) {
    reset();
    return;
  } else if (code == m2::sub::SleepEnable.address || code == m2::sub::SleepDisable.address) {
    // SLEEP_ENABLE / SLEEP_DISABLE set Battery Status[SLEEP_EN] (SLUUBY2B 7.3); a device in SLEEP leaves it
    // when SLEEP is disallowed (SLUSE14B, SLUSE96: "or through a subcommand"). Ignored in CONFIG_UPDATE: seen
    // on hardware (LibreSolar bms-firmware 82195d2), not in a TI document, and TI's examples send
    // SLEEP_DISABLE after EXIT_CFGUPDATE: the safe side (regmaps/README.md).
    if (!cfgUpdate_) sleepAllowed_ = code == m2::sub::SleepEnable.address;
  } else if (!bq7690x()) {
    // Host FET commands act only with FET Options[HOST_FET_EN] (SLUUBY1B FET Options). Each ALL_FETS_* sets
    // both host-off states; DSG_PDSG_OFF and CHG_PCHG_OFF only add one: after ALL_FETS_OFF neither re-allows
    // the other FET; only ALL_FETS_ON or FET_CONTROL do (SLUUBY2B 5.2.3.2, SLUUCW9 FET_CONTROL).
    const bool hostFets =
        (dataMemory(m2::dm::FetOptions.address, 1) & m2::bits::FetOptions::host_fet_en_mask) != 0;
    if (hostFets && code == m2::sub::AllFetsOn.address) hostChgOff_ = hostDsgOff_ = false;
    if (hostFets && code == m2::sub::AllFetsOff.address) hostChgOff_ = hostDsgOff_ = true;
    if (hostFets && code == m2::sub::DsgPdsgOff.address) hostDsgOff_ = true;
    if (hostFets && code == m2::sub::ChgPchgOff.address) hostChgOff_ = true;
  }

  regs_[kSub] = static_cast<uint8_t>(code);
  regs_[kSub + 1] = static_cast<uint8_t>(code >> 8);
  if (staleLag_.us != 0) {
    // Fault: the echo is there, but the buffer still holds the previous result for a while.
    const fw::Duration lag = staleLag_;
    staleLag_ = {};
    std::vector<uint8_t> saved(data, data + 32);
    bufferEvent_ = clock_.scheduleIn(lag, [this, code, saved, n, reported] {
      bufferEvent_ = 0;
      fillResult(code, saved.data(), n, reported);
    });
  } else {
    fillResult(code, data, n, reported);
  }
  update();
}

// --- the register image ------------------------------------------------------------------------------------

void Bq769xEmulator::put16(uint8_t cmd, uint16_t v) {
  fw::bytes::storeLe16(&regs_[cmd], v);
}

uint8_t Bq769xEmulator::reg(uint8_t cmd) {
  refresh();
  return regs_[cmd & 0x7F];
}

void Bq769xEmulator::refresh() {
  if (!sleeping_) measure();  // in SLEEP the registers hold the last SLEEP measurement (device.cpp)
  const Measured& m = measured_;
  const uint8_t n = cellCount();
  int sum = 0;
  for (uint8_t i = 0; i < n; ++i)
    sum += m.cells[i];
  if (bq7690x()) {
    using B = m7::bits::BatteryStatus;
    regs_[0x02] = safetyAlertA_;
    regs_[0x03] = safetyStatusA_;
    regs_[0x04] = safetyAlertB_;
    regs_[0x05] = safetyStatusB_;
    uint16_t bs = static_cast<uint16_t>(1U << 10);  // SEC = FULLACCESS
    if (safetyStatusA_ != 0 || safetyStatusB_ != 0) bs |= B::ss_mask;
    if (safetyAlertA_ != 0 || safetyAlertB_ != 0) bs |= B::sa_mask;
    if (fetEn_) bs |= B::fet_en_mask;
    if (por_) bs |= B::por_mask;
    if (sleepAllowed_) bs |= B::sleep_en_mask;
    if (sleeping_) bs |= B::sleep_mask;
    if (cfgUpdate_) bs |= B::cfgupdate_mask;
    if (alertAsserted_) bs |= B::alertpin_mask;
    if (chgOn_) bs |= B::chg_mask;
    if (dsgOn_) bs |= B::dsg_mask;
    put16(0x12, bs);
    for (uint8_t i = 0; i < 7; ++i)
      put16(static_cast<uint8_t>(0x14 + 2 * i), static_cast<uint16_t>(i < n ? m.cells[i] : 0));
    put16(0x22, 19153);  // REG18 (SLUAAM4 script output)
    put16(0x24, 3);      // VSS
    put16(0x26, static_cast<uint16_t>(stackOverride_ ? stackRaw_ : clamp16(sum)));
    put16(0x28, static_cast<uint16_t>(m.intTemp));
    put16(0x2A, static_cast<uint16_t>(m.ts[0]));
    put16(0x3A, static_cast<uint16_t>(clamp16(m.currentMa)));
    put16(0x3C, static_cast<uint16_t>(clamp16(m.currentMa)));
  } else {
    using B = m2::bits::BatteryStatus;
    regs_[0x02] = safetyAlertA_;
    regs_[0x03] = safetyStatusA_;
    regs_[0x04] = safetyAlertB_;
    regs_[0x05] = safetyStatusB_;
    regs_[0x06] = safetyAlertC_;
    regs_[0x07] = safetyStatusC_;
    uint16_t bs = static_cast<uint16_t>(1U << 8);  // SEC = FULLACCESS
    if ((safetyStatusA_ | safetyStatusB_ | safetyStatusC_) != 0) bs |= B::ss_mask;
    if (por_) bs |= B::por_mask;
    if (sleepAllowed_) bs |= B::sleep_en_mask;
    if (sleeping_) bs |= B::sleep_mask;
    if (cfgUpdate_) bs |= B::cfgupdate_mask;
    put16(0x12, bs);
    for (uint8_t i = 0; i < 16; ++i)
      put16(static_cast<uint8_t>(0x14 + 2 * i), static_cast<uint16_t>(m.cells[i]));
    // Stack, PACK and LD in userV (DA Configuration[USER_VOLTS_CV]: 10 mV), CC2 in userA (USER_AMPS).
    const uint8_t da = static_cast<uint8_t>(dataMemory(m2::dm::DaConfiguration.address, 1));
    const int vLsb = (da & m2::bits::DaConfiguration::user_volts_cv_mask) != 0 ? 10 : 1;
    const int16_t stack = stackOverride_ ? stackRaw_ : clamp16(sum / vLsb);
    put16(0x34, static_cast<uint16_t>(stack));
    put16(0x36, static_cast<uint16_t>(packRaw_ >= 0 ? packRaw_ : stack));
    put16(0x38, static_cast<uint16_t>(ldRaw_ >= 0 ? ldRaw_ : stack));
    static constexpr int64_t kTenthMaPerLsb[4] = {1, 10, 100, 1000};
    put16(0x3A,
          static_cast<uint16_t>(clamp16(static_cast<int64_t>(m.currentMa) * 10 / kTenthMaPerLsb[da & 3])));
    put16(0x68, static_cast<uint16_t>(m.intTemp));
    put16(0x70, static_cast<uint16_t>(m.ts[0]));
    put16(0x72, static_cast<uint16_t>(m.ts[1]));
    put16(0x74, static_cast<uint16_t>(m.ts[2]));
    using F = m2::bits::FetStatus;
    regs_[0x7F] = static_cast<uint8_t>((chgOn_ ? F::chg_fet_mask : 0) | (dsgOn_ ? F::dsg_fet_mask : 0) |
                                       (alertAsserted_ ? F::alrt_pin_mask : 0));
  }
  put16(0x62, alarmStatus_);
  put16(0x64, alarmRaw_);
  put16(0x66, alarmEnable_);
}

// --- faults ------------------------------------------------------------------------------------------------

void Bq769xEmulator::nackNext(int transactions) {
  nackCount_ = transactions;
}
void Bq769xEmulator::stretchNext(fw::Duration d) {
  stretchOnce_ = d;
}
void Bq769xEmulator::corruptNextRead(uint8_t wireIndex, int skipReads) {
  corruptIndex_ = wireIndex;
  corruptSkip_ = skipReads;
}
void Bq769xEmulator::wrongLengthNext(uint8_t length) {
  wrongLength_ = length;
}
void Bq769xEmulator::wrongChecksumNext() {
  wrongChecksum_ = true;
}
void Bq769xEmulator::staleBufferNext(fw::Duration lag) {
  staleLag_ = lag;
}
void Bq769xEmulator::resetAfterBytes(int bytes) {
  resetAfter_ = bytes;
}

}  // namespace bsp::host
