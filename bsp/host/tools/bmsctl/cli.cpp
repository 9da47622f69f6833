#include "bmsctl/cli.hpp"

#include <cctype>
#include <cstdio>

namespace bmsctl {
namespace {
std::vector<DeviceEntry>& registry() {
  static std::vector<DeviceEntry> entries;
  return entries;
}
}  // namespace

Registrar::Registrar(DeviceEntry entry) {
  registry().push_back(entry);
}
const std::vector<DeviceEntry>& devices() {
  return registry();
}

int usageError(const std::string& message) {
  std::fprintf(stderr, "bmsctl: error: %s\n", message.c_str());
  return 2;
}

std::optional<uint32_t> parseNumber(const std::string& text, uint32_t max, bool hexDefault) {
  std::string digits = text;
  int base = hexDefault ? 16 : 10;
  if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) {
    digits = digits.substr(2);
    base = 16;
  }
  if (digits.empty() || digits.size() > 10) return std::nullopt;
  uint64_t value = 0;
  for (char c : digits) {
    int d;
    if (std::isdigit(static_cast<unsigned char>(c))) {
      d = c - '0';
    } else if (base == 16 && std::isxdigit(static_cast<unsigned char>(c))) {
      d = std::tolower(static_cast<unsigned char>(c)) - 'a' + 10;
    } else {
      return std::nullopt;
    }
    value = value * static_cast<uint64_t>(base) + static_cast<uint64_t>(d);
  }
  if (value > max) return std::nullopt;
  return static_cast<uint32_t>(value);
}

std::optional<std::vector<uint8_t>> parseHexBytes(const std::vector<std::string>& words) {
  std::vector<uint8_t> bytes;
  for (const auto& w : words) {
    auto v = parseNumber(w, 0xFF, true);
    if (!v || w.size() > 4) return std::nullopt;
    bytes.push_back(static_cast<uint8_t>(*v));
  }
  return bytes;
}

bool hasFlag(const TraceRequest& request, const std::string& flag) {
  return request.flags.count(flag) != 0;
}

std::string checkFlags(const TraceRequest& request, const std::vector<std::string>& allowed) {
  for (const auto& [flag, value] : request.flags) {
    bool ok = false;
    for (const auto& a : allowed)
      ok = ok || a == flag;
    if (!ok) return "option " + flag + " is not valid for " + request.device;
  }
  return {};
}

const fw::regmap::EntryInfo* findNamed(std::span<const fw::regmap::EntryInfo> table, fw::regmap::Kind kind,
                                       const std::string& text) {
  const bool qualified = text.find("::") != std::string::npos || text.find('.') != std::string::npos;
  const std::string name = qualified ? text : std::string(fw::regmap::kindNamespace(kind)) + "::" + text;
  const fw::regmap::EntryInfo* e = fw::regmap::findByName(table, name);
  return e != nullptr && e->kind == kind ? e : nullptr;
}

std::string flagsText(uint64_t raw, unsigned size, std::span<const fw::regmap::FieldInfo> fields) {
  char buf[24];
  const uint64_t bits = size >= 8 ? raw : raw & ((1ULL << (8 * size)) - 1);
  std::snprintf(buf, sizeof buf, "0x%0*llX", static_cast<int>(2 * size),
                static_cast<unsigned long long>(bits));
  std::string set;
  for (const auto& f : fields) {
    const uint64_t field = (raw >> f.lsb) & ((1ULL << f.width) - 1);
    if (field == 0) continue;
    set += (set.empty() ? "" : " ") + std::string(f.title);
    if (f.width > 1) set += "=" + std::to_string(field);
  }
  return set.empty() ? buf : buf + (" (" + set + ")");
}

std::string hexJoin(std::span<const uint8_t> bytes, const char* before) {
  std::string s;
  char buf[4];
  for (uint8_t b : bytes) {
    std::snprintf(buf, sizeof buf, "%s%02X", s.empty() ? "" : " ", b);
    s += buf;
  }
  return s.empty() ? s : before + s;
}

}  // namespace bmsctl
