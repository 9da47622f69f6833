// Bq769xEmulator: a BQ76952 (BQ769x2 family) or BQ76905/BQ76907 (BQ7690x) battery monitor on the simulated
// I2C bus, with two faces in the manner of Zephyr's emulators:
//   bus face      bsp::host::I2cTarget: attach it to a SimI2cBus at 0x08. It behaves like the chip on the
//                 wire: the 128-byte direct-command space with auto-increment on reads and writes, the
//                 subcommand window (0x3E/0x3F read FF FF while a command runs, then echo it; the result in
//                 0x40..0x5F with the checksum at 0x60 and the length at 0x61), data memory through the same
//                 window, writes committed by 0x60/0x61 only when checksum and length are right, data-memory
//                 writes accepted only in CONFIG_UPDATE, Alarm Status write-1-to-clear, and the optional
//                 per-byte CRC-8 (a wrong CRC from the host is refused with a NACK and the write dropped).
//                 Host FET commands act only where the device's FET Options allow them, SLEEP_ENABLE /
//                 SLEEP_DISABLE switch SLEEP, and the ALERT pin is driven as ALERT Pin Config says
//                 (device.cpp).
//   backend face  the methods below, for tests and the simulator: set cell voltages, current, temperatures;
//                 read back data memory, FET states, balancing, CONFIG_UPDATE; watch the ALERT output;
//                 inject faults.
// Time comes from the SimClock: a subcommand's result appears after its latency (Timing), CONFIG_UPDATE
// entry and exit take their own time, the device's COV/CUV protections trip after their configured delay
// and release below threshold minus hysteresis, in SLEEP the measurements are taken only every Power:Sleep:
// Voltage Time, and the emulator stretches SCL where Timing says so. Wire time itself is SimI2cBus's
// business. The files: emulator.cpp the bus face, registers and subcommands; device.cpp the device's own
// behaviour (measurements and SLEEP, protections, FETs, Alarm Status and the ALERT pin); balancing.cpp host
// balancing; open_wire.cpp a detached sense wire and the BQ769x2's cell open-wire check.
//
// Register facts come from the generated register maps (regmap/bq769x2*.hpp, regmap/bq7690x*.hpp); data
// memory starts at the maps' defaults. Where the maps have no default that the protections need (BQ7690x
// COV/CUV thresholds), the protection stays off until the host writes one. Assumptions that no TI document
// gives (latencies, boot time) are Timing fields, so a test states them.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "cell_model.hpp"
#include "core/time.hpp"
#include "sim/i2c_target.hpp"
#include "sim/sim_clock.hpp"

namespace bsp::host {

// Assumed device timings (no TI document gives them; tests state the ones they rely on).
struct Bq769xTiming {
  fw::Duration subcommand = fw::us(400);  // write of 0x3E/0x3F until the echo (typical command)
  fw::Duration dataMemory = fw::us(600);  // data-memory read until the echo
  fw::Duration iromSig = fw::us(8500);    // IROM_SIG, the slowest (LibreSolar: ~8.5 ms)
  fw::Duration configUpdate = fw::ms(1);  // SET_CFGUPDATE / EXIT_CFGUPDATE until the flag changes
  fw::Duration boot = fw::ms(2);          // after a reset: every address is NACKed for this long
  fw::Duration ackStretch{};              // SCL stretch on every address ACK (0: none)
  bool nackFirstAfterPowerUp = false;     // the first transaction after power-up is NACKed (E2E 1515940)
  // SLEEP: how long the current must stay below Sleep Current before the device enters SLEEP (SLUUBY2B 7.3
  // gives no time; SLUSE96 a 10 s hysteresis on re-entry for the BQ7690x), and the BQ7690x Power:Sleep
  // values, which the register map has no default for (the BQ769x2's defaults: 20 mA, 5 s).
  fw::Duration sleepEntry = fw::s(1);
  int16_t sleepCurrent7690xMa = 20;
  uint8_t sleepVoltageTime7690xS = 5;
  // Host-controlled balancing stops this long after the last CB_ACTIVE_CELLS write (balancing.cpp): the
  // BQ7690x's 20 s is SLUAAP7 section 3; for the BQ769x2 TI says only that it "runs a few seconds by default"
  // (E2E 958310), taken at its lower end.
  fw::Duration hostBalanceTimeout769x2 = fw::s(2);
  fw::Duration hostBalanceTimeout7690x = fw::s(20);
  // The board, not the device: the sense resistor the current comparators (OCC, OCD1/2, SCD) see the current
  // through, in micro-ohms (the BQ76952EVM's and BQ76907EVM's 1 mOhm).
  uint32_t shuntMicroOhm = 1000;
  // BQ7690x COV/CUV delays count ADSCAN intervals (SLUUCI8 Cell Undervoltage Protection Delay); how long one
  // is depends on the measurement speed settings, which no TI text read gives in time: assumed.
  fw::Duration adscan7690x = fw::ms(10);
  // BQ7690x Recovery Time (Protections:Current, 0x903F) has no default in the register map: assumed.
  uint8_t currentRecovery7690xS = 3;
  // BQ769x2 cell open-wire check (open_wire.cpp): how far one check pulls a detached input's node down, in
  // mV. SLUUBY2B "Cell Open Wire" gives the sink (55 uA typical; the BQ76922 data sheet, same family,
  // I(OW) 22..95 uA) and its duration (one ADC measurement, 3 ms); the node's capacitance is the board's,
  // not given: assumed 100 nF (55 uA x 3 ms / 100 nF = 1650 mV).
  int32_t openWireDrainMv = 1650;
};

class Bq769xEmulator final : public I2cTarget {
 public:
  enum class Model : uint8_t { Bq76952, Bq76907, Bq76905 };

