#include "flash/bsl_packet.hpp"

#include <cstdio>

namespace bmsctl::bsl {

namespace {

void putLe32(std::vector<uint8_t>& out, uint32_t value) {
  for (int i = 0; i < 4; ++i)
    out.push_back(static_cast<uint8_t>(value >> (8 * i)));
}

uint32_t le32(std::span<const uint8_t> b, size_t at) {
  return static_cast<uint32_t>(b[at]) | static_cast<uint32_t>(b[at + 1]) << 8 |
         static_cast<uint32_t>(b[at + 2]) << 16 | static_cast<uint32_t>(b[at + 3]) << 24;
}

uint16_t le16(std::span<const uint8_t> b, size_t at) {
  return static_cast<uint16_t>(b[at] | b[at + 1] << 8);
}

std::string hex2(uint8_t v) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02X", v);
  return buf;
}

}  // namespace

uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc) {
  // Bit by bit, LSB first, as SLAU887 4.2.2.3 and TI's host code describe it; no final XOR.
  for (uint8_t b : bytes) {
    crc ^= b;
    for (int bit = 0; bit < 8; ++bit)
      crc = (crc & 1U) ? (crc >> 1) ^ 0xEDB88320U : crc >> 1;
  }
  return crc;
}

const char* commandName(Command command) {
  switch (command) {
    case Command::Connection:
      return "Connection";
    case Command::GetDeviceInfo:
      return "Get Device Info";
    case Command::ProgramData:
      return "Program Data";
    case Command::UnlockBootloader:
      return "Unlock Bootloader";
    case Command::FlashRangeErase:
      return "Flash Range Erase";
    case Command::ProgramDataFast:
      return "Program Data Fast";
    case Command::StandaloneVerification:
      return "Standalone Verification";
    case Command::MemoryReadBack:
      return "Memory Read Back";
    case Command::MassErase:
      return "Mass Erase";
    case Command::StartApplication:
      return "Start Application";
    case Command::ChangeBaudRate:
      return "Change Baud Rate";
  }
  return "command";
}

std::string ackText(uint8_t ack) {
  const char* what = nullptr;
  switch (ack) {
    case kAck:
      what = "packet accepted";
      break;
    case kAckHeaderIncorrect:
      what = "header incorrect";
      break;
    case kAckChecksumIncorrect:
      what = "packet CRC incorrect";
      break;
    case kAckPacketSizeZero:
      what = "packet size zero";
      break;
    case kAckPacketTooBig:
      what = "packet larger than the BSL's buffer";
      break;
    case kAckUnknownError:
      what = "unknown error";
      break;
    case kAckUnknownBaudRate:
      what = "unknown baud rate";
      break;
    default:
      what = "not an acknowledgement byte";
      break;
  }
  return hex2(ack) + " (" + what + ")";
}

std::string messageText(uint8_t message) {
  const char* what = "not in SLAU887's message table";
  switch (static_cast<Message>(message)) {
    case Message::Success:
      what = "operation successful";
      break;
    case Message::Locked:
      what = "BSL locked";
      break;
    case Message::PasswordError:
      what = "BSL password error";
      break;
    case Message::MultiplePasswordError:
      what = "third wrong password, the security alert was taken";
      break;
    case Message::UnknownCommand:
      what = "unknown command";
      break;
    case Message::InvalidMemoryRange:
      what = "invalid memory range";
      break;
    case Message::InvalidCommand:
      what = "invalid command";
      break;
    case Message::FactoryResetDisabled:
      what = "factory reset disabled";
      break;
    case Message::FactoryResetPasswordError:
      what = "factory reset password error";
      break;
    case Message::ReadOutError:
      what = "memory read-out disabled";
      break;
    case Message::InvalidAlignment:
      what = "address or length not 8-byte aligned";
      break;
    case Message::InvalidVerificationLength:
      what = "verification length under 1 KiB";
      break;
  }
  // TI's secondary BSL (mspm0-sdk secondary_bsl_uart/bsl_ci.h) adds flash failure codes.
  if (message == 0xF1) what = "flash program failed";
  if (message == 0xF2) what = "mass erase failed";
  if (message == 0xF3) what = "flash erase failed";
  return "MSG " + hex2(message) + " (" + what + ")";
}

