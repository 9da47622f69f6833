#include "flash/invoke_app.hpp"

#include <chrono>
#include <cstdio>
#include <thread>

namespace bmsctl::flash {

namespace {

constexpr uint16_t kIdentify = 0x603, kEnterBootloader = 0x606;
constexpr uint16_t kCommandAck = 0x580, kIdentifyVersion = 0x581, kIdentifyChip = 0x582;
constexpr uint8_t kKey = 0xA5;

const char* const kResults[] = {"accepted",      "bad_crc",      "repeated_counter", "wrong_length",
                                "out_of_range",  "inconsistent", "unsupported",      "wrong_key",
                                "paths_not_off", "busy"};

uint32_t le32(const std::vector<uint8_t>& d, size_t at) {
  return static_cast<uint32_t>(d[at]) | static_cast<uint32_t>(d[at + 1]) << 8 |
         static_cast<uint32_t>(d[at + 2]) << 16 | static_cast<uint32_t>(d[at + 3]) << 24;
}

CanLine command(uint16_t id, std::vector<uint8_t> data) {
  std::vector<uint8_t> covered = {static_cast<uint8_t>(id), static_cast<uint8_t>(id >> 8)};
  covered.insert(covered.end(), data.begin() + 1, data.end());
  data[0] = crc8J1850(covered);
  return {id, std::move(data)};
}

// Reads lines until one satisfies `want` or the deadline passes.
template <class Want>
std::optional<CanLine> awaitLine(SerialPort& port, std::string& pending, Clock::time_point deadline,
                                 Want want) {
  while (Clock::now() < deadline) {
    const std::vector<uint8_t> got =
        port.read(64, std::min(deadline, Clock::now() + std::chrono::milliseconds(20)));
    pending.append(got.begin(), got.end());
    for (size_t eol; (eol = pending.find('\r')) != std::string::npos;) {
      const std::string line = pending.substr(0, eol);
      pending.erase(0, eol + 1);
      const auto frame = parseSlcanLine(line);
      if (frame && want(*frame)) return frame;
    }
  }
  return std::nullopt;
}

}  // namespace

uint8_t crc8J1850(std::span<const uint8_t> bytes) {
  uint8_t crc = 0xFF;
  for (uint8_t b : bytes) {
    crc ^= b;
    for (int bit = 0; bit < 8; ++bit)
      crc = static_cast<uint8_t>((crc & 0x80) ? (crc << 1) ^ 0x1D : crc << 1);
  }
  return static_cast<uint8_t>(crc ^ 0xFF);
}

std::string slcanLine(const CanLine& frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "t%03X%zu", frame.id & 0x7FFU, frame.data.size());
  std::string line = buf;
  for (uint8_t b : frame.data) {
    std::snprintf(buf, sizeof buf, "%02X", b);
    line += buf;
  }
  return line + "\r";
}

std::optional<CanLine> parseSlcanLine(const std::string& line) {
  auto hex = [&](size_t at, size_t n, uint32_t& out) {
    if (at + n > line.size()) return false;
    out = 0;
    for (size_t i = at; i < at + n; ++i) {
      const char c = line[i];
      const int v = c >= '0' && c <= '9'   ? c - '0'
                    : c >= 'A' && c <= 'F' ? c - 'A' + 10
                    : c >= 'a' && c <= 'f' ? c - 'a' + 10
                                           : -1;
      if (v < 0) return false;
      out = out << 4 | static_cast<uint32_t>(v);
    }
    return true;
  };
  uint32_t id = 0, dlc = 0;
  if (line.empty() || line[0] != 't' || !hex(1, 3, id) || !hex(4, 1, dlc) || dlc > 8) return std::nullopt;
  if (line.size() != 5 + 2 * dlc) return std::nullopt;
  CanLine f{static_cast<uint16_t>(id), {}};
  for (uint32_t i = 0; i < dlc; ++i) {
    uint32_t b = 0;
    hex(5 + 2 * i, 2, b);
    f.data.push_back(static_cast<uint8_t>(b));
  }
  return f;
}

