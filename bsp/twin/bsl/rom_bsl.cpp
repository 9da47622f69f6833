#include "bsl/rom_bsl.hpp"

#include <algorithm>
#include <cstdio>

namespace twin {

namespace {

constexpr uint8_t kHeader = 0x80, kAnswerHeader = 0x08;
constexpr uint8_t kAck = 0x00, kHeaderIncorrect = 0x51, kChecksumIncorrect = 0x52, kSizeZero = 0x53;
constexpr uint8_t kTooBig = 0x54, kUnknownBaud = 0x56;
constexpr uint8_t kLocked = 0x01, kPasswordError = 0x02, kMultiplePasswordError = 0x03,
                  kUnknownCommand = 0x04;
constexpr uint8_t kInvalidRange = 0x05, kInvalidCommand = 0x06, kReadOutError = 0x09, kAlignment = 0x0A;
constexpr uint8_t kVerifyLength = 0x0B, kProgramFailed = 0xF1;
constexpr uint32_t kNonmainBegin = 0x41C00000, kNonmainEnd = 0x41C00400;
constexpr uint32_t kSector = 1024;
constexpr uint64_t kSessionTimeoutUs = 10000000, kPasswordPenaltyUs = 2000000;
constexpr uint64_t kWordProgramUs = 50, kSectorEraseUs = 4000, kMassEraseUs = 22000, kCrcCyclesPerByte = 8;
constexpr uint32_t kRates[] = {4800, 9600, 19200, 38400, 57600, 115200, 1000000, 2000000, 3000000};
constexpr uint32_t kSysctlResetLevel = 0x400B0300, kSysctlResetCmd = 0x400B0304;

uint32_t le32(const std::vector<uint8_t>& d, size_t at) {
  return static_cast<uint32_t>(d[at]) | static_cast<uint32_t>(d[at + 1]) << 8 |
         static_cast<uint32_t>(d[at + 2]) << 16 | static_cast<uint32_t>(d[at + 3]) << 24;
}
void put32(std::vector<uint8_t>& d, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    d.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
std::string hex(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}
std::string msgText(uint8_t m) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "MSG 0x%02X", m);
  return buf;
}
bool isProtected(uint8_t command) {
  return command == 0x20 || command == 0x24 || command == 0x29 || command == 0x23 || command == 0x15 ||
         command == 0x30 || command == 0x26;
}
const char* name(uint8_t command) {
  switch (command) {
    case 0x12:
      return "Connection";
    case 0x19:
      return "Get Device Info";
    case 0x20:
      return "Program Data";
    case 0x21:
      return "Unlock";
    case 0x23:
      return "Flash Range Erase";
    case 0x24:
      return "Program Data Fast";
    case 0x26:
      return "Standalone Verification";
    case 0x29:
      return "Memory Read Back";
    case 0x15:
      return "Mass Erase";
    case 0x30:
      return "Factory Reset";
    case 0x40:
      return "Start Application";
    case 0x52:
      return "Change Baud Rate";
    default:
      return "unknown command";
  }
}

}  // namespace

uint32_t bslCrc32(const uint8_t* data, size_t size) {
  uint32_t crc = 0xFFFFFFFF;
  for (size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit)
      crc = (crc >> 1) ^ (0xEDB88320U & (0U - (crc & 1U)));
  }
  return crc;
}

RomBsl::Config RomBsl::factoryConfig(bool g3507) {
  Config c;
  c.mainFlashSize = g3507 ? 128 * 1024 : 64 * 1024;
  c.sramBase = g3507 ? 0x20200000 : 0x20000000;
  c.sramSize = g3507 ? 32 * 1024 : 4 * 1024;
  c.bufferSize = g3507 ? 0x3EC0 : 0x06C0;
  c.password.fill(0xFF);
  return c;
}

RomBsl::RomBsl(Machine& machine, const Config& config)
    : machine_(machine),
      config_(config),
      txDone_(machine.timeline(),
              [this] {
                auto [byte, then] = std::move(tx_.front());
                tx_.pop_front();
                if (sink_) sink_(byte, baud_);
                if (then) then();
                sendNext();
              }),
      execute_(machine.timeline(), [this] {
        auto action = std::move(executeAction_);
        executeAction_ = nullptr;
        if (action) action();
      }) {}

void RomBsl::start(const std::string& reason) {
  stop();
  running_ = true;
  startedAt_ = machine_.now();
  note(0, -1, "started: " + reason);
}

