// BslSession: one conversation with the MSPM0 ROM bootloader over a serial port: each command sent as a
// packet, its acknowledgement and reply read against deadlines computed from the line rate, and the
// recovery a noisy line needs.
//
// Contract
// - Every wait is bounded: the acknowledgement must come within the packet's wire time + 250 ms, the reply
//   within the command's worst-case execution time (MSPM0 flash: 275 us per 64-bit word, 200 ms per sector,
//   MSPM0L110x data sheet SLASEX5C 7.7, the worst rows) + its wire time + 250 ms.
// - A packet the BSL did not take (no acknowledgement, or 0x51/0x52/0x53/0x55: SLAU887 4.2.1 "the host must
//   retry") is sent again, up to three times in all, after resynchronising: the line is read until it is
//   quiet, then filler bytes (0xFF, never a header) complete any packet the BSL is still collecting (it has
//   no receive timeout: mspm0-sdk secondary_bsl_uart/bsl_uart.c), and what comes back is discarded. Each
//   resend is reported through `warn`.
// - A reply that is late, cut short or fails its CRC is asked for again (the command repeated) only for
//   commands that may run twice (device info, erase, verification, start); for Program Data it ends the
//   call as Kind::ReplyLost: the caller cannot know whether the words were written.
// - 0x54 (packet too big) and 0x56 (unknown baud rate) are answers, not noise: they are returned at once.
// - Unlock is sent once, never repeated: a wrong password costs a 2 s lockout and the third one the
//   device's security alert (SLAU887 4.3.3).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "flash/bsl_packet.hpp"
#include "flash/serial_port.hpp"

namespace bmsctl::flash {

struct Outcome {
  enum class Kind : uint8_t {
    Ok,         // acknowledged, and the reply (if any) says success / carries the data
    NoAnswer,   // nothing came back, every attempt
    Rejected,   // an acknowledgement byte other than 0x00, every attempt (or 0x54/0x56 at once)
    ReplyLost,  // acknowledged, but its reply never came whole
    Message,    // the core answered with a message other than success (code)
  };
  Kind kind = Kind::Ok;
  uint8_t code = 0;  // the acknowledgement byte (Rejected) or the core message (Message)
  bool ok() const { return kind == Kind::Ok; }
};

class BslSession {
 public:
  using Warn = std::function<void(const std::string&)>;
  BslSession(SerialPort& port, Warn warn) : port_(port), warn_(std::move(warn)) {}

  // Sends Connection every 400 ms until the BSL acknowledges it or `deadline` passes. `already` is set when
  // the BSL said the session was open already (MSG 0x06 after the acknowledgement).
  bool connect(Clock::time_point deadline, bool& already);
  Outcome deviceInfo(bsl::DeviceInfo& info);
  // The BSL answers at the old rate and switches after its acknowledgement (SLAU887 4.3.12); so does the
  // port.
  Outcome changeBaud(uint32_t baud);
  Outcome unlock(const std::array<uint8_t, 32>& password);
  Outcome rangeErase(uint32_t first, uint32_t last);
  Outcome program(uint32_t address, std::span<const uint8_t> bytes);
  Outcome verify(uint32_t address, uint32_t length, uint32_t& crc);
  Outcome startApplication();

  // The largest packet the BSL takes, from its device info (0 until known): bounds the resync filler.
  void setBufferSize(uint16_t bytes) { bufferSize_ = bytes; }
  unsigned resends() const { return resends_; }

 private:
  struct Exchange {
    bsl::Command command;
    std::string what;  // "Program Data at 0x00000400", for messages
    bool wantsReply = false;
    bool repeatable = true;        // may run twice (everything but Program Data)
    uint64_t executionMicros = 0;  // the command's worst-case run time before its reply
  };
  Outcome exchange(const Exchange& x, const std::vector<uint8_t>& packet, bsl::Reply* reply);
  enum class ReadResult : uint8_t { Ok, Timeout, Corrupt };
  ReadResult readReply(Clock::time_point deadline, bsl::Reply& reply);
  void resync(size_t filler);
  void drainUntilQuiet(std::chrono::microseconds quiet, std::chrono::microseconds limit);
  Clock::time_point after(uint64_t bytesOnWire, uint64_t extraMicros) const;

  SerialPort& port_;
  Warn warn_;
  uint16_t bufferSize_ = 0;
  unsigned resends_ = 0;
};

}  // namespace bmsctl::flash