  using Timing = Bq769xTiming;

  Bq769xEmulator(SimClock& clock, Model model = Model::Bq76952, Timing timing = {});

  // --- bus face --------------------------------------------------------------------------------------------
  I2cReply onStart(bool read) override;
  I2cReply onWrite(uint8_t byte) override;
  uint8_t onRead(fw::Duration& stretch) override;
  void onStop() override;
  void onBusRecovery() override;

  // --- backend: measurements -------------------------------------------------------------------------------
  void setCellMv(uint8_t cell, int16_t mv);  // cell 1..16 (1..7 on BQ7690x)
  void setAllCellsMv(int16_t mv);
  int16_t cellMv(uint8_t cell) const { return cells_.at(cell - 1); }
  void setCurrentMa(int32_t ma);       // charge positive; CC2 saturates at the int16 range in userA
  void setStackOverride(int16_t raw);  // fixes Stack Voltage (raw units) instead of the cell sum
  void setPackLd(int16_t packRaw, int16_t ldRaw);
  void setIntTemp(int16_t raw);            // BQ769x2: 0.1 K; BQ7690x: degC
  void setTs(uint8_t index, int16_t raw);  // TS1..TS3 (index 0..2) in 0.1 K; BQ7690x: index 0 = TS counts
  // BQ7690x: the REGOUT LDO out of regulation (Safety Status A[REGOUT] when that protection is enabled).
  void setRegoutFault(bool on);
  // BQ769x2 CFETOFF / DFETOFF pins as the host drives them (high = true); they act as their Pin Config says
  // (device.cpp).
  void setFetOffPins(bool cfetoff, bool dfetoff);
  // The sense wire of cell input VC`pin` (0 = VC0 below cell 1 .. cell count = the top) detached from the
  // board, or connected again (open_wire.cpp: the node holds its voltage; only the BQ769x2's open-wire check
  // moves it). One open wire at a time; BQ76952 only.
  void setOpenWire(int pin, bool open);
  void setDeviceNumber(uint16_t number) { deviceNumber_ = number; }
  void setCrc(bool on) { crc_ = on; }  // the device's Comm Type CRC setting ("OTP": survives resets)
  bool crc() const { return crc_; }
  // Completes an ADC scan: sets Alarm Raw Status FULLSCAN/ADSCAN (latched into Alarm Status if enabled).
  void completeScan();
  // The accumulated charge (charge.cpp): the counter as DASTATUS6 / PASSQ report it now (BQ769x2: userAh x
  // 2^32; BQ7690x: userA-s), and the charge that truly flowed since power-up (mA x us, never cleared, never
  // wrapped): what a state-of-charge test compares with. presetChargeCount() sets the counter (to test its
  // wrap).
  int64_t chargeCount();
  int64_t trueChargeMaUs() {
    integrateCharge();
    return trueChargeMaUs_;
  }
  void presetChargeCount(int64_t count);

