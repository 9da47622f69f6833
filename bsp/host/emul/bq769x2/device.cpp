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
void Bq769xEmulator::setFetOffPins(bool cfetoff, bool dfetoff) {
  cfetoffPin_ = cfetoff;
  dfetoffPin_ = dfetoff;
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
  // The cells as they are now, balancing's losses included (balancing.cpp). The device pauses balancing to
  // measure (BQ7690x Balancing Configuration[CBDLY], SLUUCI8), so no balancing current shows in a reading.
  settleBleed();
  for (uint8_t c = 0; c < cells_.size(); ++c)
    measured_.cells[c] = cellNowMv(static_cast<uint8_t>(c + 1));
  applyOpenWire(measured_.cells);
  measured_.currentMa = currentMa_;
  measured_.intTemp = intTemp_;
  measured_.ts = ts_;
  checkBalanceTemperatures();
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
  const bool fault = safetyStatusA_ != 0 || safetyStatusB_ != 0 || safetyStatusC_ != 0;
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

// The device's own COV and CUV protection (SLUUBY2B 5.2 "Cell Overvoltage" / "Cell Undervoltage" Protection;
// SLUUCJ0 6.3 / 6.4 for the BQ7690x): the alert flag follows the condition at once, the status flag trips
// when it has lasted the configured delay and clears once every cell is back past threshold -+ hysteresis.
// Protections pause in CONFIG_UPDATE. They use the measured cells (in SLEEP only every Voltage Time). Delays:
// BQ769x2 3.3 ms x (2 + setting), the rule SLUUBY2B gives for the OCC/OCD delays ("units of 3.3 ms with a
// 6.6 ms offset") taken for COV/CUV's 3.3 ms units too (the safe side: the later trip); BQ7690x a count of
// ADSCAN intervals (SLUUCI8 Cell Undervoltage Protection Delay; the interval is Timing::adscan7690x).
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
    // BQ7690x limits are plain mV (I2; SLUUCY8's twin core: 0..5500 mV).
    covBit = m7::bits::SafetyStatusA::cov_mask;
    cuvBit = m7::bits::SafetyStatusA::cuv_mask;
    enabled = static_cast<uint8_t>(dataMemory(m7::dm::EnabledProtectionsA.address, 1));
    covMv = static_cast<int16_t>(dataMemory(m7::dm::CellOvervoltageProtectionThreshold.address, 2));
    cuvMv = static_cast<int16_t>(dataMemory(m7::dm::CellUndervoltageProtectionThreshold.address, 2));
    covHyst = static_cast<int>(dataMemory(m7::dm::CellOvervoltageProtectionRecoveryHysteresis.address, 1));
    cuvHyst = static_cast<int>(dataMemory(m7::dm::CellUndervoltageProtectionRecoveryHysteresis.address, 1));
    covDelayUs = dataMemory(m7::dm::CellOvervoltageProtectionDelay.address, 1) * timing_.adscan7690x.us;
    cuvDelayUs = dataMemory(m7::dm::CellUndervoltageProtectionDelay.address, 1) * timing_.adscan7690x.us;
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
    covDelayUs = (dataMemory(m2::dm::CovDelay.address, 2) + 2) * 3300ULL;
    cuvDelayUs = (dataMemory(m2::dm::CuvDelay.address, 2) + 2) * 3300ULL;
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
  evaluateCurrentProtections(now, next);
  evaluateHostWatchdog(now, next);
  if (next != UINT64_MAX) scheduleProtection(next);
}

