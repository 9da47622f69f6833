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

}  // namespace bmsctl