  // --- backend: observation --------------------------------------------------------------------------------
  uint8_t reg(uint8_t cmd);  // a direct-command byte as the host would read it now
  uint32_t dataMemory(uint16_t address, uint8_t size) const;
  void setDataMemory(uint16_t address, uint32_t value, uint8_t size);
  bool inConfigUpdate() const { return cfgUpdate_; }
  bool fetEnabled() const { return fetEn_; }  // FET_EN (0 = FET test mode)
  bool chgFet() const { return chgOn_; }
  bool dsgFet() const { return dsgOn_; }
  // Cells being balanced, bit 0 = cell 1 (whatever the family's CB_ACTIVE_CELLS layout).
  uint16_t balancing() const { return static_cast<uint16_t>(bq7690x() ? cbActive_ >> 1 : cbActive_); }
  // --- backend: balancing (balancing.cpp) ------------------------------------------------------------------
  // The cell's voltage now: what was set, less what balancing took out of it.
  int16_t cellNowMv(uint8_t cell);
  void setCellModel(const CellModel& model);
  const CellModel& cellModel() const { return cellModel_; }
  // Charge balancing took out of a cell (1..16), in mA x us.
  int64_t bledChargeMaUs(uint8_t cell);
  struct BalanceCounters {
    uint32_t accepted = 0;   // CB_ACTIVE_CELLS writes taken
    uint32_t refused = 0;    // writes the device refused (the rules in balancing.cpp): nothing balances
    uint32_t adjacent = 0;   // BQ769x2 masks with two neighbouring cells (accepted: they overheat)
    uint32_t ignored = 0;    // writes ignored because Balancing Configuration[CB_NO_CMD] is set
    uint32_t timeouts = 0;   // balancing that stopped because no write came in time
    uint32_t tempStops = 0;  // balancing the device stopped outside its temperature limits
  };
  const BalanceCounters& balanceCounters() const { return balanceCounters_; }
  uint16_t alarmStatus() const { return alarmStatus_; }
  uint8_t safetyStatusA() const { return safetyStatusA_; }
  uint8_t safetyAlertA() const { return safetyAlertA_; }
  uint8_t safetyStatusB() const { return safetyStatusB_; }  // BQ7690x
  uint8_t safetyStatusC() const { return safetyStatusC_; }  // BQ769x2 (SCDL, HWDF)
  bool sleepAllowed() const { return sleepAllowed_; }       // Battery Status[SLEEP_EN]
  bool sleeping() const { return sleeping_; }               // Battery Status[SLEEP]
  // The alarm (Alarm Status non-zero), whatever the pin does with it.
  bool alertAsserted() const { return alertAsserted_; }
  // The ALERT net as an MCU input with a pull-up reads it: what the pin drives per its configuration (BQ769x2
  // ALERT Pin Config; BQ7690x: asserted low), high where it drives nothing. A configuration the input cannot
  // use (not ALERT, active-high) gives no falling edge when the alarm asserts.
  bool alertLine() const { return alertLine_; }
  // Called with the new level whenever alertLine() changes. The simulator wires it to a SimEdgeInput.
  void onAlertLine(std::function<void(bool high)> hook) { alertHook_ = std::move(hook); }
  // Every subcommand or data-memory address the device executed or served, in order.
  const std::vector<uint16_t>& executed() const { return executed_; }
  // 0x60/0x61 commits refused: wrong checksum or length, data memory outside CONFIG_UPDATE.
  uint32_t rejectedWrites() const { return rejectedWrites_; }
  uint32_t resets() const { return resets_; }
  Model model() const { return model_; }