namespace {

// A comparator protection's trip: the alert while the condition lasts, the status once it has lasted `delay`
// (SLUUBY2B 5.2 Table "Overcurrent in Charge": Alert when the sense voltage exceeds the threshold, Trip when
// it does for the delay: alert cleared, status set). Returns true on the trip. A tripped one waits for its
// own recovery (recoverAfter()).
bool tripAfter(uint64_t now, bool on, bool condition, uint8_t bit, uint64_t& since, uint64_t delayUs,
               uint8_t& alert, uint8_t& status, uint64_t& next) {
  if (!on) {
    alert &= static_cast<uint8_t>(~bit);
    status &= static_cast<uint8_t>(~bit);
    since = UINT64_MAX;
    return false;
  }
  if ((status & bit) != 0) return false;
  if (!condition) {
    alert &= static_cast<uint8_t>(~bit);
    since = UINT64_MAX;
    return false;
  }
  alert |= bit;
  if (since == UINT64_MAX) since = now;
  if (now < since + delayUs) {
    next = std::min(next, since + delayUs);
    return false;
  }
  alert &= static_cast<uint8_t>(~bit);
  status |= bit;
  since = UINT64_MAX;
  return true;
}

// A tripped protection clears once `criterion` has held for `timeUs`.
void recoverAfter(uint64_t now, uint8_t bit, bool criterion, uint64_t& since, uint64_t timeUs,
                  uint8_t& status, uint64_t& next) {
  if ((status & bit) == 0 || !criterion) {
    since = UINT64_MAX;
    return;
  }
  if (since == UINT64_MAX) since = now;
  if (now >= since + timeUs) {
    status &= static_cast<uint8_t>(~bit);
    since = UINT64_MAX;
  } else {
    next = std::min(next, since + timeUs);
  }
}

// The SCD threshold settings, in mV across the sense resistor (SLUUBY2B Protections:SCD:Threshold, SLUUCJ0
// Table 6-9: the same sixteen steps).
constexpr uint16_t kScdMv[16] = {10, 20, 40, 60, 80, 100, 125, 150, 175, 200, 250, 300, 350, 400, 450, 500};
// BQ7690x SCD delay settings 0..10 in us (SLUUCJ0 Short Circuit in Discharge Protection Delay; Table 6-10
// gives ranges, the upper ends of which these are).
constexpr uint16_t kScdDelay7690xUs[11] = {0, 15, 31, 61, 122, 244, 488, 977, 1953, 3906, 7797};

}  // namespace

