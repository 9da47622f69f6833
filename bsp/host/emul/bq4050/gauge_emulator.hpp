// Bq4050Emulator: an SBS gas gauge (BQ4050) on the simulated SMBus, for host tests and bmsctl. Two faces:
//   - the bus face, a bsp::host::I2cTarget at 7-bit address 0x0B: it sees every byte the controller drives
//     and answers byte by byte, as the gauge's SMBus engine does;
//   - the backend face for tests: the pack's values, the status registers, the FETs, fault injection.
//
// What it models (SLUUAQ3A / SBS 1.1 / SMBus 2.0 unless noted; the emulator's own choices say so):
// - Commands: every SBS command of the register map (regmaps/bq4050). Entries of 2 bytes are SMBus words,
//   all others SMBus blocks (count, then data). A command the map does not know is refused: its command
//   byte is NACKed (the controller sees DataNack). Word writes are stored for read-write words.
// - PEC: always appended to a read (a controller that wants none stops clocking after the data); the CRC-8
//   covers 0x16, the command, 0x17 and the data (computed here with the emulator's own table, independent
//   of fw::crc). A write may carry a PEC: when the byte after the expected data arrives it is checked and
//   NACKed if wrong, and the command is then discarded (counters().badPec).
// - MAC: a word write to 0x00 or a block write [02 lo hi (data)] to 0x44 runs a subcommand. Readable
//   subcommands set the MAC result; 0x44 reads return [count lo hi data...] (count includes the echo),
//   0x23 reads return [count data...] (no echo). The result stays until the next readable subcommand, so an
//   ignored or dropped command leaves the previous answer in place (a stale echo). A subcommand the gauge
//   does not know, or one not available in SEALED mode, sets BatteryStatus[EC] (3 unsupported, 4 access
//   denied) and changes nothing else.
//   Results: DeviceType 0x4050; FirmwareVersion 11 bytes "40 50 01 03 00 2B 00 ..." (emulator's choice of
//   version and build; the device number written first, most significant byte first); HardwareVersion;
//   Safety/PF alert and status, OperationStatus (4 bytes LE), ChargingStatus, GaugingStatus,
//   ManufacturingStatus (2 bytes); DAStatus1 (32 bytes: cells 1..4, BAT, PACK, cell currents, powers) and
//   DAStatus2 (14 bytes of 0.1 K temperatures), the 34-byte and 16-byte 0x44 results.
// - FETs: ManufacturingStatus[FET_EN] = 1 (firmware control) by default, with both FETs on unless the test
//   turns them off (setFirmwareFets). FETControl (0x0022) toggles FET_EN; with FET_EN = 0 the test-mode
//   toggles CHGFET 0x001F / DSGFET 0x0020 / PCHGFET 0x001E flip ManufacturingStatus CHG_TEST/DSG_TEST/
//   PCHG_TEST and the FETs follow, except the CHG FET stays off while DSG is off and the pack is above 16 V
//   (TI E2E 1445117; OperationStatus[CHG] shows the FET, not the flag: the emulator's choice). Leaving
//   firmware control clears the test bits. None of these is available SEALED (setSealed).
// - Calibration output (OutputCCandADCforCalibration 0xF081): OperationStatus[CAL] = 1 and the MAC result
//   becomes a raw-data block echoing 0xF081 until ExitCalibrationOutputMode (0xF080); readable subcommands
//   are ignored meanwhile (a gauge "left in an unexpected mode" answers with stale, foreign data).
// - Timing: no clock stretching unless injected; bus time is then the pure wire time.
// - Charge state, with a clock attached (attachClock; bms-sim and the twin attach one): the gauge counts the
//   charge Current() moves, as its coulomb counter does, and RemainingCapacity() follows it. Units as
//   SLUUAQ3A gives them for the SBS commands: Current() 0x0A in mA (charge positive); RemainingCapacity()
//   0x0F and FullChargeCapacity() 0x10 in mAh with BatteryMode()[CAPM] = 0 and in 10 mWh with [CAPM] = 1
//   (then the energy Voltage() x Current() is counted); RelativeStateOfCharge() 0x0D in % of
//   FullChargeCapacity(). RemainingCapacity stays within 0..FullChargeCapacity, and FullChargeCapacity is not
//   learned ("not updated during charging", SLUUAQ3A 0x10). SLUUAQ3A does not say how RelativeStateOfCharge
//   rounds: the emulator rounds up, as TI states for StateOfCharge() of its BQ27220 (SLUUBD4A), so 1 mAh left
//   is 1 %. The time estimates (0x11..0x13) and AverageCurrent stay as set. Without a clock nothing moves.
//
// Faults (inject(), applied to the next transactions that match, each `times` times):
//   AddressNack      the START's address is not acknowledged (gauge busy or absent)
//   DataNack         written byte `index` (0 = the command) is refused
//   Stretch          SCL held for `stretch` before read byte `index` (or written byte `index`, !onRead)
//   CorruptByte      read byte `index` (0 = first byte after Sr: a word's low byte, a block's count) XOR
//                    `value`; the PEC stays the one the gauge computed over the true bytes
//   TopBitStuck      seed 003: a word read's second byte arrives with bit 7 stuck high
//   AllOnes          seed 003: a word read arrives as FF FF (PEC as computed over the true bytes)
//   Asleep           the gauge acknowledges but drives nothing: every read byte is FF, the PEC too
//   BlockCount       a block read's count byte is replaced by `value` (data and PEC as the gauge sends them)
//   DropMacCommand   the next MAC subcommand write is acknowledged but not executed
// A fault with `command` >= 0 waits for a transaction with that command byte; AddressNack applies to the
// next START whatever its command.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <vector>