  // --- backend: power and faults ---------------------------------------------------------------------------
  void powerOn();                       // power-on reset (POR); arms nackFirstAfterPowerUp
  void reset();                         // what RESET (0x0012) does: registers and data memory to defaults
  void nackNext(int transactions = 1);  // NACK the address of the next transactions
  void setMuted(bool muted) { muted_ = muted; }  // NACK every address while muted (device gone, comm loss)
  void stretchNext(fw::Duration d);              // stretch SCL once, on the next byte of any kind
  // Flips bit 0 of byte `wireIndex` (a data or CRC byte) of a read: the first read long enough, after
  // skipping `skipReads` read transactions.
  void corruptNextRead(uint8_t wireIndex, int skipReads = 0);
  void wrongLengthNext(uint8_t length);  // the next subcommand result reports this 0x61 length
  void wrongChecksumNext();              // the next subcommand result carries a wrong 0x60 checksum
  // The next result's echo appears `lag` before its buffer, checksum and length are updated.
  void staleBufferNext(fw::Duration lag = fw::ms(2));
  void resetAfterBytes(int bytes);  // the device resets after that many more bytes on the bus
  // The running subcommand completes right after the next read of 0x3E, before 0x3F is read: the poll
  // reads FF and the code's high byte, as a poll straddling the command's end does on the wire (the MSPM0
  // twin's byte-timed I2C shows it; the host bus serves a transaction's bytes at one instant).
  void straddleNextEcho() { straddleEcho_ = true; }
  void setLatency(uint16_t code, fw::Duration d) { latencyOverride_ = {code, d}; }

 private:
  struct Pending {
    uint8_t addr;
    uint8_t value;
  };

  // What the ADC measured last (in SLEEP: at the last Voltage Time tick; otherwise now).
  struct Measured {
    std::array<int16_t, 16> cells{};
    int32_t currentMa = 0;
    int16_t intTemp = 0;
    std::array<int16_t, 3> ts{};
  };

  bool bq7690x() const { return model_ != Model::Bq76952; }
  uint8_t cellCount() const;
  uint8_t cellsInUse() const;
  void measure();
  void applyOpenWire(std::array<int16_t, 16>& cells);  // open_wire.cpp
  int32_t inputMv(int pin);                            // open_wire.cpp
  void scheduleOpenWireCheck();
  void openWireCheck();
  void updateSleep();
  void sleepTick();
  void evaluateTemperatures();
  bool computeAlertLine() const;
  int32_t userAmpTenthMa() const;
  void integrateCharge();
  void resetCharge();
  uint8_t fillCharge(uint8_t* data);
  void writeBalancing(uint16_t mask);  // balancing.cpp
  void settleBleed();
  void stopBalancing();
  void checkBalanceTemperatures();
  void refresh();
  void put16(uint8_t cmd, uint16_t v);
  void commit();
  void startCommand(uint16_t code);
  void complete(uint16_t code);
  void fillResult(uint16_t code, const uint8_t* data, uint8_t n, uint8_t reportedLen);
  void executeWrite();
  void update();
  void evaluateProtections();
  void evaluateCurrentProtections(uint64_t now, uint64_t& next);
  void evaluateHostWatchdog(uint64_t now, uint64_t& next);
  bool fetOffPin(uint16_t configAddress, bool level, bool& both) const;
  void scheduleProtection(uint64_t atUs);
  void setAlert(bool asserted);
  void loadDefaults();
  void initRegisters();
  bool resetIfDue();
  bool dmValid(uint16_t address) const;
  fw::Duration latencyOf(uint16_t code) const;

  SimClock& clock_;
  Model model_;
  Timing timing_;
  std::array<uint8_t, 128> regs_{};
  std::vector<uint8_t> dm_;
  std::vector<uint8_t> dmDefaults_;
  uint16_t dmBase_ = 0;

  // Measurement state
  std::array<int16_t, 16> cells_{};
  int32_t currentMa_ = 0;
  // Accumulated charge (charge.cpp): mA x us since the counter was cleared, the count it was cleared to,
  // when; and the true charge since construction.
  __int128 chargeMaUs_ = 0;
  int64_t chargeBase_ = 0;
  uint64_t chargeAtUs_ = 0;
  uint64_t chargeSinceUs_ = 0;
  int64_t trueChargeMaUs_ = 0;
  bool stackOverride_ = false;
  int16_t stackRaw_ = 0;
  int16_t packRaw_ = -1;  // -1: follows the stack
  int16_t ldRaw_ = -1;
  int16_t intTemp_ = 0;
  std::array<int16_t, 3> ts_{};
  uint16_t deviceNumber_ = 0;

