// bmsctl trace bq79616: one operation through the real BQ79616 chain driver against the chain emulator, with
// the exact UART traffic (README "Host tools"):
//
//   bmsctl trace bq79616 [--devices N] wake
//   bmsctl trace bq79616 [--devices N] autoaddress
//   bmsctl trace bq79616 [--devices N] read single <dev> <reg> <len>
//   bmsctl trace bq79616 [--devices N] read stack|broadcast <reg> <len>
//   bmsctl trace bq79616 [--devices N] write single <dev> <reg> <byte>...
//   bmsctl trace bq79616 [--devices N] write stack|broadcast|reverse <reg> <byte>...
//   bmsctl trace bq79616 [--devices N] app-start
//
// <reg> is a register address in hex (0x0309, or 309) or a generated register-map name (Control1, CONTROL1,
// vcell16_hi, Vcell16); <dev> and <len> are decimal; bytes are hex (20, 0x20). --devices defaults to 2 (TI's
// example). Output: the wire lines (TX/RX/PING), then '#' lines decoding the result. `wake` starts from a
// chain in SHUTDOWN; `autoaddress` wakes the chain first without tracing; read and write bring the chain up
// (wake, auto-address, configure) without tracing, then trace only the requested frame. `app-start` runs the
// lp-mspm0g3507-bq79616 application itself (firmware/app/monitors/bq79616_app.hpp, as the image composes it
// with N devices) from reset until its first complete scan and traces everything it sends and receives, with
// "# at <ms>" lines where the line was quiet for a millisecond or more.
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "bmsctl/cli.hpp"
#include "bq79616/board.hpp"
#include "bq79616/chain_emulator.hpp"
#include "core/status.hpp"
#include "drivers/bq79616/chain.hpp"
#include "drivers/bq79616/frame.hpp"
#include "regmap/bq79616_table.hpp"
#include "sim/harness.hpp"
#include "sim/uart.hpp"

namespace {

namespace bq = fw::drivers::bq79616;
using fw::Status;

constexpr fw::sched::TaskId kTask = 1;
constexpr fw::sched::EventMask kBus = 0x1;
constexpr fw::sched::EventMask kTimer = 0x2;

class DriverTask final : public fw::sched::Task {
 public:
  bq::Chain* chain = nullptr;
  int done = 0;
  void run(fw::sched::EventMask events) override {
    if (chain != nullptr && (events & chain->events()) != 0 &&
        chain->onEvent(events) == fw::drivers::Progress::Done)
      ++done;
  }
};

struct Rig {
  explicit Rig(uint8_t devices)
      : emulator(harness.clock, uart, devices),
        chain(uart, harness.clock, fw::drivers::DriverContext{harness.sched, kTask, kBus, kTimer},
              bq::ChainConfig{.devices = devices}) {
    task.chain = &chain;
    harness.sched.addTask(kTask, task);
  }
  // Runs one started operation to its end; every operation is bounded well inside 10 s of virtual time.
  Status finish(Status started) {
    if (started != Status::Ok) return started;
    const int before = task.done;
    if (!harness.runUntil([&] { return task.done > before; }, fw::s(10))) return Status::Timeout;
    return chain.result();
  }

