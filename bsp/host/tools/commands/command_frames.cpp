#include "command_frames.hpp"

#include <charconv>
#include <cstdio>

#include "app/command/e2e.hpp"

namespace bmstool {

namespace {

constexpr uint8_t kDefaultNode = 1;  // FW_COMMAND_NODE's default (firmware/app/config.hpp)

// Bit positions of a signal (DBC numbering: Intel from the LSB up, Motorola from the MSB down).
std::vector<uint32_t> bitsOf(const table::Signal& s) {
  std::vector<uint32_t> bits;
  uint32_t pos = s.start;
  for (uint32_t i = 0; i < s.length; ++i) {
    bits.push_back(pos);
    pos = !s.bigEndian ? pos + 1 : (pos % 8 == 0 ? pos + 15 : pos - 1);
  }
  return bits;  // least significant bit first for Intel, most significant first for Motorola
}

void setSignal(const table::Signal& s, uint64_t raw, fw::hal::CanFrame& f) {
  const auto bits = bitsOf(s);
  for (uint32_t i = 0; i < s.length; ++i) {
    const uint32_t bit = bits[i];
    const uint32_t valueBit = s.bigEndian ? s.length - 1 - i : i;
    const bool on = ((raw >> valueBit) & 1U) != 0;
    auto& byte = f.data[bit / 8];
    byte = static_cast<uint8_t>(on ? byte | (1U << (bit % 8)) : byte & ~(1U << (bit % 8)));
  }
}

int64_t rawMin(const table::Signal& s) {
  return s.isSigned ? -(int64_t{1} << (s.length - 1)) : 0;
}
int64_t rawMax(const table::Signal& s) {
  return s.isSigned ? (int64_t{1} << (s.length - 1)) - 1 : (int64_t{1} << s.length) - 1;
}

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    auto low = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; };
    if (low(a[i]) != low(b[i])) return false;
  }
  return true;
}

}  // namespace

const table::Message* findMessage(std::string_view name) {
  for (const table::Message& m : table::kMessages) {
    if (equalsIgnoringCase(m.name, name)) return &m;
  }
  return nullptr;
}

const table::Message* findMessage(uint32_t id, bool extended) {
  for (const table::Message& m : table::kMessages) {
    if (m.id == id && m.extended == extended) return &m;
  }
  return nullptr;
}

const table::Signal* findSignal(const table::Message& m, std::string_view name) {
  for (uint8_t i = 0; i < m.signalCount; ++i) {
    if (equalsIgnoringCase(m.signals[i].name, name)) return &m.signals[i];
  }
  return nullptr;
}

std::optional<int64_t> parseValue(const table::Signal& s, std::string_view text, std::string& error) {
  for (uint8_t i = 0; i < s.valueCount; ++i) {
    if (text == s.values[i].name) return s.values[i].raw;
  }
  int64_t v = 0;
  const bool negative = !text.empty() && text[0] == '-';
  std::string_view digits = negative ? text.substr(1) : text;
  int base = 10;
  if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) {
    digits.remove_prefix(2);
    base = 16;
  }
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v, base);
  if (digits.empty() || ec != std::errc{} || end != digits.data() + digits.size()) {
    std::string names;
    for (uint8_t i = 0; i < s.valueCount; ++i)
      names += std::string(names.empty() ? "" : ", ") + s.values[i].name;
    error = std::string(s.name) + ": '" + std::string(text) + "' is not a number" +
            (names.empty() ? "" : " or one of " + names);
    return std::nullopt;
  }
  if (negative) v = -v;
  if (v < rawMin(s) || v > rawMax(s)) {
    error = std::string(s.name) + ": " + std::string(text) + " is outside " + std::to_string(rawMin(s)) +
            ".." + std::to_string(rawMax(s));
    return std::nullopt;
  }
  return v;
}