void RomBsl::stop() {
  running_ = connected_ = unlocked_ = standby_ = false;
  baud_ = 9600;
  wrongPasswords_ = 0;
  deafUntil_ = lastCommandAt_ = 0;
  rx_ = Rx::Idle;
  packet_.clear();
  tx_.clear();
  txDone_.cancel();
  execute_.cancel();
  executeAction_ = nullptr;
}

uint64_t RomBsl::byteCycles() const {
  return 10ULL * machine_.clockHz() / baud_;
}

void RomBsl::note(uint8_t command, int result, std::string text) {
  records_.push_back({machine_.now(), command, result, std::move(text)});
  if (observer_) observer_(records_.back());
}

void RomBsl::send(std::vector<uint8_t> bytes, std::function<void()> then) {
  for (size_t i = 0; i < bytes.size(); ++i)
    tx_.emplace_back(bytes[i], i + 1 == bytes.size() ? std::move(then) : nullptr);
  if (!txDone_.armed()) sendNext();
}

void RomBsl::sendNext() {
  if (!tx_.empty() && !txDone_.armed()) txDone_.after(byteCycles());
}

void RomBsl::receive(uint8_t byte, uint32_t hostBaud) {
  if (!running_ || standby_) return;
  if (hostBaud != baud_) {
    ++lost_;
    return;
  }
  const uint64_t now = machine_.now();
  if (!connected_ && now - startedAt_ > micros(kSessionTimeoutUs)) {
    standby_ = true;
    note(0, -1, "no Connection within 10 s of the start: STANDBY until the next reset");
    return;
  }
  if (now < deafUntil_) return;
  switch (rx_) {
    case Rx::Blocked:
      return;  // a command is executing or answering: the byte is dropped
    case Rx::Idle:
      if (byte != kHeader) {
        packetError(kHeaderIncorrect);
        return;
      }
      packet_.assign(1, byte);
      rx_ = Rx::Header;
      return;
    case Rx::Header: {
      packet_.push_back(byte);
      if (packet_.size() < 3) return;
      const size_t length = packet_[1] | packet_[2] << 8;
      if (length == 0) {
        packetError(kSizeZero);
      } else if (length + 7 > config_.bufferSize) {
        packetError(kTooBig);
      } else {
        expected_ = 3 + length + 4;
        rx_ = Rx::Body;
      }
      return;
    }
    case Rx::Body:
      packet_.push_back(byte);
      if (packet_.size() == expected_) packetDone();
      return;
  }
}

void RomBsl::packetError(uint8_t ack) {
  rx_ = Rx::Idle;
  if (!connected_) return;  // not yet connected: no answer to anything but Connection
  char text[48];
  std::snprintf(text, sizeof text, "packet error: 0x%02X", ack);
  send({ack});
  note(0, ack, text);
}

void RomBsl::packetDone() {
  const uint16_t length = static_cast<uint16_t>(packet_[1] | packet_[2] << 8);
  const uint32_t crc = bslCrc32(packet_.data() + 3, length);
  if (crc != le32(packet_, 3 + length)) {
    packetError(kChecksumIncorrect);
    return;
  }
  const uint8_t command = packet_[3];
  const std::vector<uint8_t> data(packet_.begin() + 4, packet_.begin() + 3 + length);
  const uint64_t now = machine_.now();
  if (!connected_) {
    rx_ = Rx::Idle;
    if (command != 0x12) return;
    connected_ = true;
    connectedAt_ = lastCommandAt_ = now;
    rx_ = Rx::Blocked;
    send({kAck}, [this] {
      rx_ = Rx::Idle;
      note(0x12, -1, "Connection: ACK");
    });
    return;
  }
  if (unlocked_ && now - lastCommandAt_ > micros(kSessionTimeoutUs)) {
    unlocked_ = false;
    note(0, -1, "locked again: 10 s without a command");
  }
  lastCommandAt_ = now;
  if (command == 0x52) {  // handled by the interface layer: ACK at the old rate, then the new one
    const uint8_t id = data.size() == 1 ? data[0] : 0;
    if (id < 1 || id > 9) {
      packetError(kUnknownBaud);
      return;
    }
    rx_ = Rx::Blocked;
    const uint32_t rate = kRates[id - 1];
    send({kAck}, [this, rate] {
      baud_ = rate;
      rx_ = Rx::Idle;
      note(0x52, -1, "Change Baud Rate: ACK, now " + std::to_string(rate) + " Bd");
    });
    return;
  }
  if (command == 0x24) {  // non-blocking: the next packet may arrive while it executes
    rx_ = Rx::Idle;
    send({kAck});
    uint64_t cycles = 0;
    const uint8_t result =
        unlocked_ ? (data.size() < 4 ? kInvalidRange
                                     : program(le32(data, 0), {data.begin() + 4, data.end()}, cycles))
                  : kLocked;
    note(0x24, result, std::string("Program Data Fast: ") + msgText(result) + " (no answer)");
    return;
  }
  rx_ = Rx::Blocked;
  send({kAck}, [this, command, data, length] { interpret(command, data, length); });
}

