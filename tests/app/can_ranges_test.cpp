// Every signal of the CAN catalogue covers the largest pack the firmware supports, and every signal that can
// lack a reading has a not-available value outside that range. The ranges are computed here from bms.yaml as
// regmapgen reads it (length, signedness, factor, offset, not_available), not from the generated files, and
// compared with what the largest configuration needs: kMaxBoards boards of kMaxCellsPerBoard cells of up to
// 5 V (64 x 16 x 5 V = 5 120 V), the current the monitors report, the temperatures a BoardSample can hold
// and indices up to 64 x 16.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <string>

#include "app/pack/pack_view.hpp"
#include "app/protection/protection.hpp"
#include "app/store/records.hpp"
#include "can/can_model.hpp"

namespace {

using regmapgen::Diagnostics;
using regmapgen::Sources;

// What one signal must carry in the largest configuration (physical units of bms.yaml), and whether it can
// lack a reading (then it needs a not-available value outside [lo, hi]).
struct Need {
  double lo;
  double hi;
  bool canLack;
};

constexpr double kCellMaxMv = 6250;  // the highest cell reading: BQ79616 full scale, int16 x 190.73 uV
constexpr double kCellInputV = 5.0;  // every supported monitor's cell input range is 0..5 V
constexpr int kBoards = fw::app::kMaxBoards;
constexpr int kCells = fw::app::kMaxCellsPerBoard;
constexpr int kTemps = fw::app::kMaxTempsPerBoard;
// Temperatures are int16 in 0.1 K and never below 0 K: 0 .. 32 767 dK.
constexpr double kTempLo = -273.15;
constexpr double kTempHi = 32767 * 0.1 - 273.15;
// Current: the BQ769x2 CC2 (1 mA userA) and the BQ4050 Current() are int16 mA.
constexpr double kCurrentA = 32.768;
constexpr double kFaultBits = (1 << fw::app::kFaultCount) - 1;

// Commands and their answers: a setting's value is at most the discharge over-current bound (-40 000 mA), in
// mV, mA or 0.1 K; node numbers 1..254 (255 = all); identifiers 11 bits; the chip's TraceId 32 bits.
constexpr double kSettingLo = -40000, kSettingHi = 20000, kSettings = 11;

std::map<std::string, Need> commandNeeds() {
  std::map<std::string, Need> t;
  for (const char* m : {"ClearFaults", "PathRequest", "BalancingMode", "Identify", "SettingRead",
                        "SettingWrite", "EnterBootloader", "StorageMode"}) {
    t[std::string(m) + ".Crc"] = {0, 255, false};
    t[std::string(m) + ".Counter"] = {0, 15, false};
    t[std::string(m) + ".Target"] = {1, 255, false};
  }
  for (const char* m : {"CommandAck", "IdentifyVersion", "IdentifyChip", "SettingValue", "SettingRange"})
    t[std::string(m) + ".Node"] = {1, 254, false};
  t["PathRequest.ChargeOff"] = t["PathRequest.DischargeOff"] = {0, 1, false};
  t["BalancingMode.Mode"] = {0, 2, false};
  t["BalancingMode.Board"] = {0, kBoards - 1, false};
  t["BalancingMode.CellMask"] = {0, (1 << kCells) - 1, false};
  t["SettingRead.Setting"] = t["SettingWrite.Setting"] = t["SettingValue.Setting"] = {0, kSettings, false};
  t["SettingRange.Setting"] = {0, kSettings, false};
  t["SettingWrite.Value"] = t["SettingValue.Value"] = {kSettingLo, kSettingHi, false};
  t["SettingRange.Min"] = t["SettingRange.Max"] = {kSettingLo, kSettingHi, false};
  t["SettingValue.Unit"] = {0, 2, false};
  t["SettingValue.Source"] = {0, 3, false};  // app/command/settings.hpp SettingSource
  t["EnterBootloader.TraceId"] = t["IdentifyChip.TraceId"] = {0, 4294967295.0, false};
  t["EnterBootloader.Key"] = {0, 255, false};
  t["CommandAck.Command"] = {0, 0x7FF, false};
  t["CommandAck.Counter"] = {0, 15, false};
  t["CommandAck.Result"] = {0, 12, false};  // app/command/result.hpp Result
  t["StorageMode.Mode"] = {0, 1, false};
  t["CommandAck.Rejected"] = {0, 65535, false};
  t["IdentifyVersion.VersionMajor"] = t["IdentifyVersion.VersionMinor"] = {0, 255, false};
  t["IdentifyVersion.VersionPatch"] = {0, 255, false};
  t["IdentifyVersion.BuildId"] = {0, 0xFFFFFF, false};
  t["IdentifyVersion.Image"] = {0, 5, false};
  t["IdentifyChip.ResetCause"] = {0, 31, false};  // SYSCTL RSTCAUSE ID, 5 bits
  t["IdentifyChip.PartNumber"] = {0, 65535, false};
  return t;
}

const std::map<std::string, Need>& needs() {
  static const std::map<std::string, Need> table = [] {
    std::map<std::string, Need> t = commandNeeds();
    t.merge(std::map<std::string, Need>{
        {"PackSummary.PackVoltage", {0, kBoards * kCells * kCellInputV, true}},
        {"PackSummary.PackCurrent", {-kCurrentA, kCurrentA - 0.001, true}},
        {"PackSummary.StateOfCharge", {0, 100, true}},
        // A pack file's capacity is at most 1 048 574 mAh (regmapgen pack); the gauge's words are 16 bits.
        {"StateOfCharge.Soc", {0, 100, true}},
        {"StateOfCharge.RemainingCapacity", {0, 1048574, true}},
        {"StateOfCharge.FullChargeCapacity", {0, 1048574, true}},
        {"StateOfCharge.Basis", {1, 5, true}},  // fw::app::SocBasis, Unknown sent as not available
        {"PackSummary.ChargeFet", {0, 1, true}},
        {"PackSummary.DischargeFet", {0, 1, true}},
        {"PackSummary.FaultOutput", {0, 1, false}},
        {"PackSummary.DataValid", {0, 1, false}},
        {"PackSummary.Counter", {0, 15, false}},
        {"PackSummary.ActiveFaults", {0, kFaultBits, false}},
        {"CellExtremes.MaxCellVoltage", {0, kCellMaxMv, true}},
        {"CellExtremes.MinCellVoltage", {0, kCellMaxMv, true}},
        {"CellExtremes.MaxCellIndex", {0, kBoards * kCells - 1, true}},
        {"CellExtremes.MinCellIndex", {0, kBoards * kCells - 1, true}},
        {"TemperatureExtremes.MaxTemperature", {kTempLo, kTempHi, true}},
        {"TemperatureExtremes.MinTemperature", {kTempLo, kTempHi, true}},
        {"TemperatureExtremes.MaxTemperatureIndex", {0, kBoards * kTemps - 1, true}},
        {"TemperatureExtremes.MinTemperatureIndex", {0, kBoards * kTemps - 1, true}},
        {"ProtectionEvent.ActiveFaults", {0, kFaultBits, false}},
        {"ProtectionEvent.NewlyTripped", {0, kFaultBits, false}},
        {"ProtectionEvent.NewlyCleared", {0, kFaultBits, false}},
        {"ProtectionEvent.CommErrors", {0, 65535, false}},
        {"CellVoltages.Board", {0, kBoards - 1, false}},
        {"CellVoltages.FrameIndex", {0, (kCells + 2) / 3 - 1, false}},
        {"CellVoltages.Status", {0, 4, false}},
        {"CellVoltages.Cell", {0, kCellMaxMv, true}},
        {"Temperatures.Board", {0, kBoards - 1, false}},
        {"Temperatures.FrameIndex", {0, (kTemps + 2) / 3 - 1, false}},
        {"Temperatures.Status", {0, 3, false}},
        {"Temperatures.Temp", {kTempLo, kTempHi, true}},
        {"StorageStatus.Mode", {0, 1, false}},
        {"StorageStatus.DeviceSleep", {0, 1, false}},
        {"StorageStatus.ScanPeriod", {100, 25000, false}},  // regmapgen pack: at most 250 scan periods
        // Saturated short of not available (frame_plan.cpp); the Instant wraps after 71.6 minutes anyway.
        {"StorageStatus.MeasurementAge", {0, 16777214, true}},
        {"BalancingStatus.Board", {0, kBoards - 1, false}},
        {"BalancingStatus.Mode", {0, 2, false}},   // fw::app::BalancingMode
        {"BalancingStatus.State", {0, 8, false}},  // fw::app::BalancingState
        {"BalancingStatus.Cells", {0, (1 << kCells) - 1, false}},
        {"BalancingStatus.Time", {0, 194 * 86400, false}},  // 194 days of seconds
        // Raw BQ79616 codes, any int16 (seed 001's layout has no room for a not-available value).
        {"TiCellVoltages.VCell", {-32768 * 0.00019073, 32767 * 0.00019073, false}},
        // Startup: RSTCAUSE.ID is 5 bits; a version part is a byte; fw::Module goes up to 99 (Test); a fault
        // line or code up to 0xFFFE (HardFault, bsp/mspm0/fault.hpp), so 0xFFFF can mean "no record".
        {"Startup.ResetCause", {0, 31, false}},
        {"Startup.FirmwareMajor", {0, 255, false}},
        {"Startup.FirmwareMinor", {0, 255, false}},
        {"Startup.FirmwarePatch", {0, 255, false}},
        {"Startup.FaultModule", {0, 99, true}},
        {"Startup.FaultLine", {0, 0xFFFE, true}},
        {"Startup.ProtectionLogEntries", {0, fw::app::store::ProtectionLogRecord::kEntries, true}},
        {"Startup.FaultSource", {0, 2, true}},
    });
    return t;
  }();
  return table;
}

regmapgen::can::Catalogue load(Sources& sources) {
  std::string text;
  EXPECT_TRUE(regmapgen::readFile(BMS_CAN_YAML, text)) << BMS_CAN_YAML;
  const int file = sources.add(BMS_CAN_YAML, text);
  Diagnostics diag(sources);
  auto cat = regmapgen::can::buildCatalogue(sources, file, diag);
  EXPECT_EQ(diag.errorCount(), 0u);
  return cat;
}

double physical(const regmapgen::can::Signal& s, int64_t raw) {
  return static_cast<double>(raw) * s.factorValue + s.offsetValue;
}

TEST(CanRanges, EverySignalCoversTheLargestPack) {
  Sources sources;
  const auto cat = load(sources);
  size_t checked = 0;
  for (const auto& m : cat.messages) {
    for (const auto& s : m.signals) {
      const std::string name = m.name + "." + s.name;
      const auto it = needs().find(name);
      ASSERT_NE(it, needs().end()) << name << " has no entry in needs(): say what it must carry";
      const Need& need = it->second;
      // The readings' range: every raw value but the not-available one (regmapgen leaves it out at either
      // end). Computed here from length and signedness, not taken from the generator.
      int64_t lo = s.isSigned ? -(int64_t{1} << (s.length - 1)) : 0;
      int64_t hi = s.isSigned ? (int64_t{1} << (s.length - 1)) - 1 : (int64_t{1} << s.length) - 1;
      if (s.notAvailable == lo) ++lo;
      if (s.notAvailable == hi) --hi;
      const double a = physical(s, lo), b = physical(s, hi);
      const double pLo = std::min(a, b), pHi = std::max(a, b);
      const double tolerance = std::fabs(s.factorValue) / 2;  // a value rounds to the nearest step
      EXPECT_LE(pLo, need.lo + tolerance) << name << ": readings start at " << pLo << " " << s.unit;
      EXPECT_GE(pHi, need.hi - tolerance)
          << name << ": readings end at " << pHi << " " << s.unit << ", the largest pack needs " << need.hi;
      if (need.canLack) {
        ASSERT_TRUE(s.notAvailable.has_value()) << name << " can lack a reading but has no not_available";
        const double na = physical(s, *s.notAvailable);
        EXPECT_TRUE(na < need.lo - tolerance || na > need.hi + tolerance)
            << name << ": not-available decodes as " << na << ", a value the pack can have";
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, needs().size()) << "needs() names a signal the catalogue no longer has";
}

TEST(CanRanges, GroupsAndFrameIndicesHoldTheLargestBoard) {
  Sources sources;
  const auto cat = load(sources);
  for (const auto& m : cat.messages) {
    const auto* mux = m.multiplexer();
    for (const auto& s : m.signals) {
      if (s.total == 0) continue;
      const int items = m.name == "CellVoltages" ? kCells : kTemps;
      EXPECT_GE(static_cast<int>(s.total), items) << m.name << "." << s.name;
      ASSERT_NE(mux, nullptr);
      EXPECT_LE((s.total + s.count - 1) / s.count, 1U << mux->length) << m.name;
    }
  }
}

}  // namespace