int64_t signalValue(const table::Signal& s, const fw::hal::CanFrame& f) {
  const auto bits = bitsOf(s);
  uint64_t raw = 0;
  for (uint32_t i = 0; i < s.length; ++i) {
    const uint32_t bit = bits[i];
    const uint32_t valueBit = s.bigEndian ? s.length - 1 - i : i;
    if ((f.data[bit / 8] >> (bit % 8)) & 1U) raw |= uint64_t{1} << valueBit;
  }
  if (s.isSigned && ((raw >> (s.length - 1)) & 1U))
    return static_cast<int64_t>(raw) - (int64_t{1} << s.length);
  return static_cast<int64_t>(raw);
}

std::string describe(const fw::hal::CanFrame& f) {
  char buf[32];
  const table::Message* m = findMessage(f.id, f.extended);
  if (m == nullptr) {
    std::snprintf(buf, sizeof buf, "0x%03X [%u]", f.id, f.dlc);
    std::string out = buf;
    for (uint8_t i = 0; i < f.dlc && i < 8; ++i) {
      std::snprintf(buf, sizeof buf, " %02X", f.data[i]);
      out += buf;
    }
    return out;
  }
  std::string out = m->name;
  for (uint8_t i = 0; i < m->signalCount; ++i) {
    const table::Signal& s = m->signals[i];
    const int64_t v = signalValue(s, f);
    out += std::string(" ") + s.name + "=";
    bool named = false;
    for (uint8_t k = 0; k < s.valueCount && !named; ++k) {
      if (s.values[k].raw == v) out += s.values[k].name, named = true;
    }
    if (named) continue;
    if (std::string_view(s.name) == "Command" || std::string_view(s.name) == "TraceId") {
      std::snprintf(buf, sizeof buf, "0x%llX", static_cast<unsigned long long>(v));
      out += buf;
    } else {
      out += std::to_string(v);
    }
  }
  return out;
}

std::optional<fw::hal::CanFrame> CommandBuilder::build(std::string_view message,
                                                       const std::vector<std::string>& words,
                                                       std::string& error) {
  const table::Message* m = findMessage(message);
  if (m == nullptr) {
    std::string known;
    for (const table::Message& k : table::kMessages) {
      if (k.received) known += std::string(known.empty() ? "" : ", ") + k.name;
    }
    error = "unknown message '" + std::string(message) + "' (commands: " + known + ")";
    return std::nullopt;
  }
  return build(*m, words, error);
}

std::optional<fw::hal::CanFrame> CommandBuilder::build(const table::Message& m,
                                                       const std::vector<std::string>& words,
                                                       std::string& error) {
  fw::hal::CanFrame f{m.id, m.extended, m.dlc, {}};
  std::map<std::string, int64_t> given;
  for (const std::string& w : words) {
    const size_t eq = w.find('=');
    if (eq == std::string::npos || eq == 0) {
      error = "'" + w + "' is not Signal=value";
      return std::nullopt;
    }
    const table::Signal* s = findSignal(m, std::string_view(w).substr(0, eq));
    if (s == nullptr) {
      std::string known;
      for (uint8_t i = 0; i < m.signalCount; ++i)
        known += std::string(known.empty() ? "" : ", ") + m.signals[i].name;
      error = std::string(m.name) + " has no signal '" + w.substr(0, eq) + "' (signals: " + known + ")";
      return std::nullopt;
    }
    const auto v = parseValue(*s, std::string_view(w).substr(eq + 1), error);
    if (!v) return std::nullopt;
    given[s->name] = *v;
  }
  if (m.received) {
    if (!given.count("Target")) given["Target"] = kDefaultNode;
    if (!given.count("Counter")) {
      auto [it, fresh] = next_.emplace(m.id, first_);
      given["Counter"] = it->second;
    }
    next_[m.id] = static_cast<uint8_t>((given["Counter"] + 1) & 0x0F);
  }
  for (uint8_t i = 0; i < m.signalCount; ++i) {
    const auto it = given.find(m.signals[i].name);
    if (it != given.end()) setSignal(m.signals[i], static_cast<uint64_t>(it->second), f);
  }
  if (m.received && !given.count("Crc") && m.dlc >= 1)
    f.data[0] = fw::app::command::frameCrc(f.id, f.data.data(), f.dlc);
  return f;
}

}  // namespace bmstool
