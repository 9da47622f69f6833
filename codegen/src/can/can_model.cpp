#include "can/can_model.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "model/model.hpp"
#include "model/names.hpp"
#include "yaml/yaml.hpp"

namespace regmapgen::can {
namespace {

using yaml::Node;

// [A-Za-z][A-Za-z0-9_]*: a C++ identifier that does not start with '_'.
bool isCanIdentifier(const std::string& s) {
  return isIdentifier(s) && s[0] != '_';
}

// Reports keys of `map` that are not in `allowed`, and missing keys of `required`.
void checkKeys(const Node& map, const std::vector<std::string>& allowed,
               const std::vector<std::string>& required, const std::string& what, Diagnostics& diag) {
  for (const Node& k : map.keys) {
    if (std::find(allowed.begin(), allowed.end(), k.text) == allowed.end()) {
      diag.error(k.loc, "unknown key '" + k.text + "' in " + what);
    }
  }
  for (const std::string& r : required) {
    if (map.find(r) == nullptr) diag.error(map.loc, what + " has no '" + r + "' (required)");
  }
}

std::optional<int64_t> integer(const Node* n, const std::string& what, Diagnostics& diag) {
  if (n == nullptr) return std::nullopt;
  if (!n->isScalar()) {
    diag.error(n->loc, what + " must be a number, not " + yaml::describe(n->type));
    return std::nullopt;
  }
  auto v = parseNumber(n->text);
  if (!v || !v->isInteger) {
    diag.error(n->loc, what + " must be an integer (got '" + n->text + "')");
    return std::nullopt;
  }
  return v->integer;
}

std::optional<bool> boolean(const Node* n, const std::string& what, Diagnostics& diag) {
  if (n == nullptr) return std::nullopt;
  if (n->isScalar() && (n->text == "true" || n->text == "false")) return n->text == "true";
  diag.error(n->loc, what + " must be true or false");
  return std::nullopt;
}

std::string text(const Node* n) {
  return n != nullptr && n->isScalar() ? n->text : std::string();
}

Signal buildSignal(const Node& node, const std::string& where, Diagnostics& diag) {
  Signal s;
  s.loc = node.loc;
  if (!node.isMap()) {
    diag.error(node.loc, "each signal of " + where + " must be a mapping");
    return s;
  }
  checkKeys(node,
            {"name", "start", "length", "order", "signed", "factor", "offset", "unit", "multiplexer", "count",
             "total", "values", "not_available", "description"},
            {"name", "start", "length"}, "signal of " + where, diag);
  s.name = text(node.find("name"));
  const std::string what = "signal '" + s.name + "' of " + where;
  if (!s.name.empty() && !isCanIdentifier(s.name))
    diag.error(node.find("name")->loc, what + ": not an identifier");
  if (auto v = integer(node.find("start"), what + " start", diag)) {
    if (*v < 0 || *v > 63) diag.error(node.find("start")->loc, what + ": start bit must be 0..63");
    s.start = static_cast<uint32_t>(std::clamp<int64_t>(*v, 0, 63));
  }
  if (auto v = integer(node.find("length"), what + " length", diag)) {
    if (*v < 1 || *v > 32) diag.error(node.find("length")->loc, what + ": length must be 1..32 bits");
    s.length = static_cast<uint32_t>(std::clamp<int64_t>(*v, 1, 32));
  }
  if (const Node* o = node.find("order")) {
    if (o->text == "big") {
      s.bigEndian = true;
    } else if (o->text != "little") {
      diag.error(o->loc, what + ": order must be little or big");
    }
  }
  s.isSigned = boolean(node.find("signed"), what + " signed", diag).value_or(false);
  s.multiplexer = boolean(node.find("multiplexer"), what + " multiplexer", diag).value_or(false);
  for (const char* key : {"factor", "offset"}) {
    if (const Node* n = node.find(key)) {
      auto v = parseNumber(n->text);
      if (!v || (std::string(key) == "factor" && v->real == 0)) {
        diag.error(n->loc, what + ": " + key + " must be a non-zero decimal number (got '" + n->text + "')");
        continue;
      }
      (std::string(key) == "factor" ? s.factor : s.offset) = n->text;
      (std::string(key) == "factor" ? s.factorValue : s.offsetValue) = v->real;
    }
  }
  s.unit = text(node.find("unit"));
  s.description = text(node.find("description"));
  if (auto v = integer(node.find("count"), what + " count", diag)) {
    if (*v < 1 || *v > 8) diag.error(node.find("count")->loc, what + ": count must be 1..8");
    s.count = static_cast<uint32_t>(std::clamp<int64_t>(*v, 1, 8));
  }
  if (auto v = integer(node.find("total"), what + " total", diag)) {
    if (*v < 1 || *v > 1024) diag.error(node.find("total")->loc, what + ": total must be 1..1024");
    s.total = static_cast<uint32_t>(std::clamp<int64_t>(*v, 1, 1024));
  }
  if (s.bigEndian && s.count > 1 && (s.length % 8 != 0 || s.start % 8 != 7)) {
    diag.error(node.loc, what + ": a big-endian group needs whole-byte slots starting at a byte's bit 7");
  }
  if (const Node* vals = node.find("values")) {
    if (!vals->isMap()) {
      diag.error(vals->loc, what + ": values must be a mapping of raw value to description");
    } else {
      for (size_t i = 0; i < vals->keys.size(); ++i) {
        auto k = parseNumber(vals->keys[i].text);
        if (!k || !k->isInteger) {
          diag.error(vals->keys[i].loc, what + ": value key must be an integer");
          continue;
        }
        s.values[k->integer] = vals->values[i].text;
      }
    }
  }
  if (auto v = integer(node.find("not_available"), what + " not_available", diag)) {
    const Loc at = node.find("not_available")->loc;
    if (*v < s.rawMin() || *v > s.rawMax()) {
      diag.error(at, what + ": not_available " + std::to_string(*v) + " is outside the signal's raw range " +
                         std::to_string(s.rawMin()) + ".." + std::to_string(s.rawMax()));
    } else if (s.values.count(*v) != 0) {
      diag.error(
          at, what + ": not_available " + std::to_string(*v) + " is also the value '" + s.values[*v] + "'");
    } else {
      s.notAvailable = *v;
    }
  }
  return s;
}

// Bit positions a signal slot occupies (0..63), in DBC numbering for both byte orders.
std::vector<uint32_t> bitsOf(const Signal& s, uint32_t start) {
  std::vector<uint32_t> bits;
  uint32_t pos = start;
  for (uint32_t i = 0; i < s.length; ++i) {
    bits.push_back(pos);
    if (!s.bigEndian) {
      ++pos;
    } else {
      pos = (pos % 8 == 0) ? pos + 15 : pos - 1;
    }
  }
  return bits;
}

void checkMessage(const Message& m, Diagnostics& diag) {
  const std::string where = "message '" + m.name + "'";
  const Signal* mux = nullptr;
  std::set<std::string> names;
  // Occupied bits: plain signals in slot "always"; group slots of a multiplexed group only matter against
  // plain signals (each frame carries one mux value, so the group's slots never meet each other).
  std::map<uint32_t, std::string> owner;
  for (const Signal& s : m.signals) {
    if (!names.insert(s.name).second) diag.error(s.loc, where + ": duplicate signal name '" + s.name + "'");
    if (s.multiplexer) {
      if (mux != nullptr) diag.error(s.loc, where + ": more than one multiplexer signal");
      if (s.isGroup()) diag.error(s.loc, where + ": the multiplexer cannot be a group");
      mux = &s;
    }
    for (uint32_t k = 0; k < s.count; ++k) {
      for (uint32_t bit : bitsOf(s, s.slotStart(k))) {
        if (bit >= m.dlc * 8) {
          diag.error(s.loc, where + ": signal '" + s.name + "' runs past the " + std::to_string(m.dlc) +
                                "-byte payload (bit " + std::to_string(bit) + ")");
          break;
        }
        auto [it, fresh] = owner.emplace(bit, s.name);
        if (!fresh && it->second != s.name) {
          diag.error(s.loc, where + ": signal '" + s.name + "' overlaps '" + it->second + "' at bit " +
                                std::to_string(bit));
          break;
        }
        if (!fresh && it->second == s.name && k > 0) {
          diag.error(s.loc, where + ": the slots of group '" + s.name + "' overlap each other");
          break;
        }
      }
    }
  }
  for (const Signal& s : m.signals) {
    if (s.total > 0 && mux == nullptr) {
      diag.error(s.loc, where + ": group '" + s.name + "' has a total but the message has no multiplexer");
    }
    if (s.total > 0 && mux != nullptr) {
      const uint32_t frames = (s.total + s.count - 1) / s.count;
      if (frames > (1U << mux->length)) {
        diag.error(s.loc, where + ": group '" + s.name + "' needs " + std::to_string(frames) +
                              " frames but the multiplexer has only " + std::to_string(mux->length) +
                              " bits");
      }
    }
  }
}

}  // namespace

const Signal* Message::multiplexer() const {
  for (const Signal& s : signals) {
    if (s.multiplexer) return &s;
  }
  return nullptr;
}

uint32_t Message::framesPerCycle() const {
  uint32_t frames = 1;
  for (const Signal& s : signals) {
    if (s.total > 0) frames = std::max(frames, (s.total + s.count - 1) / s.count);
  }
  return frames;
}

std::vector<std::string> Catalogue::layouts() const {
  std::vector<std::string> out;
  for (const Message& m : messages) {
    if (m.layout != kEveryLayout && std::find(out.begin(), out.end(), m.layout) == out.end())
      out.push_back(m.layout);
  }
  return out;
}

Catalogue buildCatalogue(const Sources& sources, int file, Diagnostics& diag) {
  Catalogue cat;
  const Node root = yaml::parse(sources, file, diag);
  if (!root.isMap()) {
    diag.error(Loc{file, 1, 1}, "a CAN catalogue must be a mapping with 'catalogue' and 'messages'");
    return cat;
  }
  checkKeys(root, {"catalogue", "bitrate", "node", "messages"}, {"catalogue", "messages"}, "the catalogue",
            diag);
  cat.name = text(root.find("catalogue"));
  if (!cat.name.empty() && !isCanIdentifier(cat.name)) {
    diag.error(root.find("catalogue")->loc, "catalogue name must be an identifier");
  }
  if (auto v = integer(root.find("bitrate"), "bitrate", diag)) cat.bitrate = static_cast<uint32_t>(*v);
  if (root.find("node") != nullptr) cat.node = text(root.find("node"));

  const Node* messages = root.find("messages");
  if (messages == nullptr) return cat;
  if (!messages->isSeq()) {
    diag.error(messages->loc, "messages must be a sequence");
    return cat;
  }
  std::map<std::string, Loc> names;
  std::map<std::pair<std::string, uint32_t>, std::string> ids;
  for (const Node& node : messages->items) {
    if (!node.isMap()) {
      diag.error(node.loc, "each message must be a mapping");
      continue;
    }
    Message m;
    m.loc = node.loc;
    m.name = text(node.find("name"));
    const std::string where = "message '" + m.name + "'";
    checkKeys(node,
              {"name", "id", "extended", "layout", "direction", "dlc", "cycle_ms", "description", "signals"},
              {"name", "id", "signals"}, m.name.empty() ? "a message" : where, diag);
    if (!m.name.empty() && !isCanIdentifier(m.name))
      diag.error(node.find("name")->loc, where + ": not an identifier");
    if (!m.name.empty() && !names.emplace(m.name, node.loc).second) {
      diag.error(node.find("name")->loc, "duplicate message name '" + m.name + "'");
    }
    m.extended = boolean(node.find("extended"), where + " extended", diag).value_or(false);
    if (auto v = integer(node.find("id"), where + " id", diag)) {
      const int64_t limit = m.extended ? 0x1FFFFFFF : 0x7FF;
      if (*v < 0 || *v > limit) {
        diag.error(node.find("id")->loc, where + ": id does not fit " + (m.extended ? "29" : "11") + " bits");
      }
      m.id = static_cast<uint32_t>(std::clamp<int64_t>(*v, 0, limit));
    }
    if (const Node* l = node.find("layout")) m.layout = l->text;
    if (const Node* d = node.find("direction")) {
      if (d->text == "rx") {
        m.received = true;
      } else if (d->text != "tx") {
        diag.error(d->loc, where + ": direction must be tx or rx");
      }
    }
    if (!isCanIdentifier(m.layout)) diag.error(node.loc, where + ": layout must be an identifier");
    if (auto v = integer(node.find("dlc"), where + " dlc", diag)) {
      if (*v < 0 || *v > 8) diag.error(node.find("dlc")->loc, where + ": dlc must be 0..8 (classic CAN)");
      m.dlc = static_cast<uint32_t>(std::clamp<int64_t>(*v, 0, 8));
    }
    if (auto v = integer(node.find("cycle_ms"), where + " cycle_ms", diag)) {
      m.cycleMs = static_cast<uint32_t>(std::max<int64_t>(*v, 0));
    }
    m.description = text(node.find("description"));
    if (node.find("id") != nullptr) {
      // An id is unique within each DBC: a message of every layout clashes with any message of the id.
      for (const auto& [key, other] : ids) {
        const bool sameDbc = key.first == m.layout || key.first == kEveryLayout || m.layout == kEveryLayout;
        if (key.second == m.id && sameDbc) {
          diag.error(node.find("id")->loc, where + ": id already used by '" + other + "'");
          break;
        }
      }
      ids.emplace(std::make_pair(m.layout, m.id), m.name);
    }
    const Node* sigs = node.find("signals");
    if (sigs != nullptr && !sigs->isSeq()) {
      diag.error(sigs->loc, where + ": signals must be a sequence");
    } else if (sigs != nullptr) {
      if (sigs->items.empty()) diag.error(sigs->loc, where + ": a message needs at least one signal");
      for (const Node& s : sigs->items)
        m.signals.push_back(buildSignal(s, where, diag));
    }
    checkMessage(m, diag);
    cat.messages.push_back(std::move(m));
  }
  return cat;
}

}  // namespace regmapgen::can
