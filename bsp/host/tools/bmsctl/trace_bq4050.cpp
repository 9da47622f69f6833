// bmsctl trace bq4050: one SMBus access through the real BQ4050 driver against the gauge emulator, with the
// exact wire traffic (README "Host tools"):
//
//   bmsctl trace bq4050 [--pec] word <cmd>      SMBus read word
//   bmsctl trace bq4050 [--pec] block <cmd>     SMBus block read
//   bmsctl trace bq4050 [--pec] mac <subcmd>    ManufacturerBlockAccess read (command-only subcommands are
//                                               sent as a ManufacturerAccess word write instead)
//   bmsctl trace bq4050 app-start               the lp-mspm0g3507-bq4050 application (firmware/app/
//                                               bq4050_app.hpp) from reset until its first complete scan
//
// <cmd> is an SBS command in hex (0x09 or 09) or its register-map name (Voltage, RelativeStateOfCharge);
// <subcmd> a MAC subcommand in hex (0x0001) or its name (DeviceType, SafetyStatus, FETControl). With --pec
// every transaction carries a PEC; without it each value is read twice and must agree (the driver's rule).
// The bus runs at 100 kHz with the image's 25 ms stretch limit. Output: one line per transaction as it
// happens, then '#' lines decoding the result; exit 0. A failed access prints its trace, then
// "# error: <status>", exit 1. Bad arguments: "bmsctl: error: ..." on stderr, exit 2. app-start adds a
// "# at <ms>" line before each transaction that follows more than 2 ms of idle bus (the driver keeps 1 ms
// between any two).
#include <cstdio>
#include <string>
#include <vector>

#include "bmsctl/cli.hpp"
#include "bq4050/board.hpp"
#include "bq4050/gauge_emulator.hpp"
#include "core/status.hpp"
#include "drivers/bq4050/gauge.hpp"
#include "regmap/bq4050_table.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"