std::vector<uint8_t> packet(Command command, std::span<const uint8_t> data) {
  const size_t length = 1 + data.size();
  std::vector<uint8_t> out;
  out.reserve(length + 7);
  out.push_back(0x80);
  out.push_back(static_cast<uint8_t>(length));
  out.push_back(static_cast<uint8_t>(length >> 8));
  out.push_back(static_cast<uint8_t>(command));
  out.insert(out.end(), data.begin(), data.end());
  putLe32(out, crc32(std::span<const uint8_t>(out).subspan(3)));
  return out;
}

std::vector<uint8_t> connection() {
  return packet(Command::Connection);
}
std::vector<uint8_t> getDeviceInfo() {
  return packet(Command::GetDeviceInfo);
}
std::vector<uint8_t> unlock(const std::array<uint8_t, 32>& password) {
  return packet(Command::UnlockBootloader, password);
}
std::vector<uint8_t> changeBaudRate(uint8_t id) {
  const uint8_t data[] = {id};
  return packet(Command::ChangeBaudRate, data);
}
std::vector<uint8_t> massErase() {
  return packet(Command::MassErase);
}
std::vector<uint8_t> flashRangeErase(uint32_t first, uint32_t last) {
  std::vector<uint8_t> data;
  putLe32(data, first);
  putLe32(data, last);
  return packet(Command::FlashRangeErase, data);
}
std::vector<uint8_t> programData(uint32_t address, std::span<const uint8_t> bytes) {
  std::vector<uint8_t> data;
  putLe32(data, address);
  data.insert(data.end(), bytes.begin(), bytes.end());
  return packet(Command::ProgramData, data);
}
std::vector<uint8_t> standaloneVerification(uint32_t address, uint32_t length) {
  std::vector<uint8_t> data;
  putLe32(data, address);
  putLe32(data, length);
  return packet(Command::StandaloneVerification, data);
}
std::vector<uint8_t> startApplication() {
  return packet(Command::StartApplication);
}

std::optional<uint8_t> baudRateId(uint32_t baud) {
  constexpr uint32_t kRates[] = {4800, 9600, 19200, 38400, 57600, 115200, 1000000, 2000000, 3000000};
  for (uint8_t i = 0; i < sizeof kRates / sizeof kRates[0]; ++i) {
    if (kRates[i] == baud) return static_cast<uint8_t>(i + 1);
  }
  return std::nullopt;
}

ReplyStatus decodeReply(std::span<const uint8_t> bytes, Reply& reply, size_t& needed) {
  needed = 3;
  if (!bytes.empty() && bytes[0] != kReplyHeader) return ReplyStatus::BadHeader;
  if (bytes.size() < 3) return ReplyStatus::Incomplete;
  const size_t length = le16(bytes, 1);
  if (length == 0) return ReplyStatus::BadLength;
  needed = 3 + length + 4;
  if (bytes.size() < needed) return ReplyStatus::Incomplete;
  const auto core = bytes.subspan(3, length);
  if (crc32(core) != le32(bytes, 3 + length)) return ReplyStatus::BadCrc;
  reply.rsp = core[0];
  reply.data.assign(core.begin() + 1, core.end());
  return ReplyStatus::Complete;
}

std::optional<DeviceInfo> parseDeviceInfo(const Reply& reply) {
  const auto& d = reply.data;
  if (reply.rsp != kRspDeviceInfo || d.size() < 12) return std::nullopt;  // up to the buffer size at least
  DeviceInfo info;
  info.commandInterpreterVersion = le16(d, 0);
  info.buildId = le16(d, 2);
  info.applicationVersion = le32(d, 4);
  info.pluginVersion = le16(d, 8);
  info.bufferSize = le16(d, 10);
  if (d.size() >= 16) info.bufferStart = le32(d, 12);
  if (d.size() >= 24) {
    info.bcrConfigId = le32(d, 16);
    info.bslConfigId = le32(d, 20);
    info.complete = true;
  }
  return info;
}

}  // namespace bmsctl::bsl
