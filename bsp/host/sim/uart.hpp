// SimUart: the host's command/response UART (implements fw::hal::Uart) wired to an emulated peer (the
// BQ79616 chain emulator).
//
// Timing: 8N1, so a byte occupies 10 bit times (10 us at 1 Mbaud). Host bytes leave back to back; the peer
// learns of them when the last stop bit has left (onHostBytes). The peer answers with peerSend(), whose bytes
// arrive back to back from the given start time (or as soon as the line is free). A ping holds TX low for the
// requested time and the peer is told its length when the line is released (onPing).
// Bytes that arrive while no exchange is armed, or beyond the armed buffer, are counted as unsolicited and
// dropped, as a real UART would overrun.
//
// Noise (noise().setPpm, bms-sim's uart-noise): bit errors on both directions of the line, as BitNoise says;
// a byte that loses its frame arrives as a framing error.
//
// Wire log, in the contract format of `bmsctl trace`: "TX 90 00 03 09 20 13 95", "RX ...",
// "PING WAKE 2250us" (the name comes from the peer's classification of the low time).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "hal/uart.hpp"
#include "sim/bit_noise.hpp"
#include "sim/sim_clock.hpp"

namespace bsp::host {

class SimIrq;

class UartPeer {
 public:
  virtual ~UartPeer() = default;
  virtual void onHostBytes(std::span<const uint8_t> bytes, uint64_t endUs) = 0;
  virtual std::string onPing(fw::Duration low, uint64_t endUs) = 0;
};

class SimUart final : public fw::hal::Uart {
 public:
  SimUart(SimClock& clock, SimIrq& irq, uint32_t baud = 1000000);

  void attach(UartPeer& peer) { peer_ = &peer; }

  // Peer side: transmit `bytes` towards the host starting no earlier than `startUs`.
  void peerSend(std::span<const uint8_t> bytes, uint64_t startUs);
  // Peer side: a framing error on the next byte slot at or after `atUs`.
  void peerFramingError(uint64_t atUs);

  uint64_t byteTimeUs() const { return 10000000ULL / baud_; }
  // Bit errors on the line, both directions (the MSPM0 twin applies the host-to-peer side itself).
  BitNoise& noise() { return noise_; }

  // Hands every byte the peer sends (at its arrival time) to `tap` instead of an exchange: the MSPM0 twin's
  // UART model receives them there (bsp/twin).
  void onPeerByte(std::function<void(uint8_t byte, bool framingError)> tap) { tap_ = std::move(tap); }

  const std::vector<std::string>& wireLog() const { return log_; }
  void clearWireLog() { log_.clear(); }
  void onRecord(std::function<void(const std::string&)> sink) { sink_ = std::move(sink); }

  uint64_t txBytes() const { return txBytes_; }
  uint64_t rxBytes() const { return rxBytes_; }
  uint64_t unsolicitedBytes() const { return unsolicited_; }
  bool busy() const { return busy_; }

 private:
  fw::Status doStart(fw::hal::UartExchange& exchange, fw::hal::Notify done) override;
  fw::Status doPing(fw::Duration low, fw::hal::Notify done) override;
  void doAbort() override;
  uint32_t doBaudRate() const override { return baud_; }

  void arrive(uint8_t byte, bool framingError);
  void txComplete();
  void armTimeout(uint64_t atUs, fw::Status status);
  void complete(fw::Status status);
  void logRx();
  void emit(std::string line);

  SimClock& clock_;
  SimIrq& irq_;
  uint32_t baud_;
  int line_;
  UartPeer* peer_ = nullptr;

  fw::hal::UartExchange* exchange_ = nullptr;
  fw::hal::Notify done_;
  bool busy_ = false;
  bool txDone_ = false;
  SimClock::EventId timeout_ = 0;
  SimClock::EventId txEvent_ = 0;
  uint64_t lineFreeUs_ = 0;  // peer -> host line busy until
  std::vector<uint8_t> rxLogged_;
  std::vector<std::string> log_;
  std::function<void(const std::string&)> sink_;
  std::function<void(uint8_t, bool)> tap_;
  BitNoise noise_;
  uint64_t txBytes_ = 0;
  uint64_t rxBytes_ = 0;
  uint64_t unsolicited_ = 0;
};

}  // namespace bsp::host
