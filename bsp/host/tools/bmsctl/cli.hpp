// bmsctl command-line front end: argument model, the device registry, and shared parsing helpers.
//
//   bmsctl trace <device> [--crc|--pec] [--devices N] [--<flag>[=value]...] <operation> [args...]
//
// The front end parses the common shape; the family that registered <device> interprets the operation.
// Every error is reported as "bmsctl: error: ..." on stderr with exit status 2 (usage) or 1 (the operation
// failed on the emulated bus); nothing is printed on stdout for a usage error.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "regmap/table.hpp"

namespace bmsctl {

struct TraceRequest {
  std::string device;                        // e.g. "bq76952"
  std::map<std::string, std::string> flags;  // "--crc" -> "", "--devices" -> "16"
  std::string operation;                     // e.g. "subcmd"
  std::vector<std::string> args;             // operation arguments, as typed
};

// A family handler runs one request and returns the process exit status.
using TraceHandler = int (*)(const TraceRequest& request);

struct DeviceEntry {
  const char* name;
  const char* summary;  // one line for `bmsctl --help`
  TraceHandler handler;
  // Every operation and option the handler accepts, one per line ("read <cmd> <len>   what it does"), for
  // `bmsctl --help` (tests/tools/help_check.py holds it to the handler's parser).
  const char* usage = nullptr;
};

// Registers a device at static-initialisation time: `static bmsctl::Registrar r{{"bq76952", "...", &run}};`
struct Registrar {
  explicit Registrar(DeviceEntry entry);
};
const std::vector<DeviceEntry>& devices();

// Prints "bmsctl: error: <message>" and returns 2 (the usage-error status).
int usageError(const std::string& message);

// Parses "0x1F", "1F" (hex digits only when `hexDefault`) or decimal; nullopt when malformed or > max.
std::optional<uint32_t> parseNumber(const std::string& text, uint32_t max, bool hexDefault = false);
// Parses a list of hex bytes, each "82", "0x82" or "F0"; nullopt if any is malformed.
std::optional<std::vector<uint8_t>> parseHexBytes(const std::vector<std::string>& words);

// Flag helpers: whether a flag is present; its numeric value (usageError-ready message on failure).
bool hasFlag(const TraceRequest& request, const std::string& flag);
// Rejects any flag not in `allowed`; returns an error message or an empty string.
std::string checkFlags(const TraceRequest& request, const std::vector<std::string>& allowed);

// The entry of `kind` that `text` names, matched as fw::regmap::findByName() matches; a qualified name
// ("dm::EnabledProtectionsA", "mac.SafetyStatus") must be qualified with the namespace of `kind`. nullptr if
// there is none.
const fw::regmap::EntryInfo* findNamed(std::span<const fw::regmap::EntryInfo> table, fw::regmap::Kind kind,
                                       const std::string& text);

// Output helpers for the '#' lines.
// A bit-field value of `size` bytes: "0x00C0 (DSG INIT)", the hex value then the titles of the fields that
// are set ("TITLE=n" for a multi-bit field); just "0x0000" when none is.
std::string flagsText(uint64_t raw, unsigned size, std::span<const fw::regmap::FieldInfo> fields);
// Bytes as two hex digits each, separated by spaces ("82 F0"), preceded by `before`; "" for no bytes.
std::string hexJoin(std::span<const uint8_t> bytes, const char* before = "");

}  // namespace bmsctl
