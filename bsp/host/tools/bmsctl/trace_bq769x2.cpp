// bmsctl trace for the BQ769x2 (bq76952) and BQ7690x (bq76907, bq76905) battery monitors on I2C.
//
//   bmsctl trace bq76952|bq76907|bq76905 [--crc] [--address=0xNN] [--fault=<kind>] <operation> [args...]
//     read <cmd> <len>          direct read of len bytes (a block read across contiguous commands)
//     write <cmd> <bytes...>    direct write
//     subcmd <code>             command-only subcommand
//     subcmd-read <code> [len]  subcommand read: echo poll, 0x61 length, 0x60 checksum
//     dm-read <addr> <len>      data-memory read
//     dm-write <addr> <bytes..> data-memory write as a CONFIG_UPDATE transaction (skipped when the value is
//                               already there)
//     app-start                 the image's application (firmware/app/monitors/bq769x_app.hpp with the host
//     defaults,
//                               i.e. the full application and its settings table) from reset to its first
//                               complete scan: every transaction it sends, then when the scan completed
//   <cmd>, <code> and <addr> are hex (0x14, 14) or generated names (Cell1Voltage, FET_ENABLE,
//   EnabledProtectionsA); lengths are decimal; bytes are hex.
//   --crc         both the emulated device and the driver use the per-byte I2C CRC
//   --address=N   the 7-bit address the driver uses (the device stays at 0x08): shows the 0x08/0x10 mix-up
//   --fault=K     inject one fault into the emulator before the operation: nack, nack-always, stretch, crc,
//                 checksum, length, stale, reset
//
// It runs the real driver (firmware/drivers/bq769x2) against the device emulator on virtual time and prints
// every transaction as it completes (README "Host tools"), then `#` lines decoding the result with the
// runtime register table's names, units and scales. A failed operation prints `# error: <status>` and
// exits 1; bad arguments exit 2 without touching the bus.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bmsctl/cli.hpp"
#include "bq769x2/board.hpp"
#include "bq769x2/emulator.hpp"
#include "drivers/bq769x2/monitor.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq7690x_table.hpp"
#include "regmap/bq769x2.hpp"
#include "regmap/bq769x2_table.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"

namespace {

namespace drv = fw::drivers::bq769x2;
using bsp::host::Bq769xEmulator;
using fw::Status;
using fw::regmap::EntryInfo;
using fw::regmap::Kind;

constexpr fw::sched::TaskId kTask = 1;
constexpr fw::sched::EventMask kBusEvent = 0x1;
constexpr fw::sched::EventMask kTimerEvent = 0x2;

class Runner final : public fw::sched::Task {
 public:
  drv::Monitor* monitor = nullptr;
  bool done = false;
  void run(fw::sched::EventMask ev) override {
    const bool linkBusy = monitor->link().busy();
    const bool monitorBusy = monitor->busy();
    if (monitor->onEvent(ev) == fw::drivers::Progress::Done ||
        (!monitorBusy && linkBusy && !monitor->link().busy()))
      done = true;
  }
};

std::string hex(uint64_t v, int digits) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%0*llX", digits, static_cast<unsigned long long>(v));
  return buf;
}

// "3700 mV", "298.2 K", "0x5082 (SSA FULLSCAN)".
std::string formatValue(const EntryInfo& e, std::span<const uint8_t> bytes) {
  if (!e.scalar || bytes.size() < e.size) {
    return "[" +
           bmsctl::hexJoin(bytes.first(std::min<size_t>(bytes.size(), e.size == 0 ? bytes.size() : e.size))) +
           "]";
  }
  const int64_t v = fw::regmap::decodeRaw(e, bytes);
  const bool flags = !e.fields.empty() || (e.type != nullptr && e.type[0] == 'H');
  if (flags) return bmsctl::flagsText(static_cast<uint64_t>(v), e.size, e.fields);
  if (e.unit == fw::regmap::Unit::None && !e.isSigned && e.scale.num == 1 && e.scale.den == 1) {
    return hex(static_cast<uint64_t>(v), 2 * e.size) + " (" + std::to_string(v) +
           ")";  // codes: DEVICE_NUMBER
  }
  std::string number;
  const int64_t num = v * e.scale.num;
  if (e.scale.den == 1) {
    number = std::to_string(num);
  } else {
    int decimals = 0;
    for (int64_t d = e.scale.den; d > 1 && d % 10 == 0; d /= 10)
      ++decimals;
    char buf[48];
    if (decimals == 0) decimals = 3;
    std::snprintf(buf, sizeof buf, "%.*f", decimals,
                  static_cast<double>(num) / static_cast<double>(e.scale.den));
    number = buf;
  }
  const char* unit = fw::regmap::unitSymbol(e.unit);
  return unit[0] != '\0' ? number + " " + unit : number;
}

