#include "app/monitors/bq769x_app.hpp"

namespace fw::app {

namespace b769 = drivers::bq769x2;

namespace {

// What both families' measurements carry the same way: cells, time, current and the device's fault flag.
template <class Measurement>
inline void toSampleCommon(const Measurement& m, uint8_t cells, BoardSample& sample, PackView& view) {
  for (uint8_t c = 0; c < cells; ++c)
    sample.cellMv[c] = m.reg.cellMv[c];
  sample.takenAt = m.takenAt;
  sample.valid = true;
  view.hasCurrent = true;
  view.currentMa = b769::currentMa(m.reg.current);  // CC2 in userA, 1 mA by default (DA Configuration)
  view.deviceFault = m.deviceFault();
}

}  // namespace

void toSample(const b769::Bq769x2Measurement& m, uint8_t cells, BoardSample& sample, PackView& view) {
  toSampleCommon(m, cells, sample, view);
  // Internal, TS1 and TS3 (seed 000's board has thermistors on TS1 and TS3), all in 0.1 K.
  sample.tempDeciK[0] = b769::deciKelvin(b769::map::cmd::IntTemperature, m.reg.intTemp);
  sample.tempDeciK[1] = b769::deciKelvin(b769::map::cmd::Ts1Temperature, m.reg.ts[0]);
  sample.tempDeciK[2] = b769::deciKelvin(b769::map::cmd::Ts3Temperature, m.reg.ts[2]);
}

void toSample(const b769::Bq7690xMeasurement& m, uint8_t cells, BoardSample& sample, PackView& view) {
  toSampleCommon(m, cells, sample, view);
  // BQ7690x Int Temperature is in whole degrees C (regmaps/README.md deviation log): to 0.1 K.
  sample.tempDeciK[0] = b769::deciKelvin(b769::map7690x::cmd::IntTemperature, m.reg.intTemp);
}

}  // namespace fw::app