  bsp::host::Harness harness;
  bsp::host::SimUart uart{harness.clock, harness.irq};
  bsp::host::Bq79616ChainEmulator emulator;
  DriverTask task;
  bq::Chain chain;
};

std::optional<uint16_t> parseRegister(const std::string& text) {
  const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
  if (!hex) {
    if (const auto* e = fw::regmap::findByName(fw::regmap::bq79616::entries, text)) {
      if (e->kind == fw::regmap::Kind::Register || e->kind == fw::regmap::Kind::Value)
        return static_cast<uint16_t>(e->address);
    }
  }
  if (auto v = bmsctl::parseNumber(text, 0xFFFF, true)) return static_cast<uint16_t>(*v);
  return std::nullopt;
}

// The entry that starts at `address`, preferring a multi-byte value that fits in `left` bytes.
const fw::regmap::EntryInfo* entryAt(uint32_t address, size_t left) {
  using fw::regmap::Kind;
  const auto* v = fw::regmap::findByAddress(fw::regmap::bq79616::entries, Kind::Value, address);
  if (v != nullptr && v->address == address && v->size <= left) return v;
  const auto* r = fw::regmap::findByAddress(fw::regmap::bq79616::entries, Kind::Register, address);
  return r != nullptr && r->address == address ? r : nullptr;
}

void printValue(uint8_t device, const fw::regmap::EntryInfo* e, std::span<const uint8_t> bytes,
                uint32_t address) {
  if (e == nullptr) {
    std::printf("# dev %u 0x%04X = 0x%02X\n", device, address, bytes[0]);
    return;
  }
  const auto raw = fw::regmap::decodeRaw(*e, bytes);
  const unsigned hexWidth = 2 * e->size;
  const auto unsignedRaw = static_cast<unsigned>(static_cast<uint64_t>(raw) & ((1ULL << (8 * e->size)) - 1));
  std::printf("# dev %u %s = 0x%0*X", device, e->name, static_cast<int>(hexWidth), unsignedRaw);
  if (e->size == 2 && e->isSigned && raw == -32768) {
    std::printf(" = not converted\n");
    return;
  }
  const double scaled = static_cast<double>(raw) * e->scale.num / e->scale.den;
  if (e->unit == fw::regmap::Unit::MicroVolt) {
    std::printf(" = %.1f mV", scaled / 1000.0);
  } else if (e->unit != fw::regmap::Unit::None) {
    std::printf(" = %.2f %s", scaled, fw::regmap::unitSymbol(e->unit));
  }
  std::printf("\n");
}

int decodeFrames(std::span<const uint8_t> rx, uint16_t reg, size_t count, size_t frames) {
  for (size_t i = 0; i < frames; ++i) {
    bq::ResponseFrame f;
    const size_t at = i * bq::responseSize(count);
    const Status s = at <= rx.size() ? bq::parseResponse(rx.subspan(at), reg, count, f) : Status::Truncated;
    if (s != Status::Ok) {
      std::printf("# frame %zu: %s\n", i, fw::statusName(s));
      return 1;
    }
    for (size_t o = 0; o < count;) {
      const auto* e = entryAt(reg + o, count - o);
      const size_t n = e != nullptr ? e->size : 1;
      printValue(f.device, e, f.data.subspan(o, n), static_cast<uint32_t>(reg + o));
      o += n;
    }
  }
  return 0;
}

void printWire(const Rig& rig) {
  for (const auto& line : rig.uart.wireLog())
    std::printf("%s\n", line.c_str());
}

double msSince(const Rig& rig, uint64_t startUs) {
  return static_cast<double>(rig.harness.nowUs() - startUs) / 1000.0;
}

// The application from reset to its first complete scan: every wire line, a "# at" line before each line that
// follows a millisecond or more of quiet, then the outcome.
int appStart(uint8_t devices) {
  bsp::host::Bq79616Board b(devices);
  uint64_t last = 0;
  b.uart.onRecord([&](const std::string& line) {
    if (b.h.nowUs() >= last + 1000) std::printf("# at %.1f ms\n", static_cast<double>(b.h.nowUs()) / 1000.0);
    last = b.h.nowUs();
    std::printf("%s\n", line.c_str());
  });
  const bool scanned = b.h.runUntil([&] { return b.app.monitor().stats().scans >= 1; }, fw::s(10));
  b.uart.onRecord({});
  if (!scanned) {
    std::printf("# app-start: no complete scan within 10 s\n");
    return 1;
  }
  uint16_t valid = 0;
  for (const auto& board : b.app.pack().boards)
    valid = static_cast<uint16_t>(valid + (board.last == Status::Ok ? 1 : 0));
  std::printf(
      "# app-start: first complete scan at %.1f ms, %u of %u devices valid, %u command frames, "
      "%llu response bytes\n",
      static_cast<double>(b.h.nowUs()) / 1000.0, valid, devices,
      b.app.monitor().chain().stats().commandFrames, static_cast<unsigned long long>(b.uart.rxBytes()));
  return valid == devices ? 0 : 1;
}

std::optional<bq::RequestType> parseKind(const std::string& kind, bool write) {
  if (kind == "single") return write ? bq::RequestType::SingleWrite : bq::RequestType::SingleRead;
  if (kind == "stack") return write ? bq::RequestType::StackWrite : bq::RequestType::StackRead;
  if (kind == "broadcast") return write ? bq::RequestType::BroadcastWrite : bq::RequestType::BroadcastRead;
  if (kind == "reverse" && write) return bq::RequestType::BroadcastWriteReverse;
  return std::nullopt;
}

int run(const bmsctl::TraceRequest& request) {
  if (auto bad = bmsctl::checkFlags(request, {"--devices"}); !bad.empty()) return bmsctl::usageError(bad);
  uint8_t devices = 2;
  if (bmsctl::hasFlag(request, "--devices")) {
    const auto n = bmsctl::parseNumber(request.flags.at("--devices"), bq::kMaxDevices);
    if (!n || *n == 0) return bmsctl::usageError("--devices needs a number from 1 to 64");
    devices = static_cast<uint8_t>(*n);
  }
  const auto& op = request.operation;
  const auto& a = request.args;
  const bool isRead = op == "read";
  const bool isWrite = op == "write";

  // Validate everything before touching the (emulated) bus.
  std::optional<bq::RequestType> type;
  uint8_t device = 0;
  uint16_t reg = 0;
  size_t count = 0;
  std::vector<uint8_t> data;
  if (isRead || isWrite) {
    if (a.empty())
      return bmsctl::usageError(op + " needs single|stack|broadcast" + (isWrite ? "|reverse" : ""));
    type = parseKind(a[0], isWrite);
    if (!type) return bmsctl::usageError("unknown " + op + " kind '" + a[0] + "'");
    size_t i = 1;
    if (bq::hasDeviceId(*type)) {
      if (a.size() < 2) return bmsctl::usageError(op + " single needs a device address");
      const auto d = bmsctl::parseNumber(a[1], bq::kMaxAddress);
      if (!d) return bmsctl::usageError("device address must be 0..63, got '" + a[1] + "'");
      device = static_cast<uint8_t>(*d);
      i = 2;
    }
    if (a.size() <= i) return bmsctl::usageError(op + " needs a register");
    const auto r = parseRegister(a[i]);
    if (!r) return bmsctl::usageError("unknown register '" + a[i] + "' (hex address or register name)");
    reg = *r;
    ++i;
    if (isRead) {
      if (a.size() != i + 1) return bmsctl::usageError("read needs exactly one length after the register");
      const auto n = bmsctl::parseNumber(a[i], bq::kMaxReadBytes);
      if (!n || *n == 0) return bmsctl::usageError("read length must be 1..128, got '" + a[i] + "'");
      count = *n;
    } else {
      const std::vector<std::string> words(a.begin() + static_cast<std::ptrdiff_t>(i), a.end());
      const auto bytes = bmsctl::parseHexBytes(words);
      if (!bytes || bytes->empty() || bytes->size() > bq::kMaxWriteBytes)
        return bmsctl::usageError("write needs 1..8 hex data bytes");
      data = *bytes;
    }
    if (*type == bq::RequestType::StackRead && devices < 2)
      return bmsctl::usageError("a stack read needs --devices 2 or more");
  } else if (op != "wake" && op != "autoaddress" && op != "app-start") {
    return bmsctl::usageError(
        "unknown bq79616 operation '" + op +
        "' (wake, autoaddress, read single|stack|broadcast, write single|stack|broadcast, app-start)");
  } else if (!a.empty()) {
    return bmsctl::usageError(op + " takes no arguments");
  }
  if (op == "app-start") return appStart(devices);

  Rig rig(devices);
  if (op == "wake") {
    const Status s = rig.finish(rig.chain.startWake());
    printWire(rig);
    std::printf("# wake: %s after %.1f ms (%u devices configured)\n", fw::statusName(s), msSince(rig, 0),
                devices);
    return s == Status::Ok ? 0 : 1;
  }
  if (op == "autoaddress") {
    Status s = rig.finish(rig.chain.startWake());
    if (s != Status::Ok) {
      std::fprintf(stderr, "bmsctl: error: wake failed: %s\n", fw::statusName(s));
      return 1;
    }
    rig.uart.clearWireLog();
    const uint64_t start = rig.harness.nowUs();
    s = rig.finish(rig.chain.startAutoAddress());
    printWire(rig);
    std::printf("# autoaddress: %s after %.1f ms, %u of %u devices answered", fw::statusName(s),
                msSince(rig, start), rig.chain.discovered(), devices);
    if (rig.chain.devices() > 0) std::printf(", addresses 0..%u read back", rig.chain.devices() - 1U);
    std::printf("\n");
    if (s != Status::Ok) {
      const auto f = rig.chain.lastFault();
      std::printf("# fault: device %u %s\n", f.device, fw::statusName(f.status));
    }
    return s == Status::Ok ? 0 : 1;
  }

  const Status up = rig.finish(rig.chain.startBringUp());
  if (up != Status::Ok) {
    std::fprintf(stderr, "bmsctl: error: bring-up of %u devices failed: %s\n", devices, fw::statusName(up));
    return 1;
  }
  rig.uart.clearWireLog();
  if (isWrite) {
    const Status s = rig.finish(rig.chain.startWrite(*type, device, reg, data));
    printWire(rig);
    std::printf("# write: %s\n", fw::statusName(s));
    return s == Status::Ok ? 0 : 1;
  }
  std::vector<uint8_t> rx(bq::kMaxDevices * bq::responseSize(bq::kMaxReadBytes));
  const Status s = rig.finish(rig.chain.startRead(*type, device, reg, static_cast<uint8_t>(count), rx));
  printWire(rig);
  const size_t frames = *type == bq::RequestType::SingleRead  ? 1
                        : *type == bq::RequestType::StackRead ? devices - 1U
                                                              : devices;
  const int bad = decodeFrames({rx.data(), rig.chain.received()}, reg, count, frames);
  std::printf("# read: %s, %zu of %zu frames\n", fw::statusName(s),
              rig.chain.received() / bq::responseSize(count), frames);
  return s == Status::Ok && bad == 0 ? 0 : 1;
}

const bmsctl::Registrar kRegistrar{
    {"bq79616", "BQ79616 daisy chain on UART, 1 Mbaud", &run,
     "wake                                  WAKE pings from SHUTDOWN\n"
     "autoaddress                           wake, then TI's auto-addressing\n"
     "read single <dev> <reg> <len>         after bring-up, one read frame and its response\n"
     "read stack|broadcast <reg> <len>\n"
     "write single <dev> <reg> <bytes...>\n"
     "write stack|broadcast|reverse <reg> <bytes...>\n"
     "app-start                             the image's application from reset to its first complete scan\n"
     "<reg>: hex (0x0309) or a register-map name (Control1); <dev>, <len> decimal; bytes hex\n"
     "--devices N                           chain length, 1..64 (default 2)"}};

}  // namespace