void RomBsl::answer(uint8_t rsp, const std::vector<uint8_t>& data, uint64_t executionCycles,
                    std::string text) {
  std::vector<uint8_t> reply = {kAnswerHeader, static_cast<uint8_t>(data.size() + 1),
                                static_cast<uint8_t>((data.size() + 1) >> 8), rsp};
  reply.insert(reply.end(), data.begin(), data.end());
  uint32_t crc = bslCrc32(reply.data() + 3, data.size() + 1);
  if (corruptAnswer_ != 0 && --corruptAnswer_ == 0) {
    crc ^= 0x00010000;  // fault injection: one bit of the CRC flipped on the line
    text += " (CRC corrupted by the test)";
  }
  put32(reply, crc);
  const uint8_t command = packet_.size() > 3 ? packet_[3] : 0;
  const int result = rsp == 0x3B ? data[0] : -1;
  executeAction_ = [this, reply = std::move(reply), command, result, text = std::move(text)]() mutable {
    send(std::move(reply), [this, command, result, text = std::move(text)] {
      rx_ = Rx::Idle;
      note(command, result, text);
      if (command == 0x21 && result != 0) {
        // A wrong password: 2 s deaf, and the rate back to 9600 Bd (SLAU887 4.3.3, 4.3.12).
        deafUntil_ = machine_.now() + micros(kPasswordPenaltyUs);
        baud_ = 9600;
      }
    });
  };
  execute_.after(executionCycles);
}

uint8_t RomBsl::program(uint32_t address, const std::vector<uint8_t>& bytes, uint64_t& cycles) {
  const uint64_t end = static_cast<uint64_t>(address) + bytes.size();
  if (address >= config_.sramBase && end <= static_cast<uint64_t>(config_.sramBase) + config_.sramSize) {
    for (size_t i = 0; i < bytes.size(); ++i)
      machine_.busWrite(address + static_cast<uint32_t>(i), 1, bytes[i]);
    return 0;
  }
  if (address % 8 != 0 || bytes.size() % 8 != 0) return kAlignment;
  if (address < kNonmainEnd && end > kNonmainBegin) {
    machine_.stop("BSL: Program Data into NONMAIN at " + hex(address) +
                  ": it rewrites the boot configuration, a flasher must never do it");
    return kInvalidRange;
  }
  if (end > config_.mainFlashSize) return kInvalidRange;
  std::vector<uint8_t>& flash = machine_.flash();
  for (size_t w = 0; w < bytes.size(); w += 8) {
    const auto word = flash.begin() + static_cast<long>(address + w);
    if (std::any_of(word, word + 8, [](uint8_t b) { return b != 0xFF; })) return kProgramFailed;
    std::copy(bytes.begin() + static_cast<long>(w), bytes.begin() + static_cast<long>(w + 8), word);
    cycles += micros(kWordProgramUs);
  }
  machine_.flashReprogrammed();
  return 0;
}