namespace {

namespace bq = fw::drivers::bq4050;
namespace rm = fw::regmap;
using fw::Status;

constexpr fw::sched::TaskId kTask = 1;
constexpr fw::sched::EventMask kBus = 0x1;
constexpr fw::sched::EventMask kTimer = 0x2;

class DriverTask final : public fw::sched::Task {
 public:
  bq::Gauge* gauge = nullptr;
  bool done = false;
  void run(fw::sched::EventMask events) override {
    if (gauge != nullptr && (events & gauge->events()) != 0 &&
        gauge->onEvent(events) == fw::drivers::Progress::Done)
      done = true;
  }
};

struct Target {
  uint32_t code = 0;
  const rm::EntryInfo* entry = nullptr;  // nullptr: an address the register map does not name
};

// Resolves a hex code or a register-map name of `kind`; an empty string in `error` means success.
Target resolve(const std::string& text, rm::Kind kind, uint32_t max, std::string& error) {
  Target t;
  if (auto n = bmsctl::parseNumber(text, max, true)) {
    t.code = *n;
    t.entry = rm::findByAddress(rm::bq4050::entries, kind, t.code);
    return t;
  }
  t.entry = bmsctl::findNamed(rm::bq4050::entries, kind, text);
  if (t.entry == nullptr) {
    error = "'" + text + "' is neither a hex " + (kind == rm::Kind::Mac ? "subcommand" : "command") +
            " nor a BQ4050 " + std::string(rm::kindName(kind)) + " name";
    return t;
  }
  t.code = t.entry->address;
  return t;
}

std::string unitText(rm::Unit u) {
  return u == rm::Unit::Percent ? "%" : rm::unitSymbol(u);
}

// "15000 mV", "298.2 K", "0x00C0 (DSG INIT)" (the bit fields that are set), "-1500 mA".
std::string formatScalar(const rm::EntryInfo& e, int64_t raw) {
  char buf[96];
  if (!e.fields.empty() || e.unit == rm::Unit::None)
    return bmsctl::flagsText(static_cast<uint64_t>(raw), e.size, e.fields);
  if (e.scale.den == 1) {
    std::snprintf(buf, sizeof buf, "%lld %s", static_cast<long long>(raw * e.scale.num),
                  unitText(e.unit).c_str());
    return buf;
  }
  int decimals = 0;
  for (int32_t d = e.scale.den; d > 1; d /= 10)
    ++decimals;
  std::snprintf(buf, sizeof buf, "%.*f %s (raw %lld)", decimals,
                static_cast<double>(raw) * e.scale.num / e.scale.den, unitText(e.unit).c_str(),
                static_cast<long long>(raw));
  return buf;
}

std::string nameOf(const Target& t, int digits) {
  if (t.entry != nullptr) return t.entry->name;
  char buf[12];
  std::snprintf(buf, sizeof buf, "0x%0*X", digits, t.code);
  return buf;
}

// A block's contents as text: a string entry in quotes, a scalar entry decoded, anything else in hex.
std::string formatBlock(const Target& t, const uint8_t* data, size_t n) {
  if (t.entry != nullptr && t.entry->type[0] == 'S') return "\"" + std::string(data, data + n) + "\"";
  if (t.entry != nullptr && t.entry->scalar && n == t.entry->size) {
    return formatScalar(*t.entry, rm::decodeRaw(*t.entry, std::span<const uint8_t>(data, n)));
  }
  return "[" + std::to_string(n) + " bytes]" + bmsctl::hexJoin({data, n}, " ");
}

// The application from reset to its first complete scan, as the image composes it (PEC detected by the
// probe): every transaction, a "# at" line before each one that follows more than 2 ms of idle bus, then the
// outcome.
int appStart() {
  bsp::host::Bq4050Board b;
  uint64_t last = 0;
  b.bus.onRecord([&](const bsp::host::I2cWireRecord& r) {
    if (r.startUs > last + 2000) std::printf("# at %.1f ms\n", static_cast<double>(r.startUs) / 1000.0);
    last = r.endUs;
    std::printf("%s\n", r.text.c_str());
  });
  const bool scanned = b.h.runUntil([&] { return b.app.monitor().stats().scans >= 1; }, fw::s(10));
  b.bus.onRecord({});
  if (!scanned) {
    std::printf("# app-start: no complete scan within 10 s\n");
    return 1;
  }
  const bool valid = b.app.pack().boards[0].last == Status::Ok;
  std::printf(
      "# app-start: first complete scan at %.1f ms (%s), pec=%s, %llu transactions, %llu us of bus time\n",
      static_cast<double>(b.h.nowUs()) / 1000.0, valid ? "valid" : "failed",
      b.app.monitor().gauge().pecEnabled() ? "on" : "off",
      static_cast<unsigned long long>(b.bus.transactions()),
      static_cast<unsigned long long>(b.bus.busTimeUs()));
  return valid ? 0 : 1;
}

int run(const bmsctl::TraceRequest& request) {
  if (std::string e = bmsctl::checkFlags(request, {"--pec"}); !e.empty()) return bmsctl::usageError(e);
  if (bmsctl::hasFlag(request, "--pec") && !request.flags.at("--pec").empty()) {
    return bmsctl::usageError("--pec takes no value");
  }
  const std::string& op = request.operation;
  if (op == "app-start") {
    if (!request.args.empty() || bmsctl::hasFlag(request, "--pec")) {
      return bmsctl::usageError("app-start takes no arguments (the application detects PEC itself)");
    }
    return appStart();
  }
  if (op != "word" && op != "block" && op != "mac") {
    return bmsctl::usageError("unknown bq4050 operation '" + op +
                              "' (expected word, block, mac or app-start)");
  }
  if (request.args.size() != 1) {
    return bmsctl::usageError("bq4050 " + op + " takes exactly one " +
                              (op == "mac" ? "subcommand" : "command") +
                              " (hex or name), e.g. 'word Voltage', 'mac 0x0001'");
  }
  const rm::Kind kind = op == "mac" ? rm::Kind::Mac : rm::Kind::Sbs;
  std::string error;
  const Target target = resolve(request.args[0], kind, op == "mac" ? 0xFFFF : 0xFF, error);
  if (!error.empty()) return bmsctl::usageError(error);
  if (op == "word" && target.entry != nullptr && (target.entry->size != 2 || target.entry->variable)) {
    return bmsctl::usageError(std::string(target.entry->name) + " is not an SMBus word; use 'block'");
  }

  bsp::host::Harness harness;
  bsp::host::SimI2cBus bus(harness.clock, harness.irq, {100000, fw::ms(25), fw::us(4)});
  bsp::host::Bq4050Emulator emulator;
  bus.attach(bsp::host::Bq4050Emulator::kAddress, emulator);
  bus.onRecord([](const bsp::host::I2cWireRecord& r) { std::printf("%s\n", r.text.c_str()); });
  bq::GaugeConfig config;
  config.pec = bmsctl::hasFlag(request, "--pec") ? bq::PecMode::On : bq::PecMode::Off;
  DriverTask task;
  bq::Gauge gauge(bus, harness.clock, fw::drivers::DriverContext{harness.sched, kTask, kBus, kTimer}, config);
  task.gauge = &gauge;
  harness.sched.addTask(kTask, task);

  uint16_t word = 0;
  uint8_t data[bq::kMaxBlock] = {};
  uint8_t length = 0;
  const bool commandOnly = target.entry != nullptr && target.entry->access == rm::Access::CommandOnly;
  Status started;
  if (op == "word") {
    started = gauge.startReadWord(static_cast<uint8_t>(target.code), word);
  } else if (op == "block") {
    started = gauge.startReadBlock(static_cast<uint8_t>(target.code), data, length);
  } else if (commandOnly) {
    started = gauge.startSendMac(static_cast<uint16_t>(target.code));
  } else {
    started = gauge.startReadMac(static_cast<uint16_t>(target.code), data, length);
  }
  if (started == Status::Ok) harness.runUntil([&] { return task.done; }, fw::s(10));
  const Status result = started != Status::Ok ? started : task.done ? gauge.result() : Status::Timeout;
  if (result != Status::Ok) {
    std::printf("# error: %s\n", fw::statusName(result));
    return 1;
  }

  if (op == "word") {
    const uint8_t bytes[2] = {static_cast<uint8_t>(word), static_cast<uint8_t>(word >> 8)};
    if (target.entry != nullptr) {
      std::printf("# %s = %s\n", target.entry->name,
                  formatScalar(*target.entry, rm::decodeRaw(*target.entry, bytes)).c_str());
    } else {
      std::printf("# %s = 0x%04X (%u)\n", nameOf(target, 2).c_str(), word, word);
    }
  } else if (commandOnly) {
    std::printf("# %s (0x%04X) sent through ManufacturerAccess\n", target.entry->name, target.code);
  } else {
    std::printf("# %s = %s\n", nameOf(target, op == "mac" ? 4 : 2).c_str(),
                formatBlock(target, data, length).c_str());
  }
  std::printf("# pec=%s transactions=%llu bus_us=%llu\n", config.pec == bq::PecMode::On ? "on" : "off",
              static_cast<unsigned long long>(bus.transactions()),
              static_cast<unsigned long long>(bus.busTimeUs()));
  return 0;
}

const bmsctl::Registrar registrar{
    {"bq4050", "BQ4050 gas gauge on SMBus, 100 kHz", &run,
     "word <cmd>                   SMBus read word (an SBS command: hex, or its name, e.g. Voltage)\n"
     "block <cmd>                  SMBus block read\n"
     "mac <subcmd>                 ManufacturerBlockAccess read (hex, or its name, e.g. DeviceType)\n"
     "app-start                    the image's application from reset to its first complete scan\n"
     "--pec                        every transaction with a PEC (else each value is read twice)"}};

}  // namespace
