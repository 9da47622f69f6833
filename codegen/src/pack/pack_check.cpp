#include "pack/pack_check.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <set>

namespace regmapgen::pack {
namespace {

constexpr std::int64_t kDeciKelvinAtZeroCelsius = 2732;

// A number as a message shows it: an integer as is, otherwise up to four decimals.
std::string num(double v) {
  if (std::fabs(v - std::round(v)) < 1e-9) return std::to_string(static_cast<std::int64_t>(std::llround(v)));
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  std::string s = buf;
  while (!s.empty() && s.back() == '0')
    s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

bool sameValue(double a, double b) {
  return std::fabs(a - b) <= 1e-6 * std::max(1.0, std::fabs(b));
}

const Entry* findEntry(const Family* family, const std::string& cppName) {
  if (family == nullptr) return nullptr;
  for (const Entry& e : family->entries) {
    if (e.cppName == cppName) return &e;
  }
  return nullptr;
}

struct Range {
  std::int64_t lo, hi;
};

// The codes an entry accepts: its min..max where the map gives them, else its type's range.
Range codeRange(const Entry& e) {
  Range r{e.type ? e.type->minValue() : 0, e.type ? e.type->maxValue() : 0};
  if (e.min.present && e.min.isInteger) r.lo = e.min.integer;
  if (e.max.present && e.max.isInteger) r.hi = e.max.integer;
  return r;
}

double scaleOf(const Entry& e) {
  return e.scale.present ? static_cast<double>(e.scale.num) / static_cast<double>(e.scale.den) : 1.0;
}

// A temperature window of the limits, degC.
struct Window {
  std::int64_t lo = 0, hi = 0, hyst = 0;
  bool ok = false;
};

class Checker {
 public:
  Checker(const PackFile& p, const Family* family, Resolved& out, Diagnostics& diag)
      : p_(p), family_(family), out_(out), diag_(diag) {}

  void run() {
    identity();
    if (dev_ == nullptr) return;
    cells();
    sense();
    limits();
    protections();
    stateOfCharge();
    balancing();
    can();
    storage();
  }

 private:
  // --- helpers ---------------------------------------------------------------------------------------------

  bool integer(const Quantity& q, std::int64_t lo, std::int64_t hi, const std::string& what,
               std::int64_t& v) {
    if (!q.present) return false;
    if (!q.isInteger) {
      diag_.error(q.loc, what + " must be a whole number (got " + q.text + ")");
      return false;
    }
    if (q.integer < lo || q.integer > hi) {
      diag_.error(q.loc, what + " must be in " + std::to_string(lo) + ".." + std::to_string(hi) + " (got " +
                             q.text + ")");
      return false;
    }
    v = q.integer;
    return true;
  }

  // The code of `value` (in the key's unit) for a register with `step` per code and `offset` codes added by
  // the device, within the entry's range; false (reported) when it is not a whole number of steps or out of
  // range.
  bool codeOf(double value, double step, int offset, const Entry& e, const Loc& at, const std::string& what,
              const std::string& unit, std::int64_t& code) {
    const double exact = value / step - offset;
    const std::int64_t nearest = std::llround(exact);
    const Range r = codeRange(e);
    if (!sameValue((static_cast<double>(nearest) + offset) * step, value)) {
      const std::int64_t below = static_cast<std::int64_t>(std::floor(exact));
      diag_.error(at, what + " " + num(value) + " " + unit + " is not a whole number of the device's " +
                          num(step) + " " + unit + " steps (" + e.cppName + "): the nearest settings are " +
                          num((static_cast<double>(below) + offset) * step) + " and " +
                          num((static_cast<double>(below) + 1 + offset) * step) + " " + unit);
      return false;
    }
    if (nearest < r.lo || nearest > r.hi) {
      diag_.error(at, what + " " + num(value) + " " + unit + " is outside what " + e.cppName +
                          " holds: " + num((static_cast<double>(r.lo) + offset) * step) + ".." +
                          num((static_cast<double>(r.hi) + offset) * step) + " " + unit + " (codes " +
                          std::to_string(r.lo) + ".." + std::to_string(r.hi) + ")");
      return false;
    }
    code = nearest;
    return true;
  }

  const Entry* entry(const std::string& name, const Loc& at) {
    const Entry* e = findEntry(family_, name);
    if (e == nullptr)
      diag_.error(at, "the " + dev_->family + " register map has no entry " + name + " (regmaps/" +
                          dev_->family + ")");
    return e;
  }

  // --- sections --------------------------------------------------------------------------------------------

  void identity() {
    out_.name = p_.name;
    bool nameOk = !p_.name.empty() && std::isalpha(static_cast<unsigned char>(p_.name[0])) != 0;
    for (char c : p_.name)
      nameOk = nameOk && (std::islower(static_cast<unsigned char>(c)) ||
                          std::isdigit(static_cast<unsigned char>(c)) || c == '-');
    if (!nameOk && !p_.name.empty())
      diag_.error(p_.nameLoc,
                  "pack name '" + p_.name + "': lower-case letters, digits and '-', starting with a letter");
    out_.ident = p_.name;
    std::replace(out_.ident.begin(), out_.ident.end(), '-', '_');
    out_.description = p_.description;
    out_.chemistry = p_.chemistry;
    if (!p_.chemistry.empty() && p_.chemistry != "li-ion" && p_.chemistry != "lfp")
      diag_.error(p_.chemistryLoc, "chemistry '" + p_.chemistry + "': li-ion or lfp");
    dev_ = findDevice(p_.device);
    out_.device = dev_;
    if (dev_ == nullptr && !p_.device.empty())
      diag_.error(p_.deviceLoc, "unknown device '" + p_.device + "' (known: " + deviceNames() + ")");
    if (dev_ != nullptr && dev_->settings && family_ == nullptr)
      diag_.error(p_.deviceLoc,
                  "the " + dev_->family + " register map is not loaded (regmapgen pack --regmaps DIR)");
  }

  void cells() {
    std::int64_t n = 0;
    if (!p_.cells.present) return;
    if (!p_.cells.isInteger || p_.cells.integer < 1) {
      diag_.error(p_.cells.loc, "cells must be a whole number from 1 (got " + p_.cells.text + ")");
      return;
    }
    if (p_.cells.integer > dev_->inputs) {
      diag_.error(p_.cells.loc, std::to_string(p_.cells.integer) + " cells, but the " + dev_->title +
                                    " has " + std::to_string(dev_->inputs) + " cell inputs");
      return;
    }
    n = p_.cells.integer;
    out_.cells = static_cast<int>(n);
    const bool mappable = dev_->family == "bq769x2" || dev_->family == "bq7690x";
    if (p_.cellInputs.empty()) {
      if (n < dev_->inputs && mappable) {
        diag_.error(p_.cells.loc, std::to_string(n) + " cells on the " + std::to_string(dev_->inputs) +
                                      " inputs of the " + dev_->title +
                                      ": say which inputs they use (cell_inputs: [...])");
      }
      for (int i = 1; i <= n; ++i)
        out_.inputs.push_back(i);
      return;
    }
    if (!mappable) {
      diag_.error(p_.cellInputsLoc, "the " + dev_->title +
                                        " image uses the bottom cells of each device: leave cell_inputs out");
      return;
    }
    std::set<std::int64_t> seen;
    std::int64_t last = 0;
    for (const Quantity& q : p_.cellInputs) {
      std::int64_t in = 0;
      if (!integer(q, 1, dev_->inputs, "a cell input of the " + dev_->title, in)) return;
      if (in <= last) {
        diag_.error(q.loc, "cell_inputs must rise from the bottom cell up, each input once (" +
                               std::to_string(in) + " after " + std::to_string(last) + ")");
        return;
      }
      last = in;
      out_.inputs.push_back(static_cast<int>(in));
    }
    if (static_cast<std::int64_t>(out_.inputs.size()) != n) {
      diag_.error(p_.cellInputsLoc, std::to_string(out_.inputs.size()) + " cell inputs for " +
                                        std::to_string(n) + " cells: one input per cell");
      return;
    }
    if (dev_->family == "bq7690x" && bq7690xVcellMode(dev_->inputs, out_.inputs) < 0) {
      diag_.error(p_.cellInputsLoc,
                  "the " + dev_->title +
                      " cannot be told these inputs (SLUUCJ0 Vcell Mode): with fewer cells it uses " +
                      std::string(dev_->inputs == 7 ? "[1, 7], [1, 5, 7], [1, 3, 5, 7], [1, 2, 3, 5, 7] or "
                                                      "[1, 2, 3, 5, 6, 7]"
                                                    : "all its inputs only (SLUUCI8's reduced modes are not "
                                                      "documented here)"));
    }
  }

  void sense() {
    const Quantity& shunt = p_.shuntMicroOhm;
    const Quantity& unit = p_.currentUnitMa;
    if (!dev_->current || dev_->gauge) {
      if (shunt.present)
        diag_.error(shunt.loc,
                    std::string("the ") + dev_->title +
                        (dev_->gauge ? " gauge is calibrated for its own sense resistor: leave "
                                       "shunt_micro_ohm out"
                                     : " has no current input (SLUSF21 8.3.2): leave shunt_micro_ohm out"));
      if (unit.present && !(dev_->gauge && sameValue(unit.value, 1)))
        diag_.error(unit.loc, std::string("the ") + dev_->title +
                                  (dev_->gauge ? " reports Current() in mA: current_unit_ma is 1"
                                               : " has no current input: leave current_unit_ma out"));
    } else {
      if (!shunt.present) {
        diag_.error(p_.loc,
                    "the " + dev_->title + " measures current across a shunt: shunt_micro_ohm is required");
      } else {
        std::int64_t r = 0;
        if (integer(shunt, 1, 1000000, "shunt_micro_ohm", r)) out_.shuntMicroOhm = r;
        if (dev_->family == "bq7690x" && r != 0 && r != 1000) {
          diag_.error(shunt.loc,
                      "the " + dev_->title +
                          " current gain for another sense resistor is not documented "
                          "(SLUUCJ0 Calibration:Current:Curr Gain gives no formula): only the 1000 uOhm "
                          "the device's default gain is for");
        }
      }
      if (dev_->unitsTenthMa.empty()) {
        if (unit.present && !sameValue(unit.value, 1))
          diag_.error(
              unit.loc,
              "the " + dev_->title +
                  " reports current in 1 mA (its user-amps unit is not set by the "
                  "firmware: SLUUCJ0 DA Config's layout is not documented here): current_unit_ma is 1");
        out_.currentLsbTenthMa = 10;
      } else if (!unit.present) {
        diag_.error(p_.loc, "current_unit_ma is required for the " + dev_->title + " (0.1, 1, 10 or 100)");
      } else {
        const std::int64_t tenth = std::llround(unit.value * 10);
        if (!sameValue(static_cast<double>(tenth), unit.value * 10) ||
            std::find(dev_->unitsTenthMa.begin(), dev_->unitsTenthMa.end(), tenth) ==
                dev_->unitsTenthMa.end()) {
          diag_.error(unit.loc, "current_unit_ma " + unit.text + ": the " + dev_->title +
                                    " reports current in 0.1, 1, 10 or 100 mA (DA Configuration[USER_AMPS])");
        } else {
          out_.currentLsbTenthMa = tenth;
        }
      }
    }
    if (dev_->name == "bq76952" && p_.thermistor.empty())
      diag_.error(p_.loc, "thermistor is required for the BQ76952 (103AT)");
    if (!p_.thermistor.empty() && p_.thermistor != "103AT")
      diag_.error(p_.thermistorLoc,
                  "thermistor '" + p_.thermistor +
                      "': only 103AT, the thermistor the device's default temperature model is "
                      "for (SLUUBY2B Calibration:18K Temperature Model); another needs its own "
                      "coefficients");
  }

  // The current register's reach at the chosen unit, in mA.
  Range reportableMa() const {
    const Entry* e = findEntry(family_, dev_->currentEntry);
    Range raw{-32768, 32767};
    if (e != nullptr && e->type) raw = {e->type->minValue(), e->type->maxValue()};
    return {raw.lo * out_.currentLsbTenthMa / 10, raw.hi * out_.currentLsbTenthMa / 10};
  }

  void reportable(const Quantity& q, const std::string& what) {
    if (!q.present || !dev_->current) return;
    const Range r = reportableMa();
    if (q.value < static_cast<double>(r.lo) || q.value > static_cast<double>(r.hi)) {
      diag_.error(q.loc,
                  what + " " + q.text + " mA is a current the " + dev_->title + " cannot report at " +
                      num(static_cast<double>(out_.currentLsbTenthMa) / 10) + " mA per LSB (" +
                      dev_->currentEntry + ": " + std::to_string(r.lo) + ".." + std::to_string(r.hi) +
                      " mA): the rule could never act; choose a larger current_unit_ma or a smaller limit");
    }
  }

  LimitRow& row(const std::string& fault, const std::string& action) {
    out_.limits.push_back(LimitRow{fault, 0, 0, 1, 1, action, {}});
    return out_.limits.back();
  }

  void limits() {
    if (!p_.cellOvervoltage.present) return;  // reported by the reader
    out_.limits.reserve(12);                  // rows are filled through references
    std::int64_t v = 0;
    auto mv = [&](const Group& g, const char* key, std::int64_t& to) {
      if (integer(g[key], 500, 5000, g.key + " " + key, v)) to = v;
    };
    LimitRow& ov = row("CellOvervoltage", "ChargeOff");
    mv(p_.cellOvervoltage, "trip_mv", ov.trip);
    mv(p_.cellOvervoltage, "clear_mv", ov.clear);
    if (ov.trip != 0 && ov.clear != 0 && ov.clear >= ov.trip)
      diag_.error(p_.cellOvervoltage["clear_mv"].loc,
                  "cell_overvoltage clear_mv must lie below trip_mv (the hysteresis)");
    LimitRow& uv = row("CellUndervoltage", "DischargeOff");
    mv(p_.cellUndervoltage, "trip_mv", uv.trip);
    mv(p_.cellUndervoltage, "clear_mv", uv.clear);
    if (uv.trip != 0 && uv.clear != 0 && uv.clear <= uv.trip)
      diag_.error(p_.cellUndervoltage["clear_mv"].loc,
                  "cell_undervoltage clear_mv must lie above trip_mv (the hysteresis)");
    if (uv.clear != 0 && ov.clear != 0 && uv.clear >= ov.clear)
      diag_.error(p_.cellUndervoltage["clear_mv"].loc, "cell_undervoltage lies above cell_overvoltage");

    auto current = [&](const Group& g, const std::string& fault, const std::string& action, bool charge) {
      LimitRow& r = row(fault, action);
      r.debounce = 2;
      r.recover = 30;
      if (integer(g["trip_ma"], -10000000, 10000000, g.key + " trip_ma", v)) r.trip = v;
      if (integer(g["clear_ma"], -10000000, 10000000, g.key + " clear_ma", v)) r.clear = v;
      if (integer(g["debounce_scans"], 1, 255, g.key + " debounce_scans", v))
        r.debounce = static_cast<int>(v);
      if (integer(g["recover_scans"], 1, 255, g.key + " recover_scans", v)) r.recover = static_cast<int>(v);
      if (g["trip_ma"].present && (charge ? r.trip <= 0 : r.trip >= 0))
        diag_.error(
            g["trip_ma"].loc,
            g.key + " trip_ma is " + std::string(charge ? "a charge: positive" : "a discharge: negative"));
      if (g["clear_ma"].present && (charge ? r.clear >= r.trip : r.clear <= r.trip))
        diag_.error(g["clear_ma"].loc,
                    g.key + " clear_ma must lie on the other side of trip_ma from the limit");
      // The over-current latch (TI's OCDL): both keys or neither.
      if (integer(g["latch_trips"], 1, 255, g.key + " latch_trips", v)) r.latchTrips = static_cast<int>(v);
      if (integer(g["trip_decay_s"], 1, 255, g.key + " trip_decay_s", v)) r.tripDecayS = static_cast<int>(v);
      if (g["latch_trips"].present != g["trip_decay_s"].present) {
        const Quantity& given = g["latch_trips"].present ? g["latch_trips"] : g["trip_decay_s"];
        diag_.error(given.loc, g.key +
                                   ": latch_trips and trip_decay_s go together (the trips that latch and "
                                   "the seconds that forgive one)");
      }
      reportable(g["trip_ma"], g.key + " trip_ma");
      reportable(g["clear_ma"], g.key + " clear_ma");
    };
    current(p_.chargeOvercurrent, "ChargeOvercurrent", "ChargeOff", true);
    current(p_.dischargeOvercurrent, "DischargeOvercurrent", "DischargeOff", false);

    auto window = [&](const Group& g) {
      Window w;
      bool ok = integer(g["min_c"], -55, 150, g.key + " min_c", w.lo);
      ok = integer(g["max_c"], -55, 150, g.key + " max_c", w.hi) && ok;
      ok = integer(g["hysteresis_c"], 1, 50, g.key + " hysteresis_c", w.hyst) && ok;
      if (ok && w.lo + w.hyst >= w.hi - w.hyst) {
        diag_.error(g["max_c"].loc, g.key + ": max_c - hysteresis_c must stay above min_c + hysteresis_c");
        ok = false;
      }
      w.ok = ok;
      return w;
    };
    chargeT_ = window(p_.chargeTemperature);
    dischargeT_ = window(p_.dischargeTemperature);
    auto deciK = [](std::int64_t c) { return kDeciKelvinAtZeroCelsius + 10 * c; };
    LimitRow& otd = row("OvertempDischarge", "DischargeOff");
    otd.trip = deciK(dischargeT_.hi), otd.clear = deciK(dischargeT_.hi - dischargeT_.hyst);
    LimitRow& utd = row("UndertempDischarge", "DischargeOff");
    utd.trip = deciK(dischargeT_.lo), utd.clear = deciK(dischargeT_.lo + dischargeT_.hyst);
    for (const char* flag : {"DeviceSafety", "StaleData", "CommLoss", "OpenWire"}) {
      LimitRow& r = row(flag, "AllOff");
      r.trip = 1, r.clear = 1;
    }
    LimitRow& otc = row("OvertempCharge", "ChargeOff");
    otc.trip = deciK(chargeT_.hi), otc.clear = deciK(chargeT_.hi - chargeT_.hyst);
    LimitRow& utc = row("UndertempCharge", "ChargeOff");
    utc.trip = deciK(chargeT_.lo), utc.clear = deciK(chargeT_.lo + chargeT_.hyst);
    if (integer(p_.staleScans, 1, 255, "limits stale_scans", v)) out_.staleScans = static_cast<int>(v);
    if (integer(p_.commLossScans, 1, 255, "limits comm_loss_scans", v))
      out_.commLossScans = static_cast<int>(v);
    ovTrip_ = ov.trip, uvTrip_ = uv.trip;
    chargeOcTrip_ = out_.limits[2].trip, dischargeOcTrip_ = out_.limits[3].trip;
  }

  // --- device protections ----------------------------------------------------------------------------------

  void protections() {
    if (!dev_->settings) {
      if (p_.hasProtections)
        diag_.error(p_.protectionsLoc, "the " + dev_->title +
                                           " image writes no device protections: leave "
                                           "device_protections out");
      return;
    }
    if (!p_.hasProtections) {
      diag_.error(p_.loc, "the " + dev_->title +
                              " needs device_protections: its own protection is the backstop, "
                              "written explicitly at start-up");
      return;
    }
    if (family_ == nullptr) return;
    baseSettings();
    std::map<std::string, std::uint64_t> enabled;  // Enabled Protections register -> bits
    // The REGOUT diagnostic stays enabled on the BQ7690x (the LDO the MCU may run from; SLUUCJ0 6.19).
    enabled["EnabledProtectionsA"] =
        dev_->family == "bq7690x" ? bit("EnabledProtectionsA", "REGOUT", p_.protectionsLoc) : 0;
    enabled["EnabledProtectionsB"] |= 0;
    if (dev_->family == "bq769x2") enabled["EnabledProtectionsC"] |= 0;
    std::vector<SettingRow> rows;
    bool scdLatch = false;
    std::set<std::string> seen;
    for (const Group& g : p_.protections) {
      const ProtectionSpec* spec = nullptr;
      std::string known;
      for (const ProtectionSpec& s : dev_->protections) {
        known += (known.empty() ? "" : ", ") + s.key;
        if (s.key == g.key) spec = &s;
      }
      if (spec == nullptr) {
        diag_.error(g.loc,
                    "the " + dev_->title + " has no protection '" + g.key + "' (known: " + known + ")");
        continue;
      }
      seen.insert(g.key);
      std::vector<std::string> keys;
      if (!spec->thresholdKey.empty()) keys.push_back(spec->thresholdKey);
      keys.push_back(spec->delayKey);
      const bool latch = spec->key == "scd" && dev_->family == "bq769x2";
      for (const auto& [k, q] : g.values) {
        if (std::find(keys.begin(), keys.end(), k) == keys.end() && !(latch && k == "latch_limit")) {
          std::string all;
          for (const std::string& x : keys)
            all += (all.empty() ? "" : ", ") + x;
          if (latch) all += ", latch_limit";
          diag_.error(q.loc, "unknown key '" + k + "' in " + spec->title + " (known: " + all + ")");
        }
      }
      for (const std::string& k : keys) {
        if (!g[k].present) diag_.error(g.loc, spec->title + " has no '" + k + "' (required)");
      }
      threshold(*spec, g, rows);
      delay(*spec, g, rows);
      if (latch && g["latch_limit"].present) {
        std::int64_t limit = 0;
        if (const Entry* e = entry("ScdlLatchLimit", g.loc);
            e != nullptr &&
            integer(g["latch_limit"], codeRange(*e).lo, codeRange(*e).hi, "SCD latch_limit", limit)) {
          rows.push_back({"ScdlLatchLimit", std::to_string(limit),
                          "the SCD latch (SCDL) after this many SCD trips; it recovers with charge current"});
          scdLatch = limit > 0;
        }
      }
      enabled[spec->enableEntry] |= bit(spec->enableEntry, spec->enableField, g.loc);
    }
    if (scdLatch) enabled["EnabledProtectionsC"] |= bit("EnabledProtectionsC", "SCDL", p_.protectionsLoc);
    for (const auto& [reg, bits] : enabled) {
      char hex[24];
      std::snprintf(hex, sizeof hex, "0x%02llX", static_cast<unsigned long long>(bits));
      const Entry* e = entry(reg, p_.protectionsLoc);
      if (e == nullptr) continue;
      const std::string type = e->fieldset.present ? e->fieldset.value : "";
      out_.settings.push_back({reg,
                               type.empty() ? std::string(hex) : "bits::" + type + "::fromRaw(" + hex + ")",
                               "the protections listed in device_protections"});
    }
    if (scdLatch) {
      // Protection Configuration[SCDL_CURR_RECOV] (bit 10): the SCD latch recovers with charge current
      // (SLUUCG7 / SLUUCF2C Settings:Protection:Protection Configuration), added to the map's default.
      if (const Entry* e = entry("ProtectionConfiguration", p_.protectionsLoc)) {
        const std::int64_t value = (e->dflt.present ? e->dflt.integer : 0) | 0x0400;
        char hex[24];
        std::snprintf(hex, sizeof hex, "0x%04llX", static_cast<unsigned long long>(value));
        out_.settings.push_back(
            {"ProtectionConfiguration", hex, "its default with SCDL_CURR_RECOV (bit 10)"});
      }
    }
    out_.settings.insert(out_.settings.end(), rows.begin(), rows.end());
  }

  std::uint64_t bit(const std::string& reg, const std::string& field, const Loc& at) {
    const Entry* e = entry(reg, at);
    if (e == nullptr || !e->fieldset.present) return 0;
    const Fieldset* fs = family_->findFieldset(e->fieldset.value);
    if (fs != nullptr) {
      for (const Field& f : fs->fields) {
        if (f.name.value == field) return f.mask();
      }
    }
    diag_.error(at, reg + " has no field " + field + " in the " + dev_->family + " register map");
    return 0;
  }

  // The settings every pack of the device has: cell inputs, user-amps unit, current gain.
  void baseSettings() {
    if (dev_->family == "bq769x2") {
      std::uint32_t mask = 0;
      for (int in : out_.inputs)
        mask |= 1U << (in - 1);
      char hex[24];
      std::snprintf(hex, sizeof hex, "0x%04X", out_.cells == 16 ? 0xFFFFu : mask);
      out_.settings.push_back({"VCellMode", hex, "the cell inputs in use, bit n-1 = VCn - VCn-1"});
      if (const Entry* e = entry("DaConfiguration", p_.loc)) {
        const std::int64_t code = out_.currentLsbTenthMa == 1     ? 0
                                  : out_.currentLsbTenthMa == 10  ? 1
                                  : out_.currentLsbTenthMa == 100 ? 2
                                                                  : 3;
        const std::int64_t dflt = e->dflt.present ? e->dflt.integer : 0x05;
        char hex[24];
        std::snprintf(hex, sizeof hex, "0x%02llX", static_cast<unsigned long long>((dflt & ~0x3LL) | code));
        out_.settings.push_back(
            {"DaConfiguration", "bits::DaConfiguration::fromRaw(" + std::string(hex) + ")",
             "USER_AMPS = " + std::to_string(code) + ": " +
                 num(static_cast<double>(out_.currentLsbTenthMa) / 10) +
                 " mA per userA (SLUUBY2B DA Configuration; TI's SDK: 0x05 = 1 mA, 0x06 = 10 mA)"});
      }
      if (out_.shuntMicroOhm > 0) {
        // SLUUBY2B Calibration, Current: CC Gain = 7.5684 / (Rsense in mOhm) at the typical VREF2 of 1.24 V,
        // Capacity Gain = CC Gain x 298261.6178 (the data sheet JAJSK08B and TI's SDK comment use 7.4768:
        // README, open questions).
        const double mOhm = static_cast<double>(out_.shuntMicroOhm) / 1000.0;
        const float ccGain = static_cast<float>(7.5684 / mOhm);
        const float capGain = static_cast<float>(7.5684 / mOhm * 298261.6178);
        for (const auto& [name, value] :
             {std::pair{std::string("CcGain"), ccGain}, {std::string("CapacityGain"), capGain}}) {
          const Entry* e = entry(name, p_.shuntMicroOhm.loc);
          if (e == nullptr) continue;
          if ((e->min.present && value < e->min.real) || (e->max.present && value > e->max.real)) {
            diag_.error(p_.shuntMicroOhm.loc, "shunt_micro_ohm " + p_.shuntMicroOhm.text + " gives " + name +
                                                  " " + num(value) + ", outside " + e->min.text + ".." +
                                                  e->max.text);
            continue;
          }
          char hex[24];
          std::snprintf(hex, sizeof hex, "0x%08X", std::bit_cast<std::uint32_t>(value));
          out_.settings.push_back({name, std::string("regmap::F4::fromRaw(") + hex + ")",
                                   num(value) +
                                       (name == "CcGain" ? " = 7.5684 / " : " = 7.5684 x 298261.6178 / ") +
                                       num(mOhm) + " mOhm (SLUUBY2B Calibration, Current)"});
        }
      }
    } else if (dev_->family == "bq7690x") {
      const int mode = bq7690xVcellMode(dev_->inputs, out_.inputs);
      if (mode >= 0)
        out_.settings.push_back({"VcellMode", std::to_string(mode), "SLUUCJ0 Vcell Mode: the inputs in use"});
    }
  }

  void threshold(const ProtectionSpec& s, const Group& g, std::vector<SettingRow>& rows) {
    if (s.kind == ThresholdKind::None) return;
    const Quantity& q = g[s.thresholdKey];
    if (!q.present) return;
    const Entry* e = entry(s.thresholdEntry, q.loc);
    if (e == nullptr) return;
    std::int64_t code = 0;
    double physical = q.value;  // in the pack file's unit (mV, mA, degC)
    std::string comment;
    switch (s.kind) {
      case ThresholdKind::CellMv:
        if (!codeOf(q.value, scaleOf(*e), 0, *e, q.loc, s.title + " threshold", "mV", code)) return;
        comment = std::to_string(code) + " x " + num(scaleOf(*e)) + " mV = " + num(q.value) + " mV";
        break;
      case ThresholdKind::DegC:
        if (!codeOf(q.value, scaleOf(*e), 0, *e, q.loc, s.title + " threshold", "degC", code)) return;
        comment = num(q.value) + " degC";
        break;
      case ThresholdKind::SenseCurrent:
      case ThresholdKind::SenseTable: {
        if (out_.shuntMicroOhm <= 0) return;
        const double mv = q.value * static_cast<double>(out_.shuntMicroOhm) / 1e6;
        if (s.kind == ThresholdKind::SenseCurrent) {
          std::int64_t c = 0;
          const double step = scaleOf(*e);
          if (!codeOf(mv, step, 0, *e, q.loc,
                      s.title + " threshold " + q.text + " mA across " + std::to_string(out_.shuntMicroOhm) +
                          " uOhm:",
                      "mV", c)) {
            return;
          }
          code = c;
          comment = std::to_string(code) + " x " + num(step) + " mV = " + num(mv) +
                    " mV: " + num(q.value / 1000) + " A";
        } else {
          std::vector<std::pair<int, std::string>> table;  // mV, C++ value
          if (e->enumRef.present) {
            if (const Enum* en = family_->findEnum(e->enumRef.value)) {
              for (const EnumValue& v : en->values) {
                int tmv = 0;
                if (std::sscanf(v.name.value.c_str(), "At%dmV", &tmv) == 1)
                  table.push_back({tmv, "enums::" + en->name.value + "::" + v.name.value});
              }
            }
          } else {
            for (size_t i = 0; i < s.tableMv.size(); ++i)
              table.push_back({s.tableMv[i], std::to_string(i)});
          }
          const auto hit = std::find_if(table.begin(), table.end(), [&](const auto& t) {
            return sameValue(static_cast<double>(t.first), mv);
          });
          if (hit == table.end()) {
            std::string list;
            for (const auto& t : table)
              list +=
                  (list.empty() ? "" : ", ") + num(t.first * 1e6 / static_cast<double>(out_.shuntMicroOhm));
            diag_.error(q.loc, s.title + " threshold " + q.text + " mA is " + num(mv) + " mV across " +
                                   std::to_string(out_.shuntMicroOhm) +
                                   " uOhm, not one of the device's settings (" + s.source +
                                   "); in mA: " + list);
            return;
          }
          rows.push_back({s.thresholdEntry, hit->second, num(mv) + " mV: " + num(q.value / 1000) + " A"});
          backsUp(s, q, physical);
          return;
        }
        break;
      }
      case ThresholdKind::None:
        return;
    }
    rows.push_back({s.thresholdEntry, std::to_string(code), comment});
    backsUp(s, q, physical);
  }

  void delay(const ProtectionSpec& s, const Group& g, std::vector<SettingRow>& rows) {
    const Quantity& q = g[s.delayKey];
    if (!q.present) return;
    const Entry* e = entry(s.delayEntry, q.loc);
    if (e == nullptr) return;
    const std::string unit = s.delayKey.substr(s.delayKey.rfind('_') + 1);
    if (!s.delayTable.empty()) {
      for (size_t i = 0; i < s.delayTable.size(); ++i) {
        if (sameValue(static_cast<double>(s.delayTable[i]), q.value)) {
          rows.push_back(
              {s.delayEntry, std::to_string(i), "setting " + std::to_string(i) + ": " + q.text + " " + unit});
          return;
        }
      }
      std::string list;
      for (int d : s.delayTable)
        list += (list.empty() ? "" : ", ") + std::to_string(d);
      diag_.error(q.loc, s.title + " delay " + q.text + " " + unit +
                             " is not one of the device's settings (" + s.source + "): " + list);
      return;
    }
    std::int64_t code = 0;
    if (!codeOf(q.value, s.delayStep, s.delayOffset, *e, q.loc, s.title + " delay", unit, code)) return;
    std::string comment = q.text + " " + unit;
    if (s.delayOffset != 0 || s.delayStep != 1)
      comment = "(" + std::to_string(code) + (s.delayOffset < 0 ? " - " : " + ") +
                std::to_string(std::abs(s.delayOffset)) + ") x " + num(s.delayStep) + " " + unit + " = " +
                q.text + " " + unit;
    rows.push_back({s.delayEntry, std::to_string(code), comment});
  }

  // The device protection sits outside the firmware limit it backs up.
  void backsUp(const ProtectionSpec& s, const Quantity& q, double v) {
    auto inside = [&](const std::string& limit, const std::string& side) {
      const std::string unit = s.thresholdKey.substr(s.thresholdKey.rfind('_') + 1);
      diag_.error(q.loc, s.title + " " + q.text +
                             (unit == "c"    ? " degC"
                              : unit == "ma" ? " mA"
                                             : " mV") +
                             " lies " + side + " the firmware's " + limit +
                             ": the device would act before the firmware; every device protection must sit "
                             "outside the firmware limit it backs up");
    };
    switch (s.backs) {
      case Backs::CellOvAbove:
        if (ovTrip_ != 0 && v <= static_cast<double>(ovTrip_))
          inside("cell_overvoltage trip_mv " + std::to_string(ovTrip_), "at or below");
        break;
      case Backs::CellUvBelow:
        if (uvTrip_ != 0 && v >= static_cast<double>(uvTrip_))
          inside("cell_undervoltage trip_mv " + std::to_string(uvTrip_), "at or above");
        break;
      case Backs::ChargeOcAbove:
        if (chargeOcTrip_ != 0 && v <= static_cast<double>(chargeOcTrip_))
          inside("charge_overcurrent trip_ma " + std::to_string(chargeOcTrip_), "at or below");
        break;
      case Backs::DischargeOcBelow:
        if (dischargeOcTrip_ != 0 && v <= static_cast<double>(-dischargeOcTrip_))
          inside("discharge_overcurrent trip_ma " + std::to_string(dischargeOcTrip_) +
                     " (as a discharge of " + std::to_string(-dischargeOcTrip_) + " mA)",
                 "at or inside");
        break;
      case Backs::ChargeOtAbove:
        if (chargeT_.ok && v <= static_cast<double>(chargeT_.hi))
          inside("charge_temperature max_c " + std::to_string(chargeT_.hi), "at or below");
        break;
      case Backs::DischargeOtAbove:
        if (dischargeT_.ok && v <= static_cast<double>(dischargeT_.hi))
          inside("discharge_temperature max_c " + std::to_string(dischargeT_.hi), "at or below");
        break;
      case Backs::AnyOtAbove:
        if (chargeT_.ok && dischargeT_.ok && v <= static_cast<double>(std::max(chargeT_.hi, dischargeT_.hi)))
          inside("temperature max_c " + std::to_string(std::max(chargeT_.hi, dischargeT_.hi)), "at or below");
        break;
      case Backs::ChargeUtBelow:
        if (chargeT_.ok && v >= static_cast<double>(chargeT_.lo))
          inside("charge_temperature min_c " + std::to_string(chargeT_.lo), "at or above");
        break;
      case Backs::DischargeUtBelow:
        if (dischargeT_.ok && v >= static_cast<double>(dischargeT_.lo))
          inside("discharge_temperature min_c " + std::to_string(dischargeT_.lo), "at or above");
        break;
      case Backs::AnyUtBelow:
        if (chargeT_.ok && dischargeT_.ok && v >= static_cast<double>(std::min(chargeT_.lo, dischargeT_.lo)))
          inside("temperature min_c " + std::to_string(std::min(chargeT_.lo, dischargeT_.lo)), "at or above");
        break;
      case Backs::None:
        break;
    }
  }

  // --- state of charge, balancing, CAN ---------------------------------------------------------------------

  void stateOfCharge() {
    if (!dev_->stateOfCharge) {
      if (p_.soc.present)
        diag_.error(p_.soc.loc, dev_->gauge ? "the " + dev_->title +
                                                  " gauge reports its own state of charge: leave "
                                                  "state_of_charge out"
                                            : "the " + dev_->title +
                                                  " has no current input (SLUSF21 8.3.2), so no "
                                                  "state of charge: leave state_of_charge out");
      return;
    }
    if (!p_.soc.present) {
      diag_.error(p_.loc, "the " + dev_->title + " counts charge: state_of_charge is required");
      return;
    }
    const Group& g = p_.soc;
    std::int64_t v = 0;
    bool ok = true;
    auto take = [&](const char* key, std::int64_t lo, std::int64_t hi, std::int64_t& to) {
      if (!g[key].present) {
        ok = false;
        return;
      }
      if (integer(g[key], lo, hi, std::string("state_of_charge ") + key, v)) {
        to = v;
      } else {
        ok = false;
      }
    };
    take("capacity_mah", 1, 1048574, out_.capacityMah);
    take("full_cell_mv", 1000, 5000, out_.fullCellMv);
    take("empty_cell_mv", 500, 5000, out_.emptyCellMv);
    take("rest_current_ma", 1, 100000, out_.restCurrentMa);
    take("rest_s", 1, 86400, out_.restS);
    if (g["ocv_min_step_mv"].present) take("ocv_min_step_mv", 0, 1000, out_.ocvMinStepMv);
    reportable(g["rest_current_ma"], "state_of_charge rest_current_ma");
    if (ok && out_.fullCellMv > ovTrip_ && ovTrip_ != 0)
      diag_.error(g["full_cell_mv"].loc,
                  "full_cell_mv lies above the cell_overvoltage trip (" + std::to_string(ovTrip_) +
                      " mV): protection stops the charge before the pack is ever full");
    if (ok && out_.emptyCellMv < uvTrip_ && uvTrip_ != 0)
      diag_.error(g["empty_cell_mv"].loc,
                  "empty_cell_mv lies below the cell_undervoltage trip (" + std::to_string(uvTrip_) +
                      " mV): protection stops the discharge before the pack is ever empty");
    if (ok && out_.emptyCellMv >= out_.fullCellMv)
      diag_.error(g["empty_cell_mv"].loc, "empty_cell_mv must lie below full_cell_mv");
    if (p_.ocvMv.size() != 11) {
      if (!p_.ocvMv.empty() || g.present)
        diag_.error(p_.ocvLoc.line != 0 ? p_.ocvLoc : g.loc,
                    "ocv_mv holds 11 cell voltages, at 0, 10, ..., 100 % (got " +
                        std::to_string(p_.ocvMv.size()) + ")");
      return;
    }
    std::int64_t last = 0;
    for (const Quantity& q : p_.ocvMv) {
      if (!integer(q, 1000, 5000, "an ocv_mv value", v)) return;
      if (v < last) {
        diag_.error(q.loc, "ocv_mv must not fall from 0 to 100 % (" + std::to_string(v) + " after " +
                               std::to_string(last) + ")");
        return;
      }
      last = v;
      out_.ocvMv.push_back(v);
    }
    out_.soc = ok;
  }

  void balancing() {
    if (!p_.balancing.present) return;
    const Group& g = p_.balancing;
    std::int64_t v = 0;
    bool ok = true;
    for (const auto& [key, q] : g.values) {
      const bool temp = key.find("_temp_c") != std::string::npos;
      if (integer(q, temp ? -55 : 0, temp ? 150 : 100000, "balancing " + key, v)) {
        out_.balancingValues[key] = v;
      } else {
        ok = false;
      }
    }
    if (ok && out_.balancingValues["stop_delta_mv"] >= out_.balancingValues["start_delta_mv"])
      diag_.error(g["stop_delta_mv"].loc, "balancing stop_delta_mv must lie below start_delta_mv");
    if (ok && out_.balancingValues["min_cell_temp_c"] >= out_.balancingValues["max_cell_temp_c"])
      diag_.error(g["min_cell_temp_c"].loc, "balancing min_cell_temp_c must lie below max_cell_temp_c");
    out_.balancing = ok;
  }

  void can() {
    if (!p_.can.present) return;
    std::int64_t v = 0;
    // The native messages span 0x100..0x202 (firmware/app/can/bms.yaml); base_id moves them together.
    if (integer(p_.can["base_id"], 0, 0x7FF - 0x102, "can base_id", v)) out_.canBaseId = v;
    if (integer(p_.can["period_ms"], 10, 1000, "can period_ms", v)) {
      if (v % 10 != 0) diag_.error(p_.can["period_ms"].loc, "can period_ms: a multiple of 10 ms");
      out_.canPeriodMs = v;
    }
    if (integer(p_.can["slow_every"], 1, 100, "can slow_every", v)) out_.canSlowEvery = v;
  }

  // Pack storage (firmware/app/monitors/storage_mode.hpp).
  void storage() {
    const Group& g = p_.storage;
    if (!g.present) return;
    std::int64_t v = 0;
    bool ok = true;
    // Storage scans are whole scan periods (the monitor skips the others: the watchdog check-in and
    // protection's tick stay on the scan period), at most 255 of them.
    const Quantity& period = g["scan_period_ms"];
    if (integer(period, 2 * kScanPeriodMs, 250 * kScanPeriodMs, "storage scan_period_ms", v)) {
      if (v % kScanPeriodMs != 0)
        diag_.error(period.loc, "storage scan_period_ms must be a whole number of the firmware's " +
                                    std::to_string(kScanPeriodMs) + " ms scan periods (got " + period.text +
                                    ")");
      out_.storageScanEvery = v / kScanPeriodMs;
    } else {
      ok = false;
    }
    // The device's host watchdog opens the FETs when the host is silent for its timeout (SLUUBY2B 5.2 Host
    // Watchdog; SLUUCJ0 6.15): the storage scans must come more often. The BQ7690x gives a timeout code
    // whose seconds the generator does not know (the EVM pack's code 1 is 2 s): the shortest, 2 s, is taken.
    for (const Group& p : p_.protections) {
      if (p.key != "hwd" || !ok) continue;
      std::int64_t timeoutMs = 2000;
      if (p["timeout_s"].present && p["timeout_s"].isInteger) timeoutMs = p["timeout_s"].integer * 1000;
      if (out_.storageScanEvery * kScanPeriodMs >= timeoutMs)
        diag_.error(period.loc, "storage scan_period_ms " + period.text +
                                    " is not shorter than the device's host watchdog (" +
                                    std::to_string(timeoutMs) +
                                    " ms): it would open the FETs between storage scans (" +
                                    (dev_->family == "bq769x2" ? "SLUUBY2B 5.2" : "SLUUCJ0 6.15") + ")");
    }
    if (p_.deviceSleep == "true") {
      out_.storageDeviceSleep = true;
      if (dev_->sleepSource.empty()) {
        diag_.error(p_.deviceSleepLoc, "the " + dev_->title +
                                           "'s own SLEEP is not controlled by the firmware: device_sleep "
                                           "false (storage is the scan period only)");
      } else if (const Entry* e = entry("VoltageTime", p_.deviceSleepLoc)) {
        // What the firmware publishes as the age of a SLEEP measurement: the device's interval there.
        if (!e->dflt.present || !e->dflt.isInteger || e->dflt.integer <= 0)
          diag_.error(p_.deviceSleepLoc, "device_sleep true needs the " + dev_->title +
                                             "'s SLEEP measurement interval (Power:Sleep:Voltage Time), "
                                             "which its register map gives no default for: device_sleep "
                                             "false");
        else
          out_.storageSleepS = e->dflt.integer;
      }
    } else if (p_.deviceSleep != "false") {
      diag_.error(p_.deviceSleepLoc,
                  "storage device_sleep must be true or false (got '" + p_.deviceSleep + "')");
    }
    if (g["auto_entry_min"].present && integer(g["auto_entry_min"], 0, 1440, "storage auto_entry_min", v))
      out_.storageAutoEntryMin = v;
    // At rest: the storage rest current, else the state of charge's.
    if (g["rest_current_ma"].present) {
      if (integer(g["rest_current_ma"], 1, 100000, "storage rest_current_ma", v))
        out_.storageRestCurrentMa = v;
    } else {
      out_.storageRestCurrentMa = out_.restCurrentMa;
    }
    if (out_.storageAutoEntryMin != 0 && (!dev_->current || out_.storageRestCurrentMa == 0))
      diag_.error(g["auto_entry_min"].loc,
                  dev_->current ? "storage auto_entry_min needs a rest current: rest_current_ma here or in "
                                  "state_of_charge"
                                : "the " + dev_->title +
                                      " has no current input, so no rest: storage auto_entry_min 0 (by "
                                      "command only)");
    if (dev_->current && out_.storageRestCurrentMa == 0)
      diag_.error(g.loc,
                  "storage needs a rest current (it leaves storage above it): rest_current_ma here or "
                  "in state_of_charge");
  }

  const PackFile& p_;
  const Family* family_;
  Resolved& out_;
  Diagnostics& diag_;
  const DeviceSpec* dev_ = nullptr;
  std::int64_t ovTrip_ = 0, uvTrip_ = 0, chargeOcTrip_ = 0, dischargeOcTrip_ = 0;
  Window chargeT_, dischargeT_;
};

}  // namespace

bool resolvePack(const PackFile& pack, const Family* family, Resolved& out, Diagnostics& diag) {
  const std::size_t before = diag.errorCount();
  Checker(pack, family, out, diag).run();
  return diag.errorCount() == before;
}

}  // namespace regmapgen::pack
