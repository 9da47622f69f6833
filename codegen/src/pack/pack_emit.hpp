// The C++ a pack file becomes: packs/<name>.hpp, namespace fw::packs::<name> (every value constexpr, in
// flash), and the image's packs/selected.hpp, which names one of them fw::pack.
//
// packs/<name>.hpp holds
//   kName, kCells, kCellInputs[] (the device input of each cell, 1-based, bottom first),
//   kCurrentLsbTenthMa (the device's user-amps unit), kShuntMicroOhm,
//   kLimitRows[] (app::LimitRow, FaultId order), kStaleScans, kCommLossScans,
//   kDeviceSettings[] (BQ769x2 / BQ7690x: the pack's start-up settings as typed register codes),
//   kSoc (app::SocConfig; devices that count charge), kBalancing (app::BalancingConfig, when the file has
//   it), kCanBaseId, kCanPeriodMs, kCanSlowEvery.
#pragma once

#include <string>

#include "pack/pack_check.hpp"

namespace regmapgen::pack {

// `source` names the pack file in the header's first line.
std::string emitPackHeader(const Resolved& pack, const std::string& source);
std::string emitSelectedHeader(const Resolved& pack);

}  // namespace regmapgen::pack