  // Device state
  bool crc_ = false;
  bool cfgUpdate_ = false;
  bool por_ = true;
  bool fetEn_ = false;
  bool hostChgOff_ = false;  // BQ769x2 host-off states (ALL_FETS_*, *_OFF, FET_CONTROL)
  bool hostDsgOff_ = false;
  uint8_t fetControl_ = 0;  // BQ7690x FET Control as written (its bits act per FET Options)
  bool chgOn_ = false;
  bool dsgOn_ = false;
  uint16_t cbActive_ = 0;
  CellModel cellModel_;
  std::array<int64_t, 16> bled_{};  // mA x us each cell lost to balancing
  uint64_t bledUntilUs_ = 0;        // bled_ covers the time up to here
  SimClock::EventId cbTimeoutEvent_ = 0;
  BalanceCounters balanceCounters_;
  uint16_t alarmStatus_ = 0;
  uint16_t alarmRaw_ = 0;
  uint16_t alarmEnable_ = 0;
  uint8_t safetyAlertA_ = 0;
  uint8_t safetyStatusA_ = 0;
  uint8_t safetyAlertB_ = 0;
  uint8_t safetyStatusB_ = 0;
  bool regoutFault_ = false;
  bool alertAsserted_ = false;
  bool alertLine_ = true;
  uint8_t safetyAlertC_ = 0;  // BQ769x2
  uint8_t safetyStatusC_ = 0;
  uint64_t covSince_ = UINT64_MAX;
  uint64_t cuvSince_ = UINT64_MAX;
  // Current protections: when each condition (or, tripped, its recovery criterion) began; SCD's trip time.
  uint64_t occSince_ = UINT64_MAX, ocd1Since_ = UINT64_MAX, ocd2Since_ = UINT64_MAX, scdSince_ = UINT64_MAX;
  uint64_t occRecoverSince_ = UINT64_MAX, ocdRecoverSince_ = UINT64_MAX, scdlRecoverSince_ = UINT64_MAX;
  uint64_t scdTrippedAt_ = 0;
  uint8_t scdlCounter_ = 0;
  uint64_t lastCommUs_ = 0;  // the last transaction the device acknowledged (host watchdog)
  bool cfetoffPin_ = false;
  bool dfetoffPin_ = false;
  SimClock::EventId protectionEvent_ = 0;
  std::function<void(bool)> alertHook_;
  Measured measured_;
  bool sleepAllowed_ = true;
  bool sleeping_ = false;
  uint64_t relaxSince_ = UINT64_MAX;
  SimClock::EventId sleepEvent_ = 0;
  int openPin_ = -1;        // the detached VC input (open_wire.cpp), -1: none
  int32_t openNodeMv_ = 0;  // its node's voltage above VSS
  SimClock::EventId openWireEvent_ = 0;

  // Subcommand window state
  uint16_t running_ = 0;  // the command being executed (its result is not in the buffer yet)
  SimClock::EventId commandEvent_ = 0;
  SimClock::EventId bufferEvent_ = 0;
  uint16_t writeCode_ = 0;  // a write waiting for its 0x60/0x61 commit
  std::vector<uint8_t> writeData_;
  bool writePending_ = false;

  // Transaction state
  bool addressed_ = false;
  bool reading_ = false;
  bool haveCommand_ = false;
  bool dropped_ = false;  // a wrong CRC was received: nothing of this transaction is committed
  bool dead_ = false;     // the device reset during this transaction
  uint8_t ptr_ = 0;
  uint8_t cmd_ = 0;         // the command byte of this transaction (its read CRC covers it)
  uint8_t crcAcc_ = 0;      // running CRC of the first data byte
  int dataIndex_ = 0;       // data bytes seen in this phase
  bool expectCrc_ = false;  // next written byte is a CRC (CRC mode)
  uint8_t lastData_ = 0;
  std::vector<Pending> pending_;
  int readIndex_ = 0;  // bytes read in this phase (wire index)
  uint8_t readData_ = 0;
  uint64_t bootUntil_ = 0;

  // Faults
  bool nackFirst_ = false;
  bool muted_ = false;
  int nackCount_ = 0;
  fw::Duration stretchOnce_{};
  int corruptIndex_ = -1;
  int corruptSkip_ = 0;
  bool corruptThis_ = false;
  int wrongLength_ = -1;
  bool wrongChecksum_ = false;
  bool straddleEcho_ = false;
  fw::Duration staleLag_{};
  int resetAfter_ = -1;
  std::pair<uint16_t, fw::Duration> latencyOverride_{0, {}};

  std::vector<uint16_t> executed_;
  uint32_t rejectedWrites_ = 0;
  uint32_t resets_ = 0;
};

}  // namespace bsp::host