#include "core/time.hpp"
#include "sim/i2c_target.hpp"
#include "sim/sim_clock.hpp"

namespace bsp::host {

class Bq4050Emulator final : public I2cTarget {
 public:
  static constexpr uint8_t kAddress = 0x0B;

  enum class FaultKind : uint8_t {
    AddressNack,
    DataNack,
    Stretch,
    CorruptByte,
    TopBitStuck,
    AllOnes,
    Asleep,
    BlockCount,
    DropMacCommand,
  };
  struct Fault {
    FaultKind kind = FaultKind::AddressNack;
    int command = -1;        // the command byte it waits for (-1: the next transaction)
    uint8_t index = 0;       // byte index (see the kinds)
    uint8_t value = 0;       // XOR mask (CorruptByte) or count (BlockCount)
    fw::Duration stretch{};  // Stretch
    bool onRead = true;      // Stretch: before a read byte (else before a written byte)
    int times = 1;           // transactions it affects
  };

  Bq4050Emulator();

  // --- bus face ------------------------------------------------------------------------------------------
  I2cReply onStart(bool read) override;
  I2cReply onWrite(uint8_t byte) override;
  uint8_t onRead(fw::Duration& stretch) override;
  void onStop() override;
  void onBusRecovery() override;

  // --- backend face --------------------------------------------------------------------------------------
  void setWord(uint8_t command, uint16_t value) { words_[command] = value; }
  uint16_t word(uint8_t command) const { return words_[command]; }
  void setBlock(uint8_t command, std::vector<uint8_t> data) { blocks_[command] = std::move(data); }
  void setVoltage(uint16_t mv) {
    count();
    words_[0x09] = mv;
  }
  void setCurrent(int16_t ma) {
    count();  // the charge moved at the old current up to now
    words_[0x0A] = static_cast<uint16_t>(ma);
  }
  void setTemperature(uint16_t deciK) { words_[0x08] = deciK; }
  void setRsoc(uint16_t percent) { words_[0x0D] = percent; }
  void setRemainingCapacity(uint16_t v) {
    count();
    words_[0x0F] = v;
  }
  void setFullChargeCapacity(uint16_t v) {
    count();
    words_[0x10] = v;
  }
  // Counts charge from now on (see "Charge state" above); the clock must outlive the emulator.
  void attachClock(const SimClock& clock);
  void setTimeToEmpty(uint16_t minutes) { words_[0x12] = minutes; }
  void setTimeToFull(uint16_t minutes) { words_[0x13] = minutes; }
  void setCell(int cell, uint16_t mv);  // cell 1..4 (CellVoltage1 is 0x3F)
  void setCells(const std::array<uint16_t, 4>& mv);
  void setBatteryStatus(uint16_t raw) { words_[0x16] = raw; }
  void setSpecificationInfo(uint16_t raw) { words_[0x1A] = raw; }
  void setSafetyStatus(uint32_t raw) { safetyStatus_ = raw; }
  void setSafetyAlert(uint32_t raw) { safetyAlert_ = raw; }
  void setPfStatus(uint32_t raw) { pfStatus_ = raw; }
  // OperationStatus bits other than CHG/DSG/PCHG/SEC/CAL (those follow the model).
  void setOperationFlags(uint32_t raw) { operationFlags_ = raw; }
  void setManufacturingStatus(uint16_t raw) { manufacturing_ = raw; }
  void setFirmwareFets(bool chg, bool dsg) {
    firmwareChg_ = chg;
    firmwareDsg_ = dsg;
  }
  void setSealed(bool sealed) { sealed_ = sealed; }
  void setDeviceType(uint16_t type) { deviceType_ = type; }
  void setMacResult(uint16_t subcommand, std::vector<uint8_t> data);  // a readable subcommand's answer