// The comparator-based current protections on the sense voltage (current x Timing::shuntMicroOhm), which the
// analog comparators see at once (in SLEEP too, unlike the ADC readings):
//   OCC (SLUUBY2B 5.2 "Overcurrent in Charge Protection", SLUUCJ0 6.6): trips when the charge voltage
//     reaches 2 mV x threshold for 3.3 ms x (2 + delay); recovers when a current <= OCC Recovery Threshold
//     (a discharge, default -200 mA) lasts Protections:Recovery:Time (default 3 s). The alternative PACK-TOS
//     recovery is not modelled (PACK follows the stack here).
//   OCD1, OCD2 (SLUUBY2B 5.2 "Overcurrent in Discharge", SLUUCW9 the same): the discharge voltage, the same
//     units; recover when a current >= OCD Recovery Threshold (default 200 mA) lasts Recovery:Time.
//   SCD (SLUUBY2B 5.2 "Short Circuit in Discharge", SLUUCG7 the same; SLUUCJ0 6.5): the discharge voltage
//     reaches the threshold setting's mV (kScdMv) for (setting - 1) x 15 us (1: at once; BQ7690x:
//     kScdDelay7690xUs); recovers Protections:SCD:Recovery Time after the trip (default 5 s; BQ7690x Recovery
//     Time). Each trip counts towards the SCD latch: with Enabled Protections C[SCDL] the latch trips once
//     the count reaches SCDL Latch Limit (Safety Status C[SCDL]) and recovers, with Protection
//     Configuration[SCDL_CURR_RECOV], when a current >= SCDL Recovery Threshold (default 200 mA) lasts SCDL
//     Recovery Time (default 15 s) (SLUUCG7 Protection Configuration; load detection and the counter's
//     decrement are not modelled).
// BQ7690x: OCD1/OCD2/OCC are not enabled by the images and not modelled there.
void Bq769xEmulator::evaluateCurrentProtections(uint64_t now, uint64_t& next) {
  // Sense voltage in uV, charge positive.
  const int64_t senseUv = static_cast<int64_t>(currentMa_) * timing_.shuntMicroOhm / 1000;
  if (bq7690x()) {
    using A = m7::bits::SafetyStatusA;
    const uint8_t enabled = static_cast<uint8_t>(dataMemory(m7::dm::EnabledProtectionsA.address, 1));
    const uint8_t setting = static_cast<uint8_t>(
        dataMemory(m7::dm::ShortCircuitInDischargeProtectionThreshold.address, 1) & 0x0F);
    const uint8_t delay =
        static_cast<uint8_t>(dataMemory(m7::dm::ShortCircuitInDischargeProtectionDelay.address, 1));
    const uint64_t delayUs = kScdDelay7690xUs[std::min<uint8_t>(delay, 10)];
    const uint64_t recoverUs = std::max<uint64_t>(1, dataMemory(m7::dm::RecoveryTime.address, 1) != 0
                                                         ? dataMemory(m7::dm::RecoveryTime.address, 1)
                                                         : timing_.currentRecovery7690xS) *
                               1000000ULL;
    uint64_t since = scdTrippedAt_;
    recoverAfter(now, A::scd_mask, true, since, recoverUs, safetyStatusA_, next);
    if (tripAfter(now, (enabled & m7::bits::EnabledProtectionsA::scd_mask) != 0,
                  -senseUv >= kScdMv[setting] * 1000LL, A::scd_mask, scdSince_, delayUs, safetyAlertA_,
                  safetyStatusA_, next)) {
      scdTrippedAt_ = now;
    }
    return;
  }
  using A = m2::bits::SafetyA;
  using C = m2::bits::SafetyC;
  const auto enabledA =
      m2::bits::SafetyA::fromRaw(static_cast<uint8_t>(dataMemory(m2::dm::EnabledProtectionsA.address, 1)));
  const auto enabledC =
      m2::bits::SafetyC::fromRaw(static_cast<uint8_t>(dataMemory(m2::dm::EnabledProtectionsC.address, 1)));
  auto comparatorUs = [&](uint16_t delayAddress) { return (dataMemory(delayAddress, 1) + 2) * 3300ULL; };
  const int64_t occUv = dataMemory(m2::dm::OccThreshold.address, 1) * 2000LL;
  const int64_t ocd1Uv = dataMemory(m2::dm::Ocd1Threshold.address, 1) * 2000LL;
  const int64_t ocd2Uv = dataMemory(m2::dm::Ocd2Threshold.address, 1) * 2000LL;
  const uint8_t scdSetting = static_cast<uint8_t>(dataMemory(m2::dm::ScdThreshold.address, 1) & 0x0F);
  const uint32_t scdDelay = dataMemory(m2::dm::ScdDelay.address, 1);
  // Recovery first (Protections:Recovery:Time for OCC/OCD; SCD Recovery Time after the trip), so a condition
  // still present trips again in the same evaluation.
  const uint64_t recoveryUs = dataMemory(m2::dm::Time.address, 1) * 1000000ULL;
  const int32_t occRecoveryMa = static_cast<int16_t>(dataMemory(m2::dm::OccRecoveryThreshold.address, 2));
  const int32_t ocdRecoveryMa = static_cast<int16_t>(dataMemory(m2::dm::OcdRecoveryThreshold.address, 2));
  recoverAfter(now, A::occ_mask, currentMa_ <= occRecoveryMa, occRecoverSince_, recoveryUs, safetyStatusA_,
               next);
  const uint8_t ocdBits = A::ocd1_mask | A::ocd2_mask;
  if ((safetyStatusA_ & ocdBits) != 0) {
    uint8_t both = safetyStatusA_ & ocdBits;
    recoverAfter(now, both, currentMa_ >= ocdRecoveryMa, ocdRecoverSince_, recoveryUs, both, next);
    safetyStatusA_ = static_cast<uint8_t>((safetyStatusA_ & ~ocdBits) | both);
  } else {
    ocdRecoverSince_ = UINT64_MAX;
  }
  uint64_t scdSince = scdTrippedAt_;
  recoverAfter(now, A::scd_mask, true, scdSince, dataMemory(m2::dm::ScdRecoveryTime.address, 1) * 1000000ULL,
               safetyStatusA_, next);
  tripAfter(now, enabledA.occ(), senseUv >= occUv, A::occ_mask, occSince_,
            comparatorUs(m2::dm::OccDelay.address), safetyAlertA_, safetyStatusA_, next);
  tripAfter(now, enabledA.ocd1(), -senseUv >= ocd1Uv, A::ocd1_mask, ocd1Since_,
            comparatorUs(m2::dm::Ocd1Delay.address), safetyAlertA_, safetyStatusA_, next);
  tripAfter(now, enabledA.ocd2(), -senseUv >= ocd2Uv, A::ocd2_mask, ocd2Since_,
            comparatorUs(m2::dm::Ocd2Delay.address), safetyAlertA_, safetyStatusA_, next);
  if (tripAfter(now, enabledA.scd(), -senseUv >= kScdMv[scdSetting] * 1000LL, A::scd_mask, scdSince_,
                scdDelay > 1 ? (scdDelay - 1) * 15ULL : 0, safetyAlertA_, safetyStatusA_, next)) {
    scdTrippedAt_ = now;
    if (scdlCounter_ < 0xFF) ++scdlCounter_;
  }
  // The SCD latch.
  const uint8_t latchLimit = static_cast<uint8_t>(dataMemory(m2::dm::ScdlLatchLimit.address, 1));
  if (!enabledC.scdl()) {
    safetyStatusC_ &= static_cast<uint8_t>(~C::scdl_mask);
  } else if (latchLimit != 0 && scdlCounter_ >= latchLimit) {
    safetyStatusC_ |= C::scdl_mask;
  }
  const bool currentRecovery = (dataMemory(m2::dm::ProtectionConfiguration.address, 2) & (1U << 10)) != 0;
  const int32_t scdlRecoveryMa = static_cast<int16_t>(dataMemory(m2::dm::ScdlRecoveryThreshold.address, 2));
  const bool wasLatched = (safetyStatusC_ & C::scdl_mask) != 0;
  recoverAfter(now, C::scdl_mask, currentRecovery && currentMa_ >= scdlRecoveryMa, scdlRecoverSince_,
               dataMemory(m2::dm::ScdlRecoveryTime.address, 1) * 1000000ULL, safetyStatusC_, next);
  if (wasLatched && (safetyStatusC_ & C::scdl_mask) == 0) scdlCounter_ = 0;
}

