#include "app/monitors/bq769x_app.hpp"

namespace fw::app {

namespace b769 = drivers::bq769x2;

namespace {

constexpr uint8_t kCharge = static_cast<uint8_t>(Action::ChargeOff);
constexpr uint8_t kDischarge = static_cast<uint8_t>(Action::DischargeOff);

// What both families' measurements carry the same way: cells, time and current.
template <class Measurement>
inline void toSampleCommon(const Measurement& m, uint8_t cells, BoardSample& sample, PackView& view) {
  for (uint8_t c = 0; c < cells; ++c)
    sample.cellMv[c] = m.reg.cellMv[c];
  sample.takenAt = m.takenAt;
  sample.valid = true;
  view.hasCurrent = true;
  view.currentMa = b769::currentMa(m.reg.current);  // CC2 in userA, 1 mA by default (DA Configuration)
}

// The paths a flag set concerns: `charge` and `discharge` are the flags that turn that FET off, `both` the
// ones that turn both off.
constexpr uint8_t paths(uint32_t flags, uint32_t charge, uint32_t discharge, uint32_t both) {
  return static_cast<uint8_t>((((flags & (charge | both)) != 0) ? kCharge : 0) |
                              (((flags & (discharge | both)) != 0) ? kDischarge : 0));
}

}  // namespace

// BQ769x2: each protection's FET (SLUUBY2B 5.2, the CHG/DSG FET Protections A/B/C defaults, which the
// settings table keeps but for SCD's CHG action): COV, OCC, OTC, UTC, COVL, PTO the charge FET; CUV,
// OCD1/2/3, SCD, SCDL, OCDL, OTD, UTD the discharge FET; OTF, OTINT, UTINT and the host watchdog both, as
// does any permanent failure. An alert (the condition is present and its delay runs) counts as its trip: the
// device is about to act, and the flag does not flap between the two. Safety Alert C's latch bits count down
// a counter after a trip and PTOS is a suspend state, so only its OCD3 alert counts.
uint8_t deviceBlocks(const b769::Bq769x2Measurement& m) {
  using A = b769::map::bits::SafetyA;
  using B = b769::map::bits::SafetyB;
  using C = b769::map::bits::SafetyC;
  const auto& r = m.reg;
  const uint8_t a = static_cast<uint8_t>(r.safetyAlertA.raw() | r.safetyStatusA.raw());
  const uint8_t b = static_cast<uint8_t>(r.safetyAlertB.raw() | r.safetyStatusB.raw());
  const uint8_t c = static_cast<uint8_t>(r.safetyStatusC.raw() |
                                         (r.safetyAlertC.raw() & b769::map::bits::SafetyAlertC::ocd3_mask));
  const bool pf = (r.pfStatusA.raw() | r.pfStatusB.raw() | r.pfStatusC.raw() | r.pfStatusD.raw()) != 0;
  return static_cast<uint8_t>(
      paths(a, A::cov_mask | A::occ_mask, A::cuv_mask | A::ocd1_mask | A::ocd2_mask | A::scd_mask, 0) |
      paths(b, B::otc_mask | B::utc_mask, B::otd_mask | B::utd_mask,
            B::otf_mask | B::otint_mask | B::utint_mask) |
      paths(c, C::covl_mask | C::pto_mask, C::ocd3_mask | C::scdl_mask | C::ocdl_mask, C::hwdf_mask) |
      (pf ? kCharge | kDischarge : 0));
}

// BQ7690x (SLUUCJ0 6.3-6.15, the CHG/DSG FET Protections A defaults): COV, OCC, OTC, UTC the charge FET;
// CUV, SCD, OCD1/2, OTD, UTD the discharge FET; the current latch (it holds whichever current fault latched),
// REGOUT, OTINT, the host watchdog and the VREF/VSS diagnostics both.
uint8_t deviceBlocks(const b769::Bq7690xMeasurement& m) {
  using A = b769::map7690x::bits::SafetyStatusA;
  using B = b769::map7690x::bits::SafetyB;
  const auto& r = m.reg;
  const uint8_t a = static_cast<uint8_t>(r.safetyAlertA.raw() | r.safetyStatusA.raw());
  const uint8_t b = static_cast<uint8_t>(r.safetyAlertB.raw() | r.safetyStatusB.raw());
  return static_cast<uint8_t>(paths(a, A::cov_mask | A::occ_mask,
                                    A::cuv_mask | A::scd_mask | A::ocd1_mask | A::ocd2_mask,
                                    A::curlatch_mask | A::regout_mask) |
                              paths(b, B::otc_mask | B::utc_mask, B::otd_mask | B::utd_mask,
                                    B::otint_mask | B::hwd_mask | B::vref_mask | B::vss_mask));
}

void toSample(const b769::Bq769x2Measurement& m, uint8_t cells, BoardSample& sample, PackView& view) {
  toSampleCommon(m, cells, sample, view);
  view.deviceBlocks = deviceBlocks(m);
  // FET Status (0x7F, SLUUBY2B 12.1): what the FETs do, never the host's intent.
  view.devicePaths = static_cast<uint8_t>((m.reg.fetStatus.chg_fet() ? kCharge : 0) |
                                          (m.reg.fetStatus.dsg_fet() ? kDischarge : 0));
  // Internal, TS1 and TS3 (seed 000's board has thermistors on TS1 and TS3), all in 0.1 K.
  sample.tempDeciK[0] = b769::deciKelvin(b769::map::cmd::IntTemperature, m.reg.intTemp);
  sample.tempDeciK[1] = b769::deciKelvin(b769::map::cmd::Ts1Temperature, m.reg.ts[0]);
  sample.tempDeciK[2] = b769::deciKelvin(b769::map::cmd::Ts3Temperature, m.reg.ts[2]);
}

void toSample(const b769::Bq7690xMeasurement& m, uint8_t cells, BoardSample& sample, PackView& view) {
  toSampleCommon(m, cells, sample, view);
  view.deviceBlocks = deviceBlocks(m);
  // Battery Status[CHG], [DSG] (SLUUCJ0): the FET drivers' state.
  view.devicePaths = static_cast<uint8_t>((m.reg.batteryStatus.chg() ? kCharge : 0) |
                                          (m.reg.batteryStatus.dsg() ? kDischarge : 0));
  // BQ7690x Int Temperature is in whole degrees C (regmaps/README.md deviation log): to 0.1 K.
  sample.tempDeciK[0] = b769::deciKelvin(b769::map7690x::cmd::IntTemperature, m.reg.intTemp);
}

}  // namespace fw::app
