#include "pack/pack_model.hpp"

#include <algorithm>

#include "model/model.hpp"

namespace regmapgen::pack {
namespace {

using yaml::Node;

struct GroupSpec {
  const char* key;
  std::vector<std::string> required;
  std::vector<std::string> optional;
};

// The limit rows and the other flat groups: which quantities each holds.
const GroupSpec kCellOv{"cell_overvoltage", {"trip_mv", "clear_mv"}, {}};
const GroupSpec kCellUv{"cell_undervoltage", {"trip_mv", "clear_mv"}, {}};
const GroupSpec kChargeOc{"charge_overcurrent", {"trip_ma", "clear_ma"}, {"debounce_scans", "recover_scans"}};
const GroupSpec kDischargeOc{"discharge_overcurrent",
                             {"trip_ma", "clear_ma"},
                             {"debounce_scans", "recover_scans", "latch_trips", "trip_decay_s"}};
const GroupSpec kChargeTemp{"charge_temperature", {"min_c", "max_c", "hysteresis_c"}, {}};
const GroupSpec kDischargeTemp{"discharge_temperature", {"min_c", "max_c", "hysteresis_c"}, {}};
const GroupSpec kSoc{"state_of_charge",
                     {"capacity_mah", "full_cell_mv", "empty_cell_mv", "rest_current_ma", "rest_s"},
                     {"ocv_min_step_mv"}};
const GroupSpec kBalancing{"balancing",
                           {"start_delta_mv", "stop_delta_mv", "cell_hysteresis_mv", "min_cell_mv",
                            "charge_current_ma", "rest_current_ma", "rest_s", "min_cell_temp_c",
                            "max_cell_temp_c", "max_die_temp_c", "min_dwell_s", "refused_backoff_s"},
                           {}};
const GroupSpec kCan{"can", {"base_id", "period_ms", "slow_every"}, {}};
const GroupSpec kStorage{
    "storage", {"scan_period_ms", "device_sleep"}, {"auto_entry_min", "rest_current_ma"}};

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names)
    out += (out.empty() ? "" : ", ") + n;
  return out;
}

class Reader {
 public:
  Reader(Diagnostics& diag) : diag_(diag) {}

  Quantity quantity(const Node* n, const std::string& what) {
    Quantity q;
    if (n == nullptr) return q;
    q.loc = n->loc;
    if (!n->isScalar() || n->invalid) {
      if (!n->invalid) diag_.error(n->loc, what + " must be a number, not " + yaml::describe(n->type));
      return q;
    }
    const auto parsed = parseNumber(n->text);
    if (!parsed || n->quoted) {
      diag_.error(n->loc, what + " must be a number (got '" + n->text + "')");
      return q;
    }
    q.present = true;
    q.value = parsed->real;
    q.isInteger = parsed->isInteger;
    q.integer = parsed->integer;
    q.text = n->text;
    return q;
  }

  std::string word(const Node& map, const char* key, const std::string& what, Loc& loc) {
    const Node* n = map.find(key);
    if (n == nullptr) return {};
    loc = n->loc;
    if (!n->isScalar()) {
      if (!n->invalid) diag_.error(n->loc, what + " must be a word, not " + yaml::describe(n->type));
      return {};
    }
    return n->text;
  }

  // Unknown keys of `map` are errors; so are missing required ones (at the map).
  void checkKeys(const Node& map, const std::vector<std::string>& required,
                 const std::vector<std::string>& optional, const std::string& what) {
    for (const Node& k : map.keys) {
      if (std::find(required.begin(), required.end(), k.text) == required.end() &&
          std::find(optional.begin(), optional.end(), k.text) == optional.end()) {
        std::vector<std::string> all = required;
        all.insert(all.end(), optional.begin(), optional.end());
        diag_.error(k.loc, "unknown key '" + k.text + "' in " + what + " (known: " + joined(all) + ")");
      }
    }
    for (const std::string& r : required) {
      if (map.find(r) == nullptr) diag_.error(map.loc, what + " has no '" + r + "' (required)");
    }
  }

  Group group(const Node* n, const std::string& key, const std::vector<std::string>& required,
              const std::vector<std::string>& optional, const std::string& what) {
    Group g;
    g.key = key;
    if (n == nullptr) return g;
    g.loc = n->loc;
    if (!n->isMap()) {
      if (!n->invalid) diag_.error(n->loc, what + " must be a mapping, not " + yaml::describe(n->type));
      return g;
    }
    g.present = true;
    checkKeys(*n, required, optional, what);
    for (size_t i = 0; i < n->keys.size(); ++i) {
      if (n->values[i].isSeq() && n->keys[i].text == "ocv_mv") continue;  // the one list (state_of_charge)
      g.values[n->keys[i].text] = quantity(&n->values[i], what + " " + n->keys[i].text);
    }
    return g;
  }

  Group group(const Node& parent, const GroupSpec& spec, const std::string& what) {
    return group(parent.find(spec.key), spec.key, spec.required, spec.optional,
                 spec.key + std::string(" of ") + what);
  }

  std::vector<Quantity> list(const Node* n, const std::string& what, Loc& loc) {
    std::vector<Quantity> out;
    if (n == nullptr) return out;
    loc = n->loc;
    if (!n->isSeq()) {
      if (!n->invalid)
        diag_.error(n->loc, what + " must be a list [a, b, ...], not " + yaml::describe(n->type));
      return out;
    }
    for (const Node& item : n->items)
      out.push_back(quantity(&item, what + " item"));
    return out;
  }