  uint32_t operationStatus() const;  // as MAC 0x0054 returns it now
  uint16_t manufacturingStatus() const { return manufacturing_; }
  bool chgFet() const;
  bool dsgFet() const;
  bool pchgFet() const;
  bool calibrationOutput() const { return calibration_; }

  // A reset of the gauge (power loss, watchdog): its run-time state returns to power-on values (no MAC
  // result, calibration output off, ManufacturingStatus as configured for production, no transaction in
  // progress); the pack's values and the backend's settings stay. Tests detach the gauge from the bus around
  // it.
  void reset();

  void inject(const Fault& fault) { faults_.push_back(fault); }
  void clearFaults() { faults_.clear(); }
  size_t pendingFaults() const { return faults_.size(); }

  struct Counters {
    uint64_t transactions = 0;  // STARTs addressed to the gauge
    uint64_t reads = 0;         // transactions with a read phase
    uint64_t writes = 0;        // write-only transactions executed
    uint64_t macCommands = 0;   // subcommands executed
    uint64_t badPec = 0;        // writes refused for a wrong PEC
    uint64_t refused = 0;       // unknown commands NACKed
    uint64_t recoveries = 0;    // bus-recovery sequences seen
  };
  const Counters& counters() const { return counters_; }
  const std::vector<uint16_t>& macLog() const { return macLog_; }  // subcommands executed, in order

  // The emulator's own CRC-8 (polynomial 0x07, table driven): the PEC it sends and checks.
  static uint8_t pec(const uint8_t* data, size_t length, uint8_t crc = 0);

 private:
  enum class Phase : uint8_t { Idle, Writing, Reading };

  bool isWord(uint8_t command) const;
  bool known(uint8_t command) const;
  size_t expectedWriteLength() const;  // data bytes of the write in progress (without the PEC)
  void execute();
  void runMac(uint16_t subcommand, const std::vector<uint8_t>& data);
  std::optional<std::vector<uint8_t>> macData(uint16_t subcommand) const;
  void buildResponse();
  void count();  // moves the charge state to the clock's now

  std::array<uint16_t, 256> words_{};
  const SimClock* clock_ = nullptr;
  uint64_t countedUs_ = 0;  // the charge state is that of this instant
  int64_t residue_ = 0;     // counted, less than one unit of RemainingCapacity (mA x us, or mV x mA x us)
  std::map<uint8_t, std::vector<uint8_t>> blocks_;
  std::map<uint16_t, std::vector<uint8_t>> macResults_;  // overrides from the backend
  uint32_t safetyStatus_ = 0;
  uint32_t safetyAlert_ = 0;
  uint32_t pfStatus_ = 0;
  uint32_t operationFlags_ = 0;
  uint16_t manufacturing_ = 0x0018;  // GAUGE_EN | FET_EN: a pack configured for production
  uint16_t deviceType_ = 0x4050;
  bool firmwareChg_ = true;
  bool firmwareDsg_ = true;
  bool sealed_ = false;
  bool calibration_ = false;

  // The MAC result buffer (what 0x44 and 0x23 return).
  uint16_t macCode_ = 0;
  std::vector<uint8_t> macResult_;

  // The transaction in progress.
  Phase phase_ = Phase::Idle;
  std::vector<uint8_t> written_;
  std::vector<uint8_t> response_;
  size_t readIndex_ = 0;
  bool writeRefused_ = false;
  bool hadPec_ = false;
  Fault active_{};
  bool hasActive_ = false;

  std::deque<Fault> faults_;
  Counters counters_;
  std::vector<uint16_t> macLog_;
};

}  // namespace bsp::host
