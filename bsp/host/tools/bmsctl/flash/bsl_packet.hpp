// The MSPM0 ROM bootstrap loader's (BSL) UART packets, host side: building command packets and decoding the
// BSL's acknowledgement bytes and core replies. TI SLAU887 ("MSPM0 Bootloader User's Guide") chapter 4; the
// byte vectors of SLAU887 4.3 are checked in tests/tools/bsl_packet_test.cpp.
//
//   host -> BSL: 0x80 | length (2 bytes LE) | CMD | data | CRC32 (4 bytes LE)      (SLAU887 4.1)
//   BSL -> host: one acknowledgement byte (0x00 = packet accepted, 0x51..0x56 = why not; SLAU887 4.2.1), and
//                for commands with a reply: 0x08 | length (LE) | RSP | data | CRC32 (LE)
// `length` counts CMD/RSP and data; the CRC covers the same bytes. Addresses and lengths inside data are
// 32-bit little endian. The CRC is CRC-32 with the reflected polynomial 0xEDB88320, initial value 0xFFFFFFFF
// and no final XOR (SLAU887 4.2.2.3; TI's host code in mspm0-sdk tools/bsl/BSL_GUI_source_code BSL_pack.py
// computes the same): CRC-32/JAMCRC, the bitwise NOT of zlib's crc32, check value 0x340BC6D9 over
// "123456789".
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace bmsctl::bsl {

uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc = 0xFFFFFFFF);

// Command codes (SLAU887 4.3; the same in mspm0-sdk secondary_bsl_uart/bsl_ci.h).
enum class Command : uint8_t {
  Connection = 0x12,
  GetDeviceInfo = 0x19,
  ProgramData = 0x20,
  UnlockBootloader = 0x21,
  FlashRangeErase = 0x23,
  ProgramDataFast = 0x24,
  StandaloneVerification = 0x26,
  MemoryReadBack = 0x29,
  MassErase = 0x15,
  StartApplication = 0x40,
  ChangeBaudRate = 0x52,
};
const char* commandName(Command command);

// Acknowledgement bytes (SLAU887 4.2.1; 0x56 from mspm0-sdk flashBSL_uart.h).
inline constexpr uint8_t kAck = 0x00;
inline constexpr uint8_t kAckHeaderIncorrect = 0x51, kAckChecksumIncorrect = 0x52, kAckPacketSizeZero = 0x53;
inline constexpr uint8_t kAckPacketTooBig = 0x54, kAckUnknownError = 0x55, kAckUnknownBaudRate = 0x56;
// What an acknowledgement byte means, e.g. "0x52 (packet CRC incorrect)".
std::string ackText(uint8_t ack);

// Core reply codes (SLAU887 4.4) and the core message values (SLAU887 4.4.1 table).
inline constexpr uint8_t kReplyHeader = 0x08;
inline constexpr uint8_t kRspMemoryReadBack = 0x30, kRspDeviceInfo = 0x31, kRspVerification = 0x32;
inline constexpr uint8_t kRspMessage = 0x3B;
enum class Message : uint8_t {
  Success = 0x00,
  Locked = 0x01,
  PasswordError = 0x02,
  MultiplePasswordError = 0x03,
  UnknownCommand = 0x04,
  InvalidMemoryRange = 0x05,
  InvalidCommand = 0x06,
  FactoryResetDisabled = 0x07,
  FactoryResetPasswordError = 0x08,
  ReadOutError = 0x09,
  InvalidAlignment = 0x0A,
  InvalidVerificationLength = 0x0B,
};
// e.g. "MSG 0x0A (address or length not 8-byte aligned)"; codes outside the table say so.
std::string messageText(uint8_t message);

// Packets. `packet` frames any command; the named builders are the commands bmsctl sends.
std::vector<uint8_t> packet(Command command, std::span<const uint8_t> data = {});
std::vector<uint8_t> connection();
std::vector<uint8_t> getDeviceInfo();
std::vector<uint8_t> unlock(const std::array<uint8_t, 32>& password);
std::vector<uint8_t> changeBaudRate(uint8_t id);
std::vector<uint8_t> massErase();
std::vector<uint8_t> flashRangeErase(uint32_t first, uint32_t last);  // both inclusive
std::vector<uint8_t> programData(uint32_t address, std::span<const uint8_t> bytes);
std::vector<uint8_t> standaloneVerification(uint32_t address, uint32_t length);
std::vector<uint8_t> startApplication();

// Change Baud Rate IDs (SLAU887 4.3.12): 1 = 4800 .. 9 = 3 000 000; nullopt for a rate the BSL has no ID for.
std::optional<uint8_t> baudRateId(uint32_t baud);

// A core reply as it arrived after the 0x00 acknowledgement.
struct Reply {
  uint8_t rsp = 0;
  std::vector<uint8_t> data;
};
enum class ReplyStatus : uint8_t { Complete, Incomplete, BadHeader, BadLength, BadCrc };
// Decodes `bytes` (starting with the 0x08 header): Complete with `reply` filled, Incomplete while more bytes
// are needed (`needed` says how many in all), or what is wrong with it.
ReplyStatus decodeReply(std::span<const uint8_t> bytes, Reply& reply, size_t& needed);

// Get Device Info reply data (SLAU887 4.4.4): 24 bytes; a shorter reply (a 13-byte core, up to the buffer
// size, is reported on TI's E2E forum, thread 1334673) leaves the fields it lacks at 0 and `complete` false;
// without the buffer size it is no device info.
struct DeviceInfo {
  uint16_t commandInterpreterVersion = 0;
  uint16_t buildId = 0;
  uint32_t applicationVersion = 0;
  uint16_t pluginVersion = 0;
  uint16_t bufferSize = 0;
  uint32_t bufferStart = 0;
  uint32_t bcrConfigId = 0;
  uint32_t bslConfigId = 0;
  bool complete = false;
};
std::optional<DeviceInfo> parseDeviceInfo(const Reply& reply);

}  // namespace bmsctl::bsl
