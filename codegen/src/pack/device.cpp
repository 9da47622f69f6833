#include "pack/device.hpp"

namespace regmapgen::pack {
namespace {

// BQ769x2 (SLUUBY2B section 5.2 and Protections:*): COV/CUV/OCC/OCD delays count 3.3 ms units with 2 added
// ("delay = (setting + 2) x 3.3 ms"), the SCD delay 15 us units with 1 taken off (setting 1 = no added
// delay), temperature and host-watchdog delays whole seconds. Thresholds: COV/CUV 50.6 mV and OCC/OCD 2 mV
// steps are the map's scales; the SCD threshold is the map's ScdThreshold enum (At<n>mV).
std::vector<ProtectionSpec> bq769x2Protections() {
  const std::string src = "SLUUBY2B 5.2";
  auto cell = [&](const char* key, const char* title, const char* thr, const char* dly, const char* field,
                  Backs backs) {
    return ProtectionSpec{key, title, ThresholdKind::CellMv, "threshold_mv", thr,   {}, "delay_ms", dly, 3.3,
                          2,   {},    "EnabledProtectionsA", field,          backs, src};
  };
  auto current = [&](const char* key, const char* title, const char* thr, const char* dly, const char* field,
                     Backs backs) {
    return ProtectionSpec{
        key, title, ThresholdKind::SenseCurrent, "threshold_ma", thr,   {}, "delay_ms", dly, 3.3,
        2,   {},    "EnabledProtectionsA",       field,          backs, src};
  };
  auto temp = [&](const char* key, const char* title, const char* thr, const char* dly, const char* field,
                  Backs backs) {
    return ProtectionSpec{key, title, ThresholdKind::DegC,   "threshold_c", thr,   {}, "delay_s", dly, 1,
                          0,   {},    "EnabledProtectionsB", field,         backs, src};
  };
  return {
      cell("cov", "cell over-voltage (COV)", "CovThreshold", "CovDelay", "COV", Backs::CellOvAbove),
      cell("cuv", "cell under-voltage (CUV)", "CuvThreshold", "CuvDelay", "CUV", Backs::CellUvBelow),
      current("occ", "over-current in charge (OCC)", "OccThreshold", "OccDelay", "OCC", Backs::ChargeOcAbove),
      current("ocd1", "over-current in discharge 1 (OCD1)", "Ocd1Threshold", "Ocd1Delay", "OCD1",
              Backs::DischargeOcBelow),
      current("ocd2", "over-current in discharge 2 (OCD2)", "Ocd2Threshold", "Ocd2Delay", "OCD2",
              Backs::DischargeOcBelow),
      ProtectionSpec{"scd",
                     "short circuit in discharge (SCD)",
                     ThresholdKind::SenseTable,
                     "threshold_ma",
                     "ScdThreshold",
                     {},
                     "delay_us",
                     "ScdDelay",
                     15,
                     -1,
                     {},
                     "EnabledProtectionsA",
                     "SCD",
                     Backs::DischargeOcBelow,
                     src},
      temp("otc", "over-temperature in charge (OTC)", "OtcThreshold", "OtcDelay", "OTC",
           Backs::ChargeOtAbove),
      temp("otd", "over-temperature in discharge (OTD)", "OtdThreshold", "OtdDelay", "OTD",
           Backs::DischargeOtAbove),
      temp("otf", "FET over-temperature (OTF)", "OtfThreshold", "OtfDelay", "OTF", Backs::AnyOtAbove),
      temp("otint", "internal over-temperature (OTINT)", "OtintThreshold", "OtintDelay", "OTINT",
           Backs::AnyOtAbove),
      temp("utc", "under-temperature in charge (UTC)", "UtcThreshold", "UtcDelay", "UTC",
           Backs::ChargeUtBelow),
      temp("utd", "under-temperature in discharge (UTD)", "UtdThreshold", "UtdDelay", "UTD",
           Backs::DischargeUtBelow),
      temp("utint", "internal under-temperature (UTINT)", "UtintThreshold", "UtintDelay", "UTINT",
           Backs::AnyUtBelow),
      ProtectionSpec{"hwd",
                     "host watchdog (HWD)",
                     ThresholdKind::None,
                     "",
                     "",
                     {},
                     "timeout_s",
                     "HwdDelay",
                     1,
                     0,
                     {},
                     "EnabledProtectionsC",
                     "HWDF",
                     Backs::None,
                     "SLUUBY2B 5.2 Host Watchdog"},
  };
}

// BQ7690x (SLUUCJ0 / SLUUCI8 chapter 6): COV and CUV thresholds in plain mV, their delays in ADSCAN
// measurement intervals; the SCD threshold and delay are setting codes (SLUUCJ0 Table 6-9 and Protections:
// Current:Short Circuit in Discharge Protection Delay), the host watchdog timeout a code as well (SLUUCJ0
// 6.15). The map has no enum for these, so the tables are here.
std::vector<ProtectionSpec> bq7690xProtections() {
  const std::string src = "SLUUCJ0 6.3-6.5";
  return {
      ProtectionSpec{"cov",
                     "cell over-voltage (COV)",
                     ThresholdKind::CellMv,
                     "threshold_mv",
                     "CellOvervoltageProtectionThreshold",
                     {},
                     "delay_scans",
                     "CellOvervoltageProtectionDelay",
                     1,
                     0,
                     {},
                     "EnabledProtectionsA",
                     "COV",
                     Backs::CellOvAbove,
                     src},
      ProtectionSpec{"cuv",
                     "cell under-voltage (CUV)",
                     ThresholdKind::CellMv,
                     "threshold_mv",
                     "CellUndervoltageProtectionThreshold",
                     {},
                     "delay_scans",
                     "CellUndervoltageProtectionDelay",
                     1,
                     0,
                     {},
                     "EnabledProtectionsA",
                     "CUV",
                     Backs::CellUvBelow,
                     src},
      ProtectionSpec{"scd",
                     "short circuit in discharge (SCD)",
                     ThresholdKind::SenseTable,
                     "threshold_ma",
                     "ShortCircuitInDischargeProtectionThreshold",
                     {10, 20, 40, 60, 80, 100, 125, 150, 175, 200, 250, 300, 350, 400, 450, 500},
                     "delay_us",
                     "ShortCircuitInDischargeProtectionDelay",
                     1,
                     0,
                     {0, 15, 31, 61, 122, 244, 488, 977, 1953, 3906, 7797},
                     "EnabledProtectionsA",
                     "SCD",
                     Backs::DischargeOcBelow,
                     "SLUUCJ0 Table 6-9, Short Circuit in Discharge Protection Delay"},
      ProtectionSpec{"hwd",
                     "host watchdog (HWD)",
                     ThresholdKind::None,
                     "",
                     "",
                     {},
                     "timeout_code",
                     "HostWatchdogTimeout",
                     1,
                     0,
                     {},
                     "EnabledProtectionsB",
                     "HWD",
                     Backs::None,
                     "SLUUCJ0 6.15"},
  };
}

std::vector<DeviceSpec> makeDevices() {
  DeviceSpec bq76952{"bq76952",
                     "bq769x2",
                     "BQ76952",
                     16,
                     true,
                     "Cc2Current",
                     {1, 10, 100, 1000},
                     true,
                     true,
                     false,
                     bq769x2Protections(),
                     "SLUUBY2B 7.3"};
  DeviceSpec bq76907{"bq76907",
                     "bq7690x",
                     "BQ76907",
                     7,
                     true,
                     "Cc2Current",
                     {},
                     true,
                     true,
                     false,
                     bq7690xProtections(),
                     "SLUUCI8 SLEEP Mode"};
  DeviceSpec bq76905 = bq76907;
  bq76905.name = "bq76905";
  bq76905.title = "BQ76905";
  bq76905.inputs = 5;
  DeviceSpec bq79616{"bq79616", "bq79616", "BQ79616", 16, false, "", {}, false, false, false, {}, ""};
  DeviceSpec bq4050{"bq4050", "bq4050", "BQ4050", 4, true, "Current", {}, false, false, true, {}, ""};
  return {bq76952, bq76907, bq76905, bq79616, bq4050};
}

}  // namespace

const DeviceSpec* findDevice(const std::string& name) {
  static const std::vector<DeviceSpec> devices = makeDevices();
  for (const DeviceSpec& d : devices) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

std::string deviceNames() {
  return "bq76952, bq76907, bq76905, bq79616, bq4050";
}

int bq7690xVcellMode(int deviceInputs, const std::vector<int>& inputs) {
  if (static_cast<int>(inputs.size()) == deviceInputs)
    return deviceInputs;             // all inputs (7 = all on a BQ76907)
  if (deviceInputs != 7) return -1;  // BQ76905: SLUUCI8's reduced modes were not retrieved: all inputs only
  // SLUUCJ0 Vcell Mode (the same in SLUUCY8 for the BQ77307): which inputs each code uses.
  static const std::vector<std::vector<int>> kModes = {
      {}, {}, {1, 7}, {1, 5, 7}, {1, 3, 5, 7}, {1, 2, 3, 5, 7}, {1, 2, 3, 5, 6, 7}};
  for (int code = 2; code <= 6; ++code) {
    if (kModes[static_cast<size_t>(code)] == inputs) return code;
  }
  return -1;
}

}  // namespace regmapgen::pack
