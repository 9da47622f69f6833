// Bq769xEmulator, the device's own behaviour (the bus face is emulator.cpp): what the ADC measures and how
// often (SLEEP), the protections it runs itself, its FET drivers, Alarm Status and the ALERT pin. Every rule
// names the TI document it follows; what no TI document gives is a Timing field (emulator.hpp).
#include <algorithm>
#include <cstdlib>

#include "bq769x2/emulator.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq769x2.hpp"

namespace bsp::host {

namespace {
namespace m2 = fw::regmap::bq769x2;
namespace m7 = fw::regmap::bq7690x;
}  // namespace

// --- backend setters ---------------------------------------------------------------------------------------

void Bq769xEmulator::setCellMv(uint8_t cell, int16_t mv) {
  cells_.at(cell - 1) = mv;
  update();
}
void Bq769xEmulator::setAllCellsMv(int16_t mv) {
  cells_.fill(mv);
  update();
}
void Bq769xEmulator::setCurrentMa(int32_t ma) {
  integrateCharge();  // the charge counter has counted the old current up to now (charge.cpp)
  currentMa_ = ma;
  update();  // the current decides SLEEP
}
void Bq769xEmulator::setStackOverride(int16_t raw) {
  stackOverride_ = true;
  stackRaw_ = raw;
}
void Bq769xEmulator::setPackLd(int16_t packRaw, int16_t ldRaw) {
  packRaw_ = packRaw;
  ldRaw_ = ldRaw;
}
void Bq769xEmulator::setIntTemp(int16_t raw) {
  intTemp_ = raw;
}
void Bq769xEmulator::setTs(uint8_t index, int16_t raw) {
  ts_.at(index) = raw;
  update();  // BQ7690x temperature protections
}
void Bq769xEmulator::setRegoutFault(bool on) {
  regoutFault_ = on;
  update();
}

void Bq769xEmulator::completeScan() {
  const uint16_t scan =
      bq7690x() ? static_cast<uint16_t>(m7::bits::Alarm::fullscan_mask | m7::bits::Alarm::adscan_mask)
                : static_cast<uint16_t>(m2::bits::Alarm::fullscan_mask | m2::bits::Alarm::adscan_mask);
  // A scan completion is an event: the raw bit rises and latches if enabled.
  alarmStatus_ |= static_cast<uint16_t>(scan & alarmEnable_);
  setAlert(alarmStatus_ != 0);
}

// --- measurements and SLEEP --------------------------------------------------------------------------------

void Bq769xEmulator::measure() {
  measured_.cells = cells_;
  measured_.currentMa = currentMa_;
  measured_.intTemp = intTemp_;
  measured_.ts = ts_;
}

// SLEEP (SLUUBY2B 7.3, SLUUBY1B the same; SLUSE96/SLUSE97 for the BQ7690x): allowed after a reset (Power
// Config[SLEEP], set by default), then as SLEEP_ENABLE / SLEEP_DISABLE say (Battery Status[SLEEP_EN]). The
// device enters SLEEP when the current magnitude stays below Power:Sleep:Sleep Current (for
// Timing::sleepEntry) and leaves it at once when SLEEP is disallowed, current flows or a protection fault
// occurs. In SLEEP, ADC-based current, voltage and temperature measurements are taken only every
// Power:Sleep:Voltage Time seconds (default 5 s, SLUUCG7 "Voltage Time"): the registers keep the last ones.
void Bq769xEmulator::updateSleep() {
  const int32_t sleepCurrent = static_cast<int16_t>(bq7690x() ? dataMemory(m7::dm::SleepCurrent.address, 2)
                                                              : dataMemory(m2::dm::SleepCurrent.address, 2));
  const bool fault = safetyStatusA_ != 0 || safetyStatusB_ != 0;
  const bool relax = sleepAllowed_ && !cfgUpdate_ && !fault && std::abs(currentMa_) < sleepCurrent;
  if (!relax) {
    relaxSince_ = UINT64_MAX;
    if (sleepEvent_ != 0) clock_.cancel(sleepEvent_);
    sleepEvent_ = 0;
    if (sleeping_) {
      sleeping_ = false;
      measure();
    }
    return;
  }
  if (sleeping_) return;
  const uint64_t now = clock_.nowUs();
  if (relaxSince_ == UINT64_MAX) relaxSince_ = now;
  if (now >= relaxSince_ + timing_.sleepEntry.us) {
    sleeping_ = true;
    if (sleepEvent_ != 0) clock_.cancel(sleepEvent_);
    sleepEvent_ = 0;
    sleepTick();
  } else if (sleepEvent_ == 0) {
    sleepEvent_ = clock_.schedule(relaxSince_ + timing_.sleepEntry.us, [this] {
      sleepEvent_ = 0;
      update();
    });
  }
}

// One SLEEP measurement, and the next one Voltage Time later.
void Bq769xEmulator::sleepTick() {
  measure();
  const uint32_t seconds = std::max<uint32_t>(
      1, bq7690x() ? dataMemory(m7::dm::VoltageTime.address, 1) : dataMemory(m2::dm::VoltageTime.address, 1));
  sleepEvent_ = clock_.scheduleIn(fw::s(seconds), [this] {
    sleepEvent_ = 0;
    if (!sleeping_) return;
    sleepTick();
    update();
  });
}

// --- protections -------------------------------------------------------------------------------------------

void Bq769xEmulator::scheduleProtection(uint64_t atUs) {
  if (protectionEvent_ != 0) clock_.cancel(protectionEvent_);
  protectionEvent_ = clock_.schedule(atUs, [this] {
    protectionEvent_ = 0;
    update();
  });
}

// The cells the protections look at. BQ769x2 VCell Mode: one bit per cell input, 0 = all (SLUUBY2B). BQ7690x
// Vcell Mode: the number of cells (SLUAAM4 3.4 writes 0x04 for 4 cells), taken as inputs 1..n; 0 = all.
uint8_t Bq769xEmulator::cellsInUse() const {
  if (!bq7690x()) return cellCount();
  const uint8_t n = static_cast<uint8_t>(dataMemory(m7::dm::VcellMode.address, 1));
  return n == 0 || n > cellCount() ? cellCount() : n;
}

// The device's own COV and CUV protection (SLUUBY2B section 5.2/5.3; SLUUCJ0 for the BQ7690x): the alert flag
// follows the condition at once, the status flag trips when it has lasted the configured delay and clears
// once every cell is back past threshold -+ hysteresis. Protections pause in CONFIG_UPDATE. They use the
// measured cells (in SLEEP only every Voltage Time).
void Bq769xEmulator::evaluateProtections() {
  if (cfgUpdate_) return;
  const uint8_t n = cellsInUse();
  const uint16_t mask = bq7690x() ? 0 : static_cast<uint16_t>(dataMemory(m2::dm::VCellMode.address, 2));
  int maxMv = INT16_MIN;
  int minMv = INT16_MAX;
  for (uint8_t i = 0; i < n; ++i) {
    if (mask != 0 && (mask & (1U << i)) == 0) continue;
    maxMv = std::max<int>(maxMv, measured_.cells[i]);
    minMv = std::min<int>(minMv, measured_.cells[i]);
  }
  uint8_t covBit, cuvBit;
  int covMv, cuvMv, covHyst, cuvHyst;
  uint64_t covDelayUs, cuvDelayUs;
  uint8_t enabled;
  if (bq7690x()) {
    // BQ7690x limits are plain mV (I2); delays are taken as milliseconds (the map gives no unit).
    covBit = m7::bits::SafetyStatusA::cov_mask;
    cuvBit = m7::bits::SafetyStatusA::cuv_mask;
    enabled = static_cast<uint8_t>(dataMemory(m7::dm::EnabledProtectionsA.address, 1));
    covMv = static_cast<int16_t>(dataMemory(m7::dm::CellOvervoltageProtectionThreshold.address, 2));
    cuvMv = static_cast<int16_t>(dataMemory(m7::dm::CellUndervoltageProtectionThreshold.address, 2));
    covHyst = static_cast<int>(dataMemory(m7::dm::CellOvervoltageProtectionRecoveryHysteresis.address, 1));
    cuvHyst = static_cast<int>(dataMemory(m7::dm::CellUndervoltageProtectionRecoveryHysteresis.address, 1));
    covDelayUs = dataMemory(m7::dm::CellOvervoltageProtectionDelay.address, 1) * 1000ULL;
    cuvDelayUs = dataMemory(m7::dm::CellUndervoltageProtectionDelay.address, 1) * 1000ULL;
    // REGOUT (SLUUCJ0 Safety Status A bit 0; enabled by default, SLUAAM4 3.1): a fault while the LDO is out.
    const bool regout = regoutFault_ && (enabled & m7::bits::EnabledProtectionsA::regout_mask) != 0;
    safetyStatusA_ = static_cast<uint8_t>((safetyStatusA_ & ~m7::bits::SafetyStatusA::regout_mask) |
                                          (regout ? m7::bits::SafetyStatusA::regout_mask : 0));
    evaluateTemperatures();
  } else {
    // BQ769x2: thresholds and hysteresis in 50.6 mV steps, delays in 3.3 ms steps (the map's scales).
    covBit = m2::bits::SafetyA::cov_mask;
    cuvBit = m2::bits::SafetyA::cuv_mask;
    enabled = static_cast<uint8_t>(dataMemory(m2::dm::EnabledProtectionsA.address, 1));
    covMv = static_cast<int>(dataMemory(m2::dm::CovThreshold.address, 1) * 253 / 5);
    cuvMv = static_cast<int>(dataMemory(m2::dm::CuvThreshold.address, 1) * 253 / 5);
    covHyst = static_cast<int>(dataMemory(m2::dm::CovRecoveryHysteresis.address, 1) * 253 / 5);
    cuvHyst = static_cast<int>(dataMemory(m2::dm::CuvRecoveryHysteresis.address, 1) * 253 / 5);
    covDelayUs = dataMemory(m2::dm::CovDelay.address, 2) * 3300ULL;
    cuvDelayUs = dataMemory(m2::dm::CuvDelay.address, 2) * 3300ULL;
  }
  const uint64_t now = clock_.nowUs();
  uint64_t next = UINT64_MAX;
  auto track = [&](bool on, bool condition, bool recovered, uint8_t bit, uint64_t& since, uint64_t delay) {
    if (!on) {
      safetyAlertA_ &= static_cast<uint8_t>(~bit);
      safetyStatusA_ &= static_cast<uint8_t>(~bit);
      since = UINT64_MAX;
      return;
    }
    if (condition) {
      safetyAlertA_ |= bit;
      if (since == UINT64_MAX) since = now;
      if ((safetyStatusA_ & bit) == 0) {
        if (now >= since + delay) {
          safetyStatusA_ |= bit;
        } else {
          next = std::min(next, since + delay);
        }
      }
    } else {
      safetyAlertA_ &= static_cast<uint8_t>(~bit);
      since = UINT64_MAX;
      if (recovered) safetyStatusA_ &= static_cast<uint8_t>(~bit);
    }
  };
  track((enabled & covBit) != 0 && covMv > 0, maxMv >= covMv, maxMv < covMv - covHyst, covBit, covSince_,
        covDelayUs);
  track((enabled & cuvBit) != 0 && cuvMv > 0, minMv <= cuvMv, minMv > cuvMv + cuvHyst, cuvBit, cuvSince_,
        cuvDelayUs);
  if (next != UINT64_MAX) scheduleProtection(next);
}

// BQ7690x temperature protections on the TS reading (counts, which fall as the thermistor warms): OT trips
// below Threshold x 54 codes, UT above Threshold x 77 codes (SLUUCJ0 "Overtemperature in Discharge
// Protection Threshold": 54-LSB steps; the UT thresholds' 77-LSB steps), each enabled in Enabled Protections
// B (SLUUCI8), reported in Safety Alert B and Safety Status B (SLUUCJ0 layout). A tripped one recovers past
// its Recovery level (the threshold when that is 0). A threshold of 0 leaves it off (the map has no default).
// Delays (in measurements) are not modelled: Status B follows Alert B at once.
void Bq769xEmulator::evaluateTemperatures() {
  using B = m7::bits::SafetyB;
  using E = m7::bits::EnabledProtectionsB;
  struct Rule {
    uint8_t enable;
    uint8_t flag;
    uint16_t threshold;
    uint16_t recovery;
    int step;
    bool hot;
  };
  static constexpr Rule kRules[] = {
      {E::otd_mask, B::otd_mask, m7::dm::OvertemperatureInDischargeProtectionThreshold.address,
       m7::dm::OvertemperatureInDischargeProtectionRecovery.address, 54, true},
      {E::otc_mask, B::otc_mask, m7::dm::OvertemperatureInChargeProtectionThreshold.address,
       m7::dm::OvertemperatureInChargeProtectionRecovery.address, 54, true},
      {E::utd_mask, B::utd_mask, m7::dm::UndertemperatureInDischargeProtectionThreshold.address,
       m7::dm::UndertemperatureInDischargeProtectionRecovery.address, 77, false},
      {E::utc_mask, B::utc_mask, m7::dm::UndertemperatureInChargeProtectionThreshold.address,
       m7::dm::UndertemperatureInChargeProtectionRecovery.address, 77, false},
  };
  const uint8_t enabled = static_cast<uint8_t>(dataMemory(m7::dm::EnabledProtectionsB.address, 1));
  const int ts = measured_.ts[0];
  for (const Rule& r : kRules) {
    const int threshold = static_cast<int>(dataMemory(r.threshold, 1)) * r.step;
    const int recovery = static_cast<int>(dataMemory(r.recovery, 1)) * r.step;
    if ((enabled & r.enable) == 0 || threshold == 0) {
      safetyAlertB_ &= static_cast<uint8_t>(~r.flag);
      safetyStatusB_ &= static_cast<uint8_t>(~r.flag);
      continue;
    }
    const bool condition = r.hot ? ts < threshold : ts > threshold;
    const int back = recovery != 0 ? recovery : threshold;
    const bool recovered = r.hot ? ts >= back : ts <= back;
    if (condition) {
      safetyAlertB_ |= r.flag;
      safetyStatusB_ |= r.flag;
    } else {
      safetyAlertB_ &= static_cast<uint8_t>(~r.flag);
      if (recovered) safetyStatusB_ &= static_cast<uint8_t>(~r.flag);
    }
  }
}

// --- FETs, alarms, ALERT -----------------------------------------------------------------------------------

void Bq769xEmulator::update() {
  if (!sleeping_) measure();
  evaluateProtections();
  // FETs: FET_EN = 0 is FET test mode (BQ769x2: nothing turns on) or manual mode (BQ7690x: only FET Control's
  // ON bits); otherwise a FET is on unless the host forced it off, CONFIG_UPDATE is active, or a protection
  // configured to open it has tripped. In SLEEP the CHG FET is off unless FET Options[SLEEPCHG] (SLUUBY1B,
  // SLUUCI8 FET Options).
  uint8_t chgProt, dsgProt;
  bool ctrlEn = true;
  bool hostChgOff = hostChgOff_;
  bool hostDsgOff = hostDsgOff_;
  bool sleepChg;
  if (bq7690x()) {
    chgProt = m7::bits::SafetyStatusA::cov_mask;
    dsgProt = m7::bits::SafetyStatusA::cuv_mask;
    // Both FET Protections B[REGOUT] (SLUUCJ0; default 0) opens both FETs on a REGOUT fault.
    if ((dataMemory(m7::dm::BothFetProtectionsB.address, 1) & m7::bits::BothFetProtectionsB::regout_mask) !=
        0) {
      chgProt |= m7::bits::SafetyStatusA::regout_mask;
      dsgProt |= m7::bits::SafetyStatusA::regout_mask;
    }
    // FET Control's OFF bits act only with FET Options[HOST_FETOFF_EN], its ON bits only with
    // [HOST_FETON_EN] (SLUUCJ0 FET Control, SLUUCI8 FET Options; both 0 by default).
    const auto options =
        m7::bits::FetOptions::fromRaw(static_cast<uint8_t>(dataMemory(m7::dm::FetOptions.address, 1)));
    const auto control = m7::bits::FetControl::fromRaw(fetControl_);
    hostChgOff = options.host_fetoff_en() && control.chg_off();
    hostDsgOff = options.host_fetoff_en() && control.dsg_off();
    if (!fetEn_) {
      // Manual mode: a FET is on only where an obeyed ON bit forces it.
      hostChgOff = hostChgOff || !(options.host_feton_en() && control.chg_on());
      hostDsgOff = hostDsgOff || !(options.host_feton_en() && control.dsg_on());
    }
    sleepChg = options.sleepchg();
  } else {
    chgProt = static_cast<uint8_t>(dataMemory(m2::dm::ChgFetProtectionsA.address, 1));
    dsgProt = static_cast<uint8_t>(dataMemory(m2::dm::DsgFetProtectionsA.address, 1));
    const auto options =
        m2::bits::FetOptions::fromRaw(static_cast<uint8_t>(dataMemory(m2::dm::FetOptions.address, 1)));
    ctrlEn = options.fet_ctrl_en() && fetEn_;
    sleepChg = options.sleepchg();
  }
  const bool drive = ctrlEn && (fetEn_ || bq7690x()) && !cfgUpdate_;
  chgOn_ = drive && !hostChgOff && (safetyStatusA_ & chgProt) == 0 && (!sleeping_ || sleepChg);
  dsgOn_ = drive && !hostDsgOff && (safetyStatusA_ & dsgProt) == 0;

  // Alarm Raw Status, and Alarm Status latching the enabled bits that rose (SLUUBY2B / SLUUCJ0 "Alarm
  // Status"): latched until the host writes a 1 to the bit (commit()).
  uint16_t raw = 0;
  if (bq7690x()) {
    using A = m7::bits::Alarm;
    if (safetyStatusA_ != 0) raw |= A::ssa_mask;
    if (safetyStatusB_ != 0) raw |= A::ssb_mask;
    if (safetyAlertA_ != 0) raw |= A::saa_mask;
    if (safetyAlertB_ != 0) raw |= A::sab_mask;
    if (!chgOn_) raw |= A::xchg_mask;
    if (!dsgOn_) raw |= A::xdsg_mask;
    if (cbActive_ != 0) raw |= A::cb_mask;
  } else {
    using A = m2::bits::Alarm;
    if (safetyStatusA_ != 0) raw |= A::ssa_mask;
    if ((safetyAlertA_ & dataMemory(m2::dm::SfAlertMaskA.address, 1)) != 0) raw |= A::msk_sfalert_mask;
    if (!chgOn_) raw |= A::xchg_mask;
    if (!dsgOn_) raw |= A::xdsg_mask;
    if (cbActive_ != 0) raw |= A::cb_mask;
  }
  alarmStatus_ |= static_cast<uint16_t>(raw & ~alarmRaw_ & alarmEnable_);
  alarmRaw_ = raw;
  setAlert(alarmStatus_ != 0);
  updateSleep();
}

void Bq769xEmulator::setAlert(bool asserted) {
  alertAsserted_ = asserted;
  const bool line = computeAlertLine();
  if (line == alertLine_) return;
  alertLine_ = line;
  if (alertHook_) alertHook_(line);
}

// The level an MCU input with a pull-up sees on the ALERT net. BQ7690x: Alarm Status "causes the ALERT pin to
// be asserted low" (SLUUCJ0 Alarm Status). BQ769x2: ALERT Pin Config (SLUUCG7, SLUUBY1B): only PIN_FXN = 2 is
// ALERT (0x00 after reset: the pin drives nothing); OPT5 selects active-low, so the pin is driven "hi" while
// deasserted and "lo" while asserted, or the reverse for active-high; "hi" is driven only with OPT1 (from
// REG1 with OPT3, else REG18) or through the weak pull-up OPT2, otherwise the pin is tri-stated and the
// host's pull-up gives the level, unless the weak pull-down OPT0 fights it (taken as low: unusable).
bool Bq769xEmulator::computeAlertLine() const {
  if (bq7690x()) return !alertAsserted_;
  const auto cfg =
      m2::bits::AlertPinConfig::fromRaw(static_cast<uint8_t>(dataMemory(m2::dm::AlertPinConfig.address, 1)));
  if (cfg.pin_fxn() != 2) return true;
  const bool hi = alertAsserted_ != cfg.opt5();
  if (!hi) return false;
  return cfg.opt1() || cfg.opt2() || !cfg.opt0();
}

}  // namespace bsp::host