CanLine identifyFrame(uint8_t node, uint8_t counter) {
  return command(kIdentify, {0, static_cast<uint8_t>(counter & 0xF), node});
}

CanLine enterBootloaderFrame(uint8_t node, uint8_t counter, uint32_t traceId) {
  return command(kEnterBootloader,
                 {0, static_cast<uint8_t>(counter & 0xF), node, static_cast<uint8_t>(traceId),
                  static_cast<uint8_t>(traceId >> 8), static_cast<uint8_t>(traceId >> 16),
                  static_cast<uint8_t>(traceId >> 24), kKey});
}

InvokeResult invokeApplication(SerialPort& port, bool adapter, uint8_t node,
                               std::optional<bool> imageChipIsG3507) {
  auto send = [&](const std::string& text) {
    port.write(std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
  };
  if (adapter) send("C\rS6\rO\r");  // Lawicel: close, 500 kbit/s, open
  std::string pending;
  port.flushInput();
  uint8_t counter = static_cast<uint8_t>(std::chrono::steady_clock::now().time_since_epoch().count() & 0xF);
  InvokeResult result;

  send(slcanLine(identifyFrame(node, counter)));
  const auto deadline = Clock::now() + std::chrono::seconds(1);
  std::optional<CanLine> version, chip;
  awaitLine(port, pending, deadline, [&](const CanLine& f) {
    if (f.data.size() == 8 && f.data[0] == node && f.id == kIdentifyVersion) version = f;
    if (f.data.size() == 8 && f.data[0] == node && f.id == kIdentifyChip) chip = f;
    return version && chip;
  });
  if (!chip) {
    result.text = "no IdentifyChip answer from node " + std::to_string(node) + " on " + port.path() +
                  " within 1 s (is the image running and its command link connected?)";
    if (adapter) send("C\r");
    return result;
  }
  if (version) {
    result.runningImage = version->data[7];
    if (imageChipIsG3507 && result.runningImage >= 1 && result.runningImage <= 5 &&
        (result.runningImage >= 3) != *imageChipIsG3507) {
      result.kind = InvokeResult::Kind::WrongImage;
      result.text = "node " + std::to_string(node) + " runs image " + std::to_string(result.runningImage) +
                    " (bms.yaml IdentifyVersion.Image), built for the other part than the file";
      if (adapter) send("C\r");
      return result;
    }
  }
  const uint32_t traceId = le32(chip->data, 2);
  for (int attempt = 0; attempt < 2; ++attempt) {
    counter = static_cast<uint8_t>((counter + 1) & 0xF);
    send(slcanLine(enterBootloaderFrame(node, counter, traceId)));
    const auto ack = awaitLine(port, pending, Clock::now() + std::chrono::seconds(3), [&](const CanLine& f) {
      return f.id == kCommandAck && f.data.size() >= 5 && f.data[0] == node &&
             (f.data[1] | f.data[2] << 8) == kEnterBootloader && (f.data[3] & 0xF) == counter;
    });
    if (!ack) {
      result.text = "no CommandAck for EnterBootloader from node " + std::to_string(node) + " within 3 s";
      break;
    }
    const uint8_t r = ack->data[4];
    if (r == 0) {
      result.kind = InvokeResult::Kind::Entered;
      break;
    }
    result.kind = InvokeResult::Kind::Refused;
    result.text = std::string("node ") + std::to_string(node) + " refused EnterBootloader: " +
                  (r < sizeof kResults / sizeof kResults[0] ? kResults[r] : "result " + std::to_string(r));
    if (r != 2) break;  // repeated_counter: once more with the next counter
  }
  if (adapter) send("C\r");
  // TI's host MCU example waits about 0.6 s after the software-invoke request before it connects
  // (mspm0-sdk bsl_host_mcu_to_mspm0g1x0x_g3x0x_target_uart main.c: 20 000 000 cycles at 32 MHz).
  if (result.kind == InvokeResult::Kind::Entered) std::this_thread::sleep_for(std::chrono::milliseconds(600));
  return result;
}

}  // namespace bmsctl::flash
