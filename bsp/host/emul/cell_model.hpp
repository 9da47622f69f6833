// CellModel: what balancing does to an emulated cell (the BQ769x2/BQ7690x and BQ79616 emulators). A balanced
// cell loses V / balanceOhms through the balancing path, and its voltage falls by cellUvPerMah for every mAh
// it lost: a linear cell, 700 mV from empty to full over its capacity.
//
// balanceOhms: the path is the two cell input resistors and the device's internal balancing FET (BQ79616:
// I = V / (2 x RCB + RDS(ON)), SLVAE87A section 4.2). 68 ohm = 2 x 20 ohm + 28 ohm, 28 ohm being the typical
// internal balancing resistance of the BQ769x2 family (BQ76972 data sheet, R(CB) 15 / 28 / 46 ohm): about
// 54 mA from a 3.7 V cell. The EVMs' own resistor values (their user guides) were not retrievable
// (regmaps/README.md, open questions); a test or scenario that depends on another value sets it.
// cellUvPerMah: a 2.5 Ah Li-ion cell by default; a scenario scales it down so a run converges in seconds
// (bms-sim `cell-capacity`).
#pragma once

#include <cstdint>

namespace bsp::host {

struct CellModel {
  static constexpr uint32_t kSpanUv = 700000;  // empty to full
  static constexpr uint32_t uvPerMah(uint32_t capacityMah) {
    return capacityMah == 0 ? 0 : kSpanUv / capacityMah;
  }
  uint32_t balanceOhms = 68;
  uint32_t cellUvPerMah = uvPerMah(2500);
};

// The voltage drop of a cell that lost `chargeMaUs` (mA x us): mA x us -> mAh is / 3.6e9, uV -> mV / 1e3.
constexpr int64_t bleedDropMv(int64_t chargeMaUs, const CellModel& m) {
  return chargeMaUs * m.cellUvPerMah / 3600000000000LL;
}
constexpr int64_t bleedDropUv(int64_t chargeMaUs, const CellModel& m) {
  return chargeMaUs * m.cellUvPerMah / 3600000000LL;
}

}  // namespace bsp::host
