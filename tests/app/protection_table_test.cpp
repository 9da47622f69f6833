// README.md's protection table (issue 24 item 10) is generated from the tables the firmware runs: the
// firmware limits (app/protection/default_limits.hpp kLimits) and the device backstops the start-up writes
// (app/monitors/bq769x_settings.hpp), so it cannot go stale. The test rebuilds the table and compares it with
// the text between README.md's "protection-table" markers; on a difference it prints the table to paste.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "app/monitors/bq769x_settings.hpp"
#include "app/pack/pack_view.hpp"
#include "app/protection/default_limits.hpp"
#include "drivers/bq79616/open_wire.hpp"

namespace {

namespace m2 = fw::regmap::bq769x2;
namespace m7 = fw::regmap::bq7690x;
using fw::app::Action;
using fw::app::FaultId;
using fw::app::LimitRow;

int64_t value(std::span<const fw::drivers::bq769x2::Setting> table, uint16_t address, bool isSigned = false) {
  for (const auto& s : table) {
    if (s.address != address) continue;
    if (!isSigned) return s.value;
    return s.size == 1 ? static_cast<int8_t>(s.value) : static_cast<int16_t>(s.value);
  }
  ADD_FAILURE() << "0x" << std::hex << address << " not in the table";
  return 0;
}
int64_t bq76952(uint16_t address, bool isSigned = false) {
  return value(fw::app::kBq76952Settings, address, isSigned);
}
int64_t bq76907(uint16_t address) {
  return value(fw::app::kBq76907Settings, address);
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}
std::string degC(int32_t deciK) {
  return fmt("%.1f degC", (deciK - fw::app::kDeciKelvinAtZeroCelsius) / 10.0);
}
std::string scans(uint8_t n) {
  return std::to_string(n) + (n == 1 ? " scan" : " scans");
}
std::string ms33(int64_t setting) {  // BQ769x2 3.3 ms x (2 + setting)
  return fmt("%.1f ms", 3.3 * static_cast<double>(setting + 2));
}

// The link rules wait for the first bring-up (PackView::inStartupGrace(): Device::firstDataBound()).
constexpr const char* kGrace = "not before the first bring-up's bound";

// What each rule compares, how it is worded.
struct Words {
  std::string trip, clear;
};
Words words(const LimitRow& r) {
  const std::string t = std::to_string(r.trip), c = std::to_string(r.clear);
  switch (r.fault) {
    case FaultId::CellOvervoltage:
      return {"highest cell >= " + t + " mV", "< " + c + " mV"};
    case FaultId::CellUndervoltage:
      return {"lowest cell <= " + t + " mV", "> " + c + " mV"};
    case FaultId::ChargeOvercurrent:
      return {"current >= " + t + " mA (charging)", "current < " + c + " mA (a discharge)"};
    case FaultId::DischargeOvercurrent:
      return {"current <= " + t + " mA (discharging)", "current > " + c + " mA (a charge)"};
    case FaultId::OvertempDischarge:
    case FaultId::OvertempCharge:
      return {"highest temperature >= " + degC(r.trip), "< " + degC(r.clear)};
    case FaultId::UndertempDischarge:
    case FaultId::UndertempCharge:
      return {"lowest temperature <= " + degC(r.trip), "> " + degC(r.clear)};
    case FaultId::DeviceSafety:
      return {"the monitor reports a protection alert or trip of its own, or its fault line asserts",
              "no such flag in a scan"};
    case FaultId::StaleData:
      return {"no valid measurement for " + std::to_string(fw::app::kDefaultLimits.staleAfter.toMs()) +
                  " ms (" + kGrace + ")",
              "a fresh valid measurement"};
    case FaultId::CommLoss:
      return {
          std::to_string(fw::app::kDefaultLimits.commLossScans) + " scans in a row failed (" + kGrace + ")",
          "a scan succeeds"};
    case FaultId::OpenWire:
      return {
          "a sense wire is open: two neighbouring cells more than " +
              std::to_string(fw::app::kOpenWireStepMv) + " mV apart, a cell below " +
              std::to_string(fw::app::kCellFloorMv) +
              " mV, or the monitor says so (BQ79616: the devices' own VC open-wire check, every second and "
              "after every bring-up, names a cell below " +
              std::to_string(fw::drivers::bq79616::OpenWireCheck::kThresholdMv) +
              " mV with its VC sinks on: that cell and the one above it; BQ4050: a refused cell word)",
          "the readings show none (BQ79616: and the last check named no cell)"};
    case FaultId::CommErrorRate:
      return {t + " of the last " + std::to_string(fw::app::kDefaultLimits.rateWindow) +
                  " scan attempts failed (" + kGrace + ")",
              "none of the last " + std::to_string(fw::app::kDefaultLimits.rateWindow) + " failed"};
  }
  return {};
}

// Latching (Rule::latchTrips, tripDecayS): when it latches, and what ends it (ClearFaults, once the condition
// is gone: for a current limit, no more than the clear threshold's magnitude flowing the tripped way).
std::string latch(const LimitRow& r) {
  const uint8_t trips = r.latch ? 1 : r.latchTrips;
  if (trips == 0) return "no";
  std::string when = trips == 1 ? "on its first trip" : "on trip " + std::to_string(trips);
  if (trips > 1 && r.tripDecayS != 0)
    when += ", each within " + std::to_string(r.tripDecayS) + " s of the one before";
  std::string gone = "the condition is gone";
  const int32_t magnitude = r.clear < 0 ? -r.clear : r.clear;
  if (r.fault == FaultId::DischargeOvercurrent) gone = "current > " + std::to_string(-magnitude) + " mA";
  if (r.fault == FaultId::ChargeOvercurrent) gone = "current < " + std::to_string(magnitude) + " mA";
  return when + "; then until ClearFaults with " + gone;
}

std::string action(const LimitRow& r) {
  if (r.fault == FaultId::DeviceSafety)
    return "the paths the device's flags concern (both on the fault line)";
  switch (r.action) {
    case Action::ChargeOff:
      return "charge off";
    case Action::DischargeOff:
      return "discharge off";
    case Action::AllOff:
      return "both off";
    case Action::None:
      return "none";
  }
  return "";
}

// The device protection behind each rule, from the settings tables (SLUUBY2B / SLUUCJ0 units).
std::string backstop(FaultId f) {
  const auto scdMv = [](int64_t s) {
    constexpr int kMv[16] = {10, 20, 40, 60, 80, 100, 125, 150, 175, 200, 250, 300, 350, 400, 450, 500};
    return kMv[s & 15];
  };
  const double shuntMohm = fw::packs::bq76952_evm::kShuntMicroOhm / 1000.0;
  switch (f) {
    case FaultId::CellOvervoltage:
      return "BQ76952 COV " + fmt("%.0f mV", bq76952(m2::dm::CovThreshold.address) * 50.6) + " / " +
             ms33(bq76952(m2::dm::CovDelay.address)) + "; BQ7690x COV " +
             std::to_string(bq76907(m7::dm::CellOvervoltageProtectionThreshold.address)) + " mV / " +
             std::to_string(bq76907(m7::dm::CellOvervoltageProtectionDelay.address)) + " ADSCAN";
    case FaultId::CellUndervoltage:
      return "BQ76952 CUV " + fmt("%.0f mV", bq76952(m2::dm::CuvThreshold.address) * 50.6) + " / " +
             ms33(bq76952(m2::dm::CuvDelay.address)) + "; BQ7690x CUV " +
             std::to_string(bq76907(m7::dm::CellUndervoltageProtectionThreshold.address)) + " mV / " +
             std::to_string(bq76907(m7::dm::CellUndervoltageProtectionDelay.address)) + " ADSCAN";
    case FaultId::ChargeOvercurrent:
      return "BQ76952 OCC " + fmt("%.0f A", bq76952(m2::dm::OccThreshold.address) * 2 / shuntMohm) + " / " +
             ms33(bq76952(m2::dm::OccDelay.address));
    case FaultId::DischargeOvercurrent:
      return "BQ76952 OCD1 " + fmt("%.0f A", bq76952(m2::dm::Ocd1Threshold.address) * 2 / shuntMohm) + " / " +
             ms33(bq76952(m2::dm::Ocd1Delay.address)) + ", SCD " +
             fmt("%.0f A", scdMv(bq76952(m2::dm::ScdThreshold.address)) / shuntMohm) + " / " +
             std::to_string((bq76952(m2::dm::ScdDelay.address) - 1) * 15) +
             " us (latched, SCDL); BQ7690x SCD " +
             fmt("%.0f A",
                 scdMv(bq76907(m7::dm::ShortCircuitInDischargeProtectionThreshold.address)) / shuntMohm);
    case FaultId::OvertempDischarge:
      return "BQ76952 OTD " + std::to_string(bq76952(m2::dm::OtdThreshold.address, true)) + " degC, OTF " +
             std::to_string(bq76952(m2::dm::OtfThreshold.address)) + " degC, OTINT " +
             std::to_string(bq76952(m2::dm::OtintThreshold.address, true)) + " degC / " +
             std::to_string(bq76952(m2::dm::OtdDelay.address)) + " s";
    case FaultId::UndertempDischarge:
      return "BQ76952 UTD " + std::to_string(bq76952(m2::dm::UtdThreshold.address, true)) + " degC, UTINT " +
             std::to_string(bq76952(m2::dm::UtintThreshold.address, true)) + " degC / " +
             std::to_string(bq76952(m2::dm::UtdDelay.address)) + " s";
    case FaultId::OvertempCharge:
      return "BQ76952 OTC " + std::to_string(bq76952(m2::dm::OtcThreshold.address, true)) + " degC / " +
             std::to_string(bq76952(m2::dm::OtcDelay.address)) + " s";
    case FaultId::UndertempCharge:
      return "BQ76952 UTC " + std::to_string(bq76952(m2::dm::UtcThreshold.address, true)) + " degC / " +
             std::to_string(bq76952(m2::dm::UtcDelay.address)) + " s";
    case FaultId::CommLoss:
    case FaultId::StaleData:
      return "BQ76952 host watchdog " + std::to_string(bq76952(m2::dm::HwdDelay.address)) +
             " s (both FETs) and the CFETOFF/DFETOFF pins; BQ7690x host watchdog " +
             std::to_string(bq76907(m7::dm::HostWatchdogTimeout.address) + 1) + " s (discharge)";
    case FaultId::DeviceSafety:
      return "(the device's own)";
    case FaultId::OpenWire:
      return "the BQ79616 checks itself (VC open-wire diagnostic, read by the firmware); the BQ76952 drains "
             "a "
             "detached input every " +
             std::to_string(bq76952(m2::dm::CheckTime.address)) +
             " s (Cell Open-Wire Check Time): its cell reads low (device CUV), the one above high (COV); VC0 "
             "has no sink; the BQ7690x's check is not configured";
    case FaultId::CommErrorRate:
      return "BQ76952 the CFETOFF/DFETOFF pins (the scans that succeed feed the host watchdog); none on the "
             "BQ7690x";
  }
  return "";
}

std::string table() {
  std::ostringstream o;
  o << "| fault | trips when | clears when | trip after | action | latch | recovery after | device backstop "
       "|\n"
       "|---|---|---|---|---|---|---|---|\n";
  for (const LimitRow& r : fw::app::kLimits) {
    const Words w = words(r);
    std::string after = scans(r.debounce);
    // The BQ79616's own check runs every openWireEvery scans (bq79616_app.hpp: 10, once a second).
    // The BQ76952's check drains a detached node in about two Check Times (1650 mV each on an assumed
    // 100 nF, bsp/host/emul/bq769x2/open_wire.cpp) before a cell reads under the 500 mV floor.
    if (r.fault == FaultId::OpenWire)
      after += " (BQ79616 device check: within 1 s + 1 scan; BQ76952 device check: about " +
               std::to_string(2 * bq76952(m2::dm::CheckTime.address)) + " s + 1 scan)";
    o << "| `" << fw::app::faultName(r.fault) << "` | " << w.trip << " | " << w.clear << " | " << after
      << " | " << action(r) << " | " << latch(r) << " | " << scans(r.recover) << " | " << backstop(r.fault)
      << " |\n";
  }
  return o.str();
}

TEST(ProtectionTable, TheReadmeTableIsTheFirmwaresTable) {
  std::ifstream in(BMS_README);
  ASSERT_TRUE(in) << BMS_README;
  std::stringstream all;
  all << in.rdbuf();
  const std::string text = all.str();
  const std::string begin =
      "<!-- protection-table:begin (generated: tests/app/protection_table_test.cpp) -->\n";
  const std::string end = "<!-- protection-table:end -->";
  const size_t b = text.find(begin);
  const size_t e = text.find(end);
  const std::string want = table();
  ASSERT_NE(b, std::string::npos) << "README.md has no protection table; paste:\n" << begin << want << end;
  ASSERT_NE(e, std::string::npos);
  EXPECT_EQ(text.substr(b + begin.size(), e - b - begin.size()), want)
      << "README.md's table is stale; paste:\n"
      << want;
}

}  // namespace