 private:
  Diagnostics& diag_;
};

}  // namespace

const Quantity& Group::operator[](const std::string& k) const {
  static const Quantity kAbsent;
  const auto it = values.find(k);
  return it == values.end() ? kAbsent : it->second;
}

PackFile readPack(const Sources& sources, int file, Diagnostics& diag) {
  PackFile p;
  p.file = file;
  p.loc = Loc{file, 1, 1};
  const Node root = yaml::parse(sources, file, diag);
  if (!root.isMap()) {
    if (!root.invalid) diag.error(p.loc, "a pack file is a mapping (pack:, device:, cells:, limits:, ...)");
    return p;
  }
  Reader r(diag);
  r.checkKeys(root, {"pack", "device", "chemistry", "cells", "limits", "can"},
              {"description", "cell_inputs", "shunt_micro_ohm", "current_unit_ma", "thermistor",
               "device_protections", "state_of_charge", "balancing", "storage"},
              "the pack file");
  p.name = r.word(root, "pack", "pack", p.nameLoc);
  Loc unused;
  p.description = r.word(root, "description", "description", unused);
  p.device = r.word(root, "device", "device", p.deviceLoc);
  p.chemistry = r.word(root, "chemistry", "chemistry", p.chemistryLoc);
  p.thermistor = r.word(root, "thermistor", "thermistor", p.thermistorLoc);
  p.cells = r.quantity(root.find("cells"), "cells");
  p.cellInputs = r.list(root.find("cell_inputs"), "cell_inputs", p.cellInputsLoc);
  p.shuntMicroOhm = r.quantity(root.find("shunt_micro_ohm"), "shunt_micro_ohm");
  p.currentUnitMa = r.quantity(root.find("current_unit_ma"), "current_unit_ma");

  if (const Node* limits = root.find("limits")) {
    p.limitsLoc = limits->loc;
    if (!limits->isMap()) {
      if (!limits->invalid) diag.error(limits->loc, "limits must be a mapping");
    } else {
      r.checkKeys(*limits,
                  {kCellOv.key, kCellUv.key, kChargeOc.key, kDischargeOc.key, kChargeTemp.key,
                   kDischargeTemp.key, "stale_scans", "comm_loss_scans"},
                  {}, "limits");
      p.cellOvervoltage = r.group(*limits, kCellOv, "limits");
      p.cellUndervoltage = r.group(*limits, kCellUv, "limits");
      p.chargeOvercurrent = r.group(*limits, kChargeOc, "limits");
      p.dischargeOvercurrent = r.group(*limits, kDischargeOc, "limits");
      p.chargeTemperature = r.group(*limits, kChargeTemp, "limits");
      p.dischargeTemperature = r.group(*limits, kDischargeTemp, "limits");
      p.staleScans = r.quantity(limits->find("stale_scans"), "limits stale_scans");
      p.commLossScans = r.quantity(limits->find("comm_loss_scans"), "limits comm_loss_scans");
    }
  }

  if (const Node* prot = root.find("device_protections")) {
    p.protectionsLoc = prot->loc;
    p.hasProtections = true;
    if (!prot->isMap()) {
      if (!prot->invalid) diag.error(prot->loc, "device_protections must be a mapping of protection names");
    } else {
      // Each protection's keys depend on the device: the checker knows them (device.cpp); here every value
      // just has to be a number.
      for (size_t i = 0; i < prot->keys.size(); ++i) {
        const Node& v = prot->values[i];
        const std::string what = "device_protections " + prot->keys[i].text;
        std::vector<std::string> keys;
        if (v.isMap()) {
          for (const Node& k : v.keys)
            keys.push_back(k.text);
        }
        Group g = r.group(&v, prot->keys[i].text, keys, {}, what);
        g.loc = prot->keys[i].loc;
        p.protections.push_back(std::move(g));
      }
    }
  }

  if (const Node* soc = root.find("state_of_charge")) {
    std::vector<std::string> required = kSoc.required;
    required.push_back("ocv_mv");
    p.soc = r.group(soc, kSoc.key, required, kSoc.optional, "state_of_charge");
    if (soc->isMap()) p.ocvMv = r.list(soc->find("ocv_mv"), "state_of_charge ocv_mv", p.ocvLoc);
  }
  p.balancing = r.group(root, kBalancing, "the pack file");
  p.can = r.group(root, kCan, "the pack file");
  if (const Node* st = root.find("storage")) {
    p.storage.key = kStorage.key;
    p.storage.loc = st->loc;
    if (!st->isMap()) {
      if (!st->invalid)
        diag.error(st->loc, std::string("storage must be a mapping, not ") + yaml::describe(st->type));
    } else {
      p.storage.present = true;
      r.checkKeys(*st, kStorage.required, kStorage.optional, "storage of the pack file");
      for (const char* key : {"scan_period_ms", "auto_entry_min", "rest_current_ma"})
        p.storage.values[key] = r.quantity(st->find(key), std::string("storage ") + key);
      p.deviceSleep = r.word(*st, "device_sleep", "storage device_sleep", p.deviceSleepLoc);
    }
  }
  return p;
}

}  // namespace regmapgen::pack