// The host watchdog (SLUUBY2B 5.2 "Host Watchdog", SLUUCF2C the same; SLUUCJ0 6.15): enabled by Enabled
// Protections C[HWDF] (BQ7690x: B[HWD]), it trips when no communication was received for Protections:HWD:
// Delay seconds (BQ7690x Host Watchdog Timeout: codes 0..15 are 1..16 s, 16..255 are 20..976 s in 4 s steps;
// Safety Alert B[HWD] at half of it) and recovers as soon as communication is received (onStart()). There is
// no BQ769x2 alert for it.
void Bq769xEmulator::evaluateHostWatchdog(uint64_t now, uint64_t& next) {
  bool on;
  uint64_t delayUs;
  uint8_t* status;
  uint8_t bit;
  if (bq7690x()) {
    on = (dataMemory(m7::dm::EnabledProtectionsB.address, 1) & m7::bits::EnabledProtectionsB::hwd_mask) != 0;
    const uint32_t code = dataMemory(m7::dm::HostWatchdogTimeout.address, 1);
    delayUs = (code < 16 ? code + 1 : 20 + (code - 16) * 4) * 1000000ULL;
    status = &safetyStatusB_;
    bit = m7::bits::SafetyB::hwd_mask;
    const bool half = on && now >= lastCommUs_ + delayUs / 2;
    safetyAlertB_ = static_cast<uint8_t>((safetyAlertB_ & ~bit) | (half && (*status & bit) == 0 ? bit : 0));
  } else {
    on = (dataMemory(m2::dm::EnabledProtectionsC.address, 1) & m2::bits::SafetyC::hwdf_mask) != 0;
    delayUs = dataMemory(m2::dm::HwdDelay.address, 2) * 1000000ULL;
    status = &safetyStatusC_;
    bit = m2::bits::SafetyC::hwdf_mask;
  }
  if (!on || delayUs == 0 || now < lastCommUs_ + delayUs) {
    *status &= static_cast<uint8_t>(~bit);
    if (on && delayUs != 0)
      next = std::min(next,
                      lastCommUs_ + (bq7690x() && now < lastCommUs_ + delayUs / 2 ? delayUs / 2 : delayUs));
    return;
  }
  *status |= bit;
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
  uint8_t chgProtB = 0, dsgProtB = 0, chgProtC = 0, dsgProtC = 0;
  bool ctrlEn = true;
  bool hostChgOff = hostChgOff_;
  bool hostDsgOff = hostDsgOff_;
  bool sleepChg;
  if (bq7690x()) {
    // CHG / DSG FET Protections A (SLUUCJ0: DSG default 0xFF: CUV, SCD, OCD1, OCD2, HWD, OTD, UTD, OTINT; the
    // CHG layout taken from SLUUCY8, the BQ77307 on the same core, default 0xEF: COV, SCD, OCC, OTC, UTC,
    // OTINT). The register map has no default for them: the defaults are used.
    using A = m7::bits::SafetyStatusA;
    using B = m7::bits::SafetyB;
    chgProt = A::cov_mask | A::scd_mask | A::occ_mask;
    dsgProt = A::cuv_mask | A::scd_mask | A::ocd1_mask | A::ocd2_mask;
    chgProtB = B::otc_mask | B::utc_mask | B::otint_mask;
    dsgProtB = B::hwd_mask | B::otd_mask | B::utd_mask | B::otint_mask;
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
    // CHG / DSG FET Protections A, B, C (SLUUBY2B Settings:Protection): which status flags open which FET.
    chgProt = static_cast<uint8_t>(dataMemory(m2::dm::ChgFetProtectionsA.address, 1));
    dsgProt = static_cast<uint8_t>(dataMemory(m2::dm::DsgFetProtectionsA.address, 1));
    chgProtB = static_cast<uint8_t>(dataMemory(m2::dm::ChgFetProtectionsB.address, 1));
    dsgProtB = static_cast<uint8_t>(dataMemory(m2::dm::DsgFetProtectionsB.address, 1));
    chgProtC = static_cast<uint8_t>(dataMemory(m2::dm::ChgFetProtectionsC.address, 1));
    dsgProtC = static_cast<uint8_t>(dataMemory(m2::dm::DsgFetProtectionsC.address, 1));
    // CFETOFF / DFETOFF asserted force their FET off (SLUAAQ5: "when that pin is asserted from an external
    // source, the corresponding gate is then disabled"; DFETOFF with BOTHOFF both).
    bool both = false;
    if (fetOffPin(m2::dm::CfetoffPinConfig.address, cfetoffPin_, both)) hostChgOff = true;
    if (fetOffPin(m2::dm::DfetoffPinConfig.address, dfetoffPin_, both)) {
      hostDsgOff = true;
      hostChgOff = hostChgOff || both;
    }
    const auto options =
        m2::bits::FetOptions::fromRaw(static_cast<uint8_t>(dataMemory(m2::dm::FetOptions.address, 1)));
    ctrlEn = options.fet_ctrl_en() && fetEn_;
    sleepChg = options.sleepchg();
  }
  const bool drive = ctrlEn && (fetEn_ || bq7690x()) && !cfgUpdate_;
  const bool chgFault =
      (safetyStatusA_ & chgProt) != 0 || (safetyStatusB_ & chgProtB) != 0 || (safetyStatusC_ & chgProtC) != 0;
  const bool dsgFault =
      (safetyStatusA_ & dsgProt) != 0 || (safetyStatusB_ & dsgProtB) != 0 || (safetyStatusC_ & dsgProtC) != 0;
  chgOn_ = drive && !hostChgOff && !chgFault && (!sleeping_ || sleepChg);
  dsgOn_ = drive && !hostDsgOff && !dsgFault;

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
    if ((safetyStatusB_ | safetyStatusC_) != 0) raw |= A::ssbc_mask;
    if ((safetyAlertA_ & dataMemory(m2::dm::SfAlertMaskA.address, 1)) != 0 ||
        (safetyAlertB_ & dataMemory(m2::dm::SfAlertMaskB.address, 1)) != 0 ||
        (safetyAlertC_ & dataMemory(m2::dm::SfAlertMaskC.address, 1)) != 0)
      raw |= A::msk_sfalert_mask;
    if (!chgOn_) raw |= A::xchg_mask;
    if (!dsgOn_) raw |= A::xdsg_mask;
    if (cbActive_ != 0) raw |= A::cb_mask;
  }
  alarmStatus_ |= static_cast<uint16_t>(raw & ~alarmRaw_ & alarmEnable_);
  alarmRaw_ = raw;
  setAlert(alarmStatus_ != 0);
  updateSleep();
}

// Whether a CFETOFF / DFETOFF pin at `level` is asserted as its Pin Config says (SLUAAQ5; TI's example
// comments: 0x02 that FET only, 0x42 both): PIN_FXN 2 is the FET-off function, OPT5 selects active-low
// (SLUAAQ5 "DFETOFF Pin Config[OPT5]"), OPT4 BOTHOFF (DFETOFF only). Any other function ignores the pin.
bool Bq769xEmulator::fetOffPin(uint16_t configAddress, bool level, bool& both) const {
  const uint8_t cfg = static_cast<uint8_t>(dataMemory(configAddress, 1));
  if ((cfg & 0x03) != 2) return false;
  const bool asserted = level != ((cfg & 0x80) != 0);
  if (asserted && (cfg & 0x40) != 0) both = true;
  return asserted;
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