// Resolves a name of the given kind or a hex number up to `max`.
std::optional<uint32_t> resolve(std::span<const EntryInfo> table, Kind kind, const std::string& text,
                                uint32_t max, const EntryInfo** entry) {
  *entry = nullptr;
  if (!text.empty() && std::isdigit(static_cast<unsigned char>(text[0]))) {
    auto v = bmsctl::parseNumber(text, max, true);
    if (v) *entry = fw::regmap::findByAddress(table, kind, *v);
    return v;
  }
  *entry = bmsctl::findNamed(table, kind, text);
  if (*entry == nullptr) return std::nullopt;
  return (*entry)->address;
}

// Prints "# Name = value" for every entry of `kind` lying inside [start, start + bytes.size()).
void decodeRange(std::span<const EntryInfo> table, Kind kind, uint32_t start,
                 std::span<const uint8_t> bytes) {
  bool any = false;
  for (const auto& e : table) {
    if (e.kind != kind || e.address < start || e.address + e.size > start + bytes.size() || e.size == 0)
      continue;
    std::printf("# %s = %s\n", e.name, formatValue(e, bytes.subspan(e.address - start, e.size)).c_str());
    any = true;
  }
  if (!any) {
    std::printf("# %s:%s\n", hex(start, kind == Kind::Command ? 2 : 4).c_str(),
                bmsctl::hexJoin(bytes, " ").c_str());
  }
}

// The application of the image that carries `model` (lp-mspm0g3507-bq76952 for the BQ76952, CAN out;
// lp-mspm0l1306-bq76907 for the BQ7690x, SLCAN out), from reset until its first complete scan.
template <class Board>
int appStart(Board& b) {
  b.bus.onRecord([](const bsp::host::I2cWireRecord& r) { std::printf("%s\n", r.text.c_str()); });
  if (!b.h.runUntil([&] { return b.sample().valid; }, fw::s(5))) {
    std::printf("# error: no complete scan within 5 s\n");
    return 1;
  }
  std::printf("# first complete scan at %.3f ms: %llu transactions, %llu us of bus time\n",
              static_cast<double>(b.h.nowUs()) / 1000.0,
              static_cast<unsigned long long>(b.bus.transactions()),
              static_cast<unsigned long long>(b.bus.busTimeUs()));
  return 0;
}

