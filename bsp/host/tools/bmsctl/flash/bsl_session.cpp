#include "flash/bsl_session.hpp"

#include <cstdio>
#include <thread>

namespace bmsctl::flash {

namespace {

constexpr int kAttempts = 3;
constexpr uint64_t kSlackMicros = 250000;  // USB serial latency and host scheduling on top of the wire time
constexpr size_t kReplyWireBytes = 40;     // the longest reply bmsctl asks for (device info, 32 bytes)
// Worst cases from the MSPM0L110x data sheet (SLASEX5C 7.7, "Flash memory characteristics"; the same NVM on
// the L130x and G350x): 275 us per 64-bit word, 200 ms per sector erase at 10k cycles.
constexpr uint64_t kWordProgramMicros = 275, kSectorEraseMicros = 200000;
// The CRC of a verification window: at least one CPU cycle per byte at 32 MHz; 1 us per byte covers a
// byte-wise software loop too.
constexpr uint64_t kVerifyMicrosPerByte = 1;

std::string hex32(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

}  // namespace

Clock::time_point BslSession::after(uint64_t bytesOnWire, uint64_t extraMicros) const {
  return Clock::now() +
         std::chrono::microseconds(bytesOnWire * port_.byteMicros() + extraMicros + kSlackMicros);
}

void BslSession::drainUntilQuiet(std::chrono::microseconds quiet, std::chrono::microseconds limit) {
  const auto end = Clock::now() + limit;
  while (Clock::now() < end) {
    if (port_.read(256, Clock::now() + quiet).empty()) return;
  }
}

void BslSession::resync(size_t filler) {
  // Whatever the BSL still sends, then bytes that complete a packet it may be collecting: 0xFF is never a
  // header, so once it is idle each one is answered 0x51 and nothing starts. The answers are discarded.
  const auto quiet = std::chrono::microseconds(20000 + 20 * port_.byteMicros());
  drainUntilQuiet(quiet, std::chrono::milliseconds(2000));
  if (bufferSize_ != 0) filler = std::min<size_t>(filler, bufferSize_);
  const std::vector<uint8_t> fill(filler, 0xFF);
  port_.write(fill);
  drainUntilQuiet(quiet,
                  std::chrono::milliseconds(2000) + std::chrono::microseconds(filler * port_.byteMicros()));
  port_.flushInput();
}

BslSession::ReadResult BslSession::readReply(Clock::time_point deadline, bsl::Reply& reply) {
  std::vector<uint8_t> bytes = port_.read(3, deadline);
  size_t needed = 3;
  bsl::ReplyStatus status = bsl::decodeReply(bytes, reply, needed);
  if (status == bsl::ReplyStatus::Incomplete && bytes.size() == 3) {
    const std::vector<uint8_t> rest = port_.read(needed - 3, deadline);
    bytes.insert(bytes.end(), rest.begin(), rest.end());
    status = bsl::decodeReply(bytes, reply, needed);
  }
  if (status == bsl::ReplyStatus::Complete) return ReadResult::Ok;
  return status == bsl::ReplyStatus::Incomplete ? ReadResult::Timeout : ReadResult::Corrupt;
}

Outcome BslSession::exchange(const Exchange& x, const std::vector<uint8_t>& packet, bsl::Reply* reply) {
  Outcome last{Outcome::Kind::NoAnswer, 0};
  std::string why;
  const int attempts = x.command == bsl::Command::UnlockBootloader ? 1 : kAttempts;
  for (int attempt = 1; attempt <= attempts; ++attempt) {
    if (attempt > 1) {
      ++resends_;
      warn_(why + " " + x.what + "; resynchronised and sent it again (attempt " + std::to_string(attempt) +
            " of " + std::to_string(kAttempts) + ")");
      resync(packet.size());
    }
    port_.flushInput();
    if (!port_.write(packet)) return {Outcome::Kind::NoAnswer, 0};
    const std::vector<uint8_t> ack = port_.read(1, after(packet.size() + 1, 0));
    if (ack.empty()) {
      last = {Outcome::Kind::NoAnswer, 0};
      why = "no acknowledgement for";
      continue;
    }
    if (ack[0] == bsl::kAckPacketTooBig || ack[0] == bsl::kAckUnknownBaudRate) {
      return {Outcome::Kind::Rejected, ack[0]};
    }
    if (ack[0] != bsl::kAck) {
      last = {Outcome::Kind::Rejected, ack[0]};
      why = "acknowledgement " + bsl::ackText(ack[0]) + " for";
      continue;
    }
    if (!x.wantsReply) return {Outcome::Kind::Ok, 0};
    bsl::Reply r;
    const ReadResult got = readReply(after(kReplyWireBytes, x.executionMicros), r);
    if (got == ReadResult::Ok) {
      if (r.rsp == bsl::kRspMessage && r.data.size() == 1) {
        if (r.data[0] != 0) return {Outcome::Kind::Message, r.data[0]};
        if (reply == nullptr) return {Outcome::Kind::Ok, 0};
      } else if (reply != nullptr && r.rsp != bsl::kRspMessage) {
        *reply = std::move(r);
        return {Outcome::Kind::Ok, 0};
      }
      why = "a reply of an unexpected kind (RSP " + std::to_string(r.rsp) + ") to";
    } else {
      why = got == ReadResult::Timeout ? "no complete reply to" : "a reply that failed its CRC check to";
    }
    last = {Outcome::Kind::ReplyLost, 0};
    if (!x.repeatable || attempts == 1) {
      warn_(why + " " + x.what);
      return last;
    }
  }
  return last;
}

bool BslSession::connect(Clock::time_point deadline, bool& already) {
  already = false;
  const std::vector<uint8_t> packet = bsl::connection();
  while (Clock::now() < deadline) {
    port_.flushInput();
    if (!port_.write(packet)) return false;
    const auto tryEnd = std::min(deadline, Clock::now() + std::chrono::milliseconds(400) +
                                               std::chrono::microseconds(packet.size() * port_.byteMicros()));
    const std::vector<uint8_t> ack = port_.read(1, tryEnd);
    if (ack.size() == 1 && ack[0] == bsl::kAck) {
      // A BSL already connected answers MSG 0x06 (invalid command) after the acknowledgement (observed on an
      // LP-MSPM0G3507: kalanzun/lenlab_mspm0 notes/protocol.md); a fresh one sends nothing more.
      bsl::Reply r;
      if (readReply(after(kReplyWireBytes, 0) - std::chrono::microseconds(kSlackMicros) +
                        std::chrono::milliseconds(60),
                    r) == ReadResult::Ok &&
          r.rsp == bsl::kRspMessage && r.data.size() == 1 && r.data[0] == 0x06) {
        already = true;
      }
      port_.flushInput();
      return true;
    }
    std::this_thread::sleep_until(tryEnd);
  }
  return false;
}

Outcome BslSession::deviceInfo(bsl::DeviceInfo& info) {
  bsl::Reply r;
  const Outcome o =
      exchange({bsl::Command::GetDeviceInfo, "Get Device Info", true, true, 0}, bsl::getDeviceInfo(), &r);
  if (!o.ok()) return o;
  const auto parsed = bsl::parseDeviceInfo(r);
  if (!parsed) return {Outcome::Kind::ReplyLost, 0};
  info = *parsed;
  return o;
}

Outcome BslSession::changeBaud(uint32_t baud) {
  const auto id = bsl::baudRateId(baud);
  if (!id) return {Outcome::Kind::Rejected, bsl::kAckUnknownBaudRate};
  const Outcome o = exchange({bsl::Command::ChangeBaudRate, "Change Baud Rate", false, true, 0},
                             bsl::changeBaudRate(*id), nullptr);
  if (!o.ok()) return o;
  // "The new baud rate will take effect after sending out the BSL acknowledgment" (SLAU887 4.3.12).
  port_.drainOutput();
  if (!port_.setBaud(baud)) return {Outcome::Kind::Rejected, bsl::kAckUnknownBaudRate};
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return o;
}

Outcome BslSession::unlock(const std::array<uint8_t, 32>& password) {
  return exchange({bsl::Command::UnlockBootloader, "Unlock Bootloader", true, false, 0},
                  bsl::unlock(password), nullptr);
}

Outcome BslSession::rangeErase(uint32_t first, uint32_t last) {
  const uint64_t sectors = (last - first) / 1024 + 1;
  return exchange({bsl::Command::FlashRangeErase, "Flash Range Erase " + hex32(first) + ".." + hex32(last),
                   true, true, sectors * kSectorEraseMicros},
                  bsl::flashRangeErase(first, last), nullptr);
}

Outcome BslSession::program(uint32_t address, std::span<const uint8_t> bytes) {
  return exchange({bsl::Command::ProgramData, "Program Data at " + hex32(address), true, false,
                   (bytes.size() / 8 + 1) * kWordProgramMicros},
                  bsl::programData(address, bytes), nullptr);
}

Outcome BslSession::verify(uint32_t address, uint32_t length, uint32_t& crc) {
  bsl::Reply r;
  const Outcome o =
      exchange({bsl::Command::StandaloneVerification,
                "Standalone Verification " + hex32(address) + ".." + hex32(address + length - 1), true, true,
                length * kVerifyMicrosPerByte},
               bsl::standaloneVerification(address, length), &r);
  if (!o.ok()) return o;
  if (r.rsp != bsl::kRspVerification || r.data.size() != 4) return {Outcome::Kind::ReplyLost, 0};
  crc = static_cast<uint32_t>(r.data[0]) | static_cast<uint32_t>(r.data[1]) << 8 |
        static_cast<uint32_t>(r.data[2]) << 16 | static_cast<uint32_t>(r.data[3]) << 24;
  return o;
}

Outcome BslSession::startApplication() {
  const Outcome o = exchange({bsl::Command::StartApplication, "Start Application", false, true, 0},
                             bsl::startApplication(), nullptr);
  port_.drainOutput();
  return o;
}

}  // namespace bmsctl::flash