void RomBsl::interpret(uint8_t command, const std::vector<uint8_t>& data, uint16_t length) {
  const std::string what = name(command);
  auto needs = [&](size_t bytes) {
    if (data.size() >= bytes) return true;
    machine_.stop("BSL: " + what + " with " + std::to_string(data.size()) +
                  " data bytes; SLAU887 does not say what the ROM does with it");
    return false;
  };
  if (isProtected(command) && !unlocked_) {
    message(kLocked, 0, what + ": " + msgText(kLocked) + " (locked)");
    return;
  }
  switch (command) {
    case 0x12:
      message(kInvalidCommand, 0, "Connection again: " + msgText(kInvalidCommand));
      return;
    case 0x19: {
      std::vector<uint8_t> d = {0x00, 0x01, 0x00, 0x01};  // interpreter and build versions 0x0100
      put32(d, 0);                                        // application version: none configured
      d.insert(d.end(), {0x01, 0x00, static_cast<uint8_t>(config_.bufferSize),
                         static_cast<uint8_t>(config_.bufferSize >> 8)});
      put32(d, 0x20000160);
      put32(d, 1);
      put32(d, 1);
      answer(0x31, d, 0, "Get Device Info");
      return;
    }
    case 0x21: {
      const bool right = length == 0x21 && data.size() == 32 &&
                         std::equal(data.begin(), data.end(), config_.password.begin());
      if (right) {
        unlocked_ = true;
        message(0, 0, "Unlock: " + msgText(0));
        return;
      }
      unlocked_ = false;
      const uint8_t m = ++wrongPasswords_ >= 3 ? kMultiplePasswordError : kPasswordError;
      message(m, 0, "Unlock: " + msgText(m) + " (wrong password " + std::to_string(wrongPasswords_) + ")");
      return;
    }
    case 0x20: {
      if (!needs(4)) return;
      uint64_t cycles = 0;
      const uint32_t address = le32(data, 0);
      const std::vector<uint8_t> bytes(data.begin() + 4, data.end());
      const uint8_t m = program(address, bytes, cycles);
      if (machine_.stopped()) return;
      message(m, cycles,
              what + " " + hex(address) + " " + std::to_string(bytes.size()) + " B: " + msgText(m));
      return;
    }
    case 0x23: {
      if (!needs(8)) return;
      const uint32_t first = le32(data, 0), last = le32(data, 4);
      if (first > last || last >= config_.mainFlashSize) {
        message(kInvalidRange, 0, what + " " + hex(first) + ".." + hex(last) + ": " + msgText(kInvalidRange));
        return;
      }
      std::vector<uint8_t>& flash = machine_.flash();
      const uint32_t begin = first / kSector * kSector, end = (last / kSector + 1) * kSector;
      std::fill(flash.begin() + begin, flash.begin() + end, 0xFF);
      message(0, (end - begin) / kSector * micros(kSectorEraseUs),
              what + " " + hex(begin) + ".." + hex(end - 1) + ": " + msgText(0));
      return;
    }
    case 0x15:
      std::fill(machine_.flash().begin(), machine_.flash().begin() + config_.mainFlashSize, 0xFF);
      message(0, micros(kMassEraseUs), what + ": " + msgText(0));
      return;
    case 0x29:
      message(kReadOutError, 0, what + ": " + msgText(kReadOutError) + " (read-out disabled)");
      return;
    case 0x30:
      machine_.stop("BSL: Factory Reset received: it erases NONMAIN too; a flasher must never send it");
      return;
    case 0x26: {
      if (!needs(8)) return;
      const uint32_t address = le32(data, 0), size = le32(data, 4);
      const uint64_t end = static_cast<uint64_t>(address) + size;
      const std::string range = what + " " + hex(address) + " +" + std::to_string(size);
      if (size < 1024) {
        message(kVerifyLength, 0, range + ": " + msgText(kVerifyLength));
        return;
      }
      std::vector<uint8_t> bytes;
      if (end <= config_.mainFlashSize) {
        bytes.assign(machine_.flash().begin() + address, machine_.flash().begin() + static_cast<long>(end));
      } else if (address >= config_.sramBase &&
                 end <= static_cast<uint64_t>(config_.sramBase) + config_.sramSize) {
        for (uint32_t a = address; a < end; ++a) {
          uint32_t v = 0;
          machine_.busRead(a, 1, v);
          bytes.push_back(static_cast<uint8_t>(v));
        }
      } else if (address < kNonmainEnd && end > kNonmainBegin) {
        machine_.stop("BSL: Standalone Verification of NONMAIN, which the twin does not hold");
        return;
      } else {
        message(kInvalidRange, 0, range + ": " + msgText(kInvalidRange));
        return;
      }
      std::vector<uint8_t> d;
      const uint32_t crc = bslCrc32(bytes.data(), bytes.size());
      put32(d, crc);
      answer(0x32, d, kCrcCyclesPerByte * size, range + ": CRC " + hex(crc));
      return;
    }
    case 0x40:
      note(0x40, -1, "Start Application: ACK, reset with bootloader exit");
      // What the BSL does (mspm0-sdk bsl_ci.c CMD_API_startApplication): RESETLEVEL 4, RESETCMD KEY | GO.
      machine_.busWrite(kSysctlResetLevel, 4, 4);
      machine_.busWrite(kSysctlResetCmd, 4, 0xE4000001);
      return;
    default:
      message(kUnknownCommand, 0, what + " " + std::to_string(command) + ": " + msgText(kUnknownCommand));
      return;
  }
}

}  // namespace twin