int run(const bmsctl::TraceRequest& req, Bq769xEmulator::Model model) {
  if (req.operation == "app-start") {
    if (auto err = bmsctl::checkFlags(req, {}); !err.empty()) return bmsctl::usageError(err);
    if (!req.args.empty()) return bmsctl::usageError("app-start takes no arguments");
    if (model == Bq769xEmulator::Model::Bq76952) return appStart(*bsp::host::makeG3507Bq76952Board());
    return appStart(*bsp::host::makeL1306Bq7690xBoard(model));
  }
  const bool family7690x = model != Bq769xEmulator::Model::Bq76952;
  const std::span<const EntryInfo> table =
      family7690x ? fw::regmap::bq7690x::entries : fw::regmap::bq769x2::entries;
  if (auto err = bmsctl::checkFlags(req, {"--crc", "--address", "--fault"}); !err.empty())
    return bmsctl::usageError(err);
  const bool crc = bmsctl::hasFlag(req, "--crc");
  uint8_t address = drv::kDefaultAddress;
  if (bmsctl::hasFlag(req, "--address")) {
    auto a = bmsctl::parseNumber(req.flags.at("--address"), 0x7F, true);
    if (!a) return bmsctl::usageError("--address needs a 7-bit address, e.g. --address=0x08");
    address = static_cast<uint8_t>(*a);
  }
  std::string fault;
  if (bmsctl::hasFlag(req, "--fault")) {
    fault = req.flags.at("--fault");
    const char* known[] = {"nack", "nack-always", "stretch", "crc", "checksum", "length", "stale", "reset"};
    bool ok = false;
    for (const char* k : known)
      ok = ok || fault == k;
    if (!ok)
      return bmsctl::usageError("unknown --fault '" + fault +
                                "' (nack, nack-always, stretch, crc, checksum, length, stale, reset)");
  }

  // Parse the operation completely before touching the bus.
  const std::string& op = req.operation;
  const auto& a = req.args;
  const EntryInfo* entry = nullptr;
  uint32_t target = 0;
  uint32_t length = 0;
  std::vector<uint8_t> bytes;
  auto needArgs = [&](size_t min, size_t max, const char* usage) -> bool {
    if (a.size() < min || a.size() > max) {
      bmsctl::usageError(op + " expects: " + usage);
      return false;
    }
    return true;
  };
  if (op == "read" || op == "write") {
    if (!needArgs(2, op == "read" ? 2 : 1 + drv::kMaxWriteData,
                  op == "read" ? "read <cmd> <len>" : "write <cmd> <bytes...>"))
      return 2;
    auto t = resolve(table, Kind::Command, a[0], 0x7F, &entry);
    if (!t) return bmsctl::usageError("unknown direct command '" + a[0] + "'");
    target = *t;
    if (op == "read") {
      auto n = bmsctl::parseNumber(a[1], drv::kMaxReadBytes);
      if (!n || *n == 0)
        return bmsctl::usageError("read length must be 1.." + std::to_string(drv::kMaxReadBytes));
      length = *n;
    } else {
      auto b = bmsctl::parseHexBytes({a.begin() + 1, a.end()});
      if (!b) return bmsctl::usageError("bytes must be hex, e.g. 82 F0");
      bytes = *b;
    }
  } else if (op == "subcmd" || op == "subcmd-read") {
    if (!needArgs(1, op == "subcmd" ? 1 : 2, op == "subcmd" ? "subcmd <code>" : "subcmd-read <code> [len]"))
      return 2;
    auto t = resolve(table, Kind::Subcommand, a[0], 0xFFFF, &entry);
    if (!t) return bmsctl::usageError("unknown subcommand '" + a[0] + "'");
    target = *t;
    if (op == "subcmd-read") {
      if (a.size() == 2) {
        auto n = bmsctl::parseNumber(a[1], drv::kBufferBytes);
        if (!n)
          return bmsctl::usageError("subcmd-read length must be 0.." + std::to_string(drv::kBufferBytes));
        length = *n;
      } else if (entry != nullptr && !entry->variable && entry->size <= drv::kBufferBytes) {
        length = entry->size;
      }
    }
  } else if (op == "dm-read" || op == "dm-write") {
    if (!needArgs(2, op == "dm-read" ? 2 : 1 + drv::kMaxWriteData,
                  op == "dm-read" ? "dm-read <addr> <len>" : "dm-write <addr> <bytes...>"))
      return 2;
    auto t = resolve(table, Kind::DataMemory, a[0], 0xFFFF, &entry);
    if (!t) return bmsctl::usageError("unknown data-memory address '" + a[0] + "'");
    target = *t;
    if (op == "dm-read") {
      auto n = bmsctl::parseNumber(a[1], drv::kBufferBytes);
      if (!n || *n == 0)
        return bmsctl::usageError("dm-read length must be 1.." + std::to_string(drv::kBufferBytes));
      length = *n;
    } else {
      auto b = bmsctl::parseHexBytes({a.begin() + 1, a.end()});
      if (!b) return bmsctl::usageError("bytes must be hex, e.g. 8C");
      bytes = *b;
    }
  } else {
    return bmsctl::usageError("unknown operation '" + op +
                              "' (read, write, subcmd, subcmd-read, dm-read, dm-write, app-start)");
  }

  // The simulated board: 400 kHz bus, the emulated device at 0x08, the driver on its own task.
  bsp::host::Harness h;
  bsp::host::SimI2cBus bus(h.clock, h.irq, {400000, fw::ms(20), fw::us(4)});
  Bq769xEmulator emu(h.clock, model);
  emu.setCrc(crc);
  bus.attach(drv::kDefaultAddress, emu);
  bus.onRecord([](const bsp::host::I2cWireRecord& r) { std::printf("%s\n", r.text.c_str()); });
  drv::MonitorConfig config;
  config.link.crc = crc;
  config.link.address = address;
  const drv::Variant& variant = model == Bq769xEmulator::Model::Bq76952   ? drv::kBq76952
                                : model == Bq769xEmulator::Model::Bq76907 ? drv::kBq76907
                                                                          : drv::kBq76905;
  drv::Monitor monitor(bus, h.clock, fw::drivers::DriverContext{h.sched, kTask, kBusEvent, kTimerEvent},
                       variant, config);
  Runner runner;
  runner.monitor = &monitor;
  h.sched.addTask(kTask, runner);

  if (fault == "nack") emu.nackNext(1);
  if (fault == "nack-always") emu.nackNext(1000);
  if (fault == "stretch") emu.stretchNext(fw::ms(30));
  if (fault == "crc") emu.corruptNextRead(1);
  if (fault == "checksum") emu.wrongChecksumNext();
  if (fault == "length") emu.wrongLengthNext(40);
  if (fault == "stale") emu.staleBufferNext();
  if (fault == "reset") emu.resetAfterBytes(3);

  drv::Link& link = monitor.link();
  Status started = Status::Ok;
  drv::SettingsBuffer dmWrite;  // a dm-write's one setting, packed as the monitor walks it
  if (op == "read") {
    started = link.startRead(static_cast<uint8_t>(target), static_cast<uint8_t>(length));
  } else if (op == "write") {
    started = link.startWrite(static_cast<uint8_t>(target), bytes);
  } else if (op == "subcmd") {
    // After RESET, SHUTDOWN or DEEPSLEEP the device does not echo: those end at their write.
    const bool gone = target == fw::regmap::bq769x2::sub::Reset.address ||
                      target == fw::regmap::bq769x2::sub::Shutdown.address ||
                      target == fw::regmap::bq769x2::sub::Deepsleep.address;
    started = link.startSubcommand(static_cast<uint16_t>(target), !gone);
  } else if (op == "subcmd-read" || op == "dm-read") {
    started = link.startSubcommandRead(static_cast<uint16_t>(target), static_cast<uint8_t>(length));
  } else {
    uint32_t value = 0;
    for (size_t i = 0; i < bytes.size(); ++i)
      value |= static_cast<uint32_t>(bytes[i]) << (8 * i);
    const drv::Setting setting{static_cast<uint16_t>(target), static_cast<uint8_t>(bytes.size()), value};
    // A data-memory value is 1..4 bytes; anything else is refused as the monitor refuses a malformed table.
    if (bytes.empty() || bytes.size() > 4) {
      started = Status::InvalidArgument;
    } else {
      dmWrite = drv::SettingsBuffer({&setting, 1});
      started = monitor.startConfigure(dmWrite);
    }
  }
  Status result = started;
  if (started == Status::Ok) {
    h.runUntil([&] { return runner.done; }, fw::s(2));
    result = !runner.done ? Status::Timeout : op == "dm-write" ? monitor.result() : link.result();
  }
  if (result != Status::Ok) {
    std::printf("# error: %s\n", fw::statusName(result));
    return 1;
  }

  const uint8_t* d = link.data();
  if (op == "read") {
    decodeRange(table, Kind::Command, target, {d, length});
  } else if (op == "write") {
    if (entry != nullptr && entry->address == target && entry->scalar && bytes.size() == entry->size) {
      std::printf("# %s <- %s\n", entry->name, formatValue(*entry, bytes).c_str());
    } else {
      std::printf("# %s <- %zu byte(s)\n", hex(target, 2).c_str(), bytes.size());
    }
  } else if (op == "subcmd") {
    std::printf("# %s (%s) sent\n", entry != nullptr ? entry->name : "subcommand", hex(target, 4).c_str());
  } else if (op == "subcmd-read") {
    const uint8_t n = link.reported();
    const char* name = entry != nullptr ? entry->name : "subcommand";
    if (entry != nullptr && entry->scalar && n >= entry->size) {
      std::printf("# %s = %s\n", name, formatValue(*entry, {d, entry->size}).c_str());
    } else {
      std::printf("# %s:%s\n", name, bmsctl::hexJoin({d, n}, " ").c_str());
    }
    std::printf("# length %u (%u data bytes), checksum ok\n", static_cast<unsigned>(n + 4),
                static_cast<unsigned>(n));
  } else if (op == "dm-read") {
    decodeRange(table, Kind::DataMemory, target, {d, length});
  } else {
    const std::string name = entry != nullptr ? entry->name : hex(target, 4);
    const bool scalar =
        entry != nullptr && entry->address == target && entry->scalar && bytes.size() == entry->size;
    const std::string value = scalar ? formatValue(*entry, bytes) : bmsctl::hexJoin(bytes);
    if (monitor.written() == 0) {
      std::printf("# %s already %s: CONFIG_UPDATE not entered\n", name.c_str(), value.c_str());
    } else {
      std::printf("# %s <- %s: written in CONFIG_UPDATE and read back\n", name.c_str(), value.c_str());
    }
  }
  return 0;
}

static_assert(fw::regmap::bq769x2::sub::Reset.address == fw::regmap::bq7690x::sub::Reset.address &&
              fw::regmap::bq769x2::sub::Shutdown.address == fw::regmap::bq7690x::sub::Shutdown.address &&
              fw::regmap::bq769x2::sub::Deepsleep.address == fw::regmap::bq7690x::sub::Deepsleep.address);

int runBq76952(const bmsctl::TraceRequest& r) {
  return run(r, Bq769xEmulator::Model::Bq76952);
}
int runBq76907(const bmsctl::TraceRequest& r) {
  return run(r, Bq769xEmulator::Model::Bq76907);
}
int runBq76905(const bmsctl::TraceRequest& r) {
  return run(r, Bq769xEmulator::Model::Bq76905);
}

// The operations and options run() accepts, for `bmsctl --help`.
constexpr const char* kUsage =
    "read <cmd> <len>             direct read of len bytes (across contiguous commands)\n"
    "write <cmd> <bytes...>       direct write\n"
    "subcmd <code>                command-only subcommand\n"
    "subcmd-read <code> [len]     subcommand read: echo poll, 0x61 length, 0x60 checksum\n"
    "dm-read <addr> <len>         data-memory read\n"
    "dm-write <addr> <bytes...>   data-memory write in CONFIG_UPDATE (skipped when the value is there)\n"
    "app-start                    the image's application from reset to its first complete scan\n"
    "<cmd>, <code>, <addr>: hex (0x14, 14) or register-map names (Cell1Voltage, FET_ENABLE); <len> decimal\n"
    "--crc                        device and driver use the per-byte I2C CRC (not with app-start)\n"
    "--address=<7-bit>            the address the driver uses (the device stays at 0x08)\n"
    "--fault=<kind>               one fault injected before the operation: nack, nack-always, stretch,\n"
    "                             crc, checksum, length, stale, reset";

const bmsctl::Registrar kBq76952{
    {"bq76952", "BQ76952 (BQ769x2) battery monitor on I2C, 16 cells", &runBq76952, kUsage}};
const bmsctl::Registrar kBq76907{
    {"bq76907", "BQ76907 (BQ7690x) battery monitor on I2C, 7 cells", &runBq76907, kUsage}};
const bmsctl::Registrar kBq76905{
    {"bq76905", "BQ76905 (BQ7690x) battery monitor on I2C, 5 cells", &runBq76905, kUsage}};

}  // namespace
