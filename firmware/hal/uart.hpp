// Uart: an asynchronous half-duplex command/response UART (BQ79616 daisy-chain base link), with pings.
//
// An exchange sends `tx` (may be empty) and then receives into `rx` (may be empty). The receiver is armed
// before the first byte is sent, so a reply that starts during transmission is never lost.
//
// Contract
// - start(exchange, done) returns Ok (started), Busy, or InvalidArgument (both spans empty).
// - The exchange ends, and `done` is called from ISR context exactly once, when one of these happens:
//     rx is full                                        -> status Ok
//     no byte arrived within `firstByteTimeout` of the end of transmission -> NoResponse (received 0)
//     the line stayed idle for `gapTimeout` after a byte -> Truncated (received < rx.size())
//     a framing/parity/overrun error                    -> CommFault (bytes so far kept)
//   `received` counts the bytes stored in rx. No wait is unbounded.
// - ping(low, done) stops the UART, drives TX low for `low` (accurate to a few microseconds), restores the
//   UART and then calls `done`. Returns Ok, Busy or InvalidArgument (zero duration).
// - abort() stops a running exchange or ping without calling `done` (used by recovery); afterwards the UART
//   is idle and the receiver is drained.
// - Buffers must stay valid until `done` runs or abort() returns.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/status.hpp"
#include "core/time.hpp"
#include "hal/notify.hpp"

namespace fw::hal {

struct UartExchange {
  std::span<const uint8_t> tx = {};
  std::span<uint8_t> rx = {};
  Duration firstByteTimeout = ms(2);
  Duration gapTimeout = us(100);
  // Results, written by the UART before `done` runs.
  Status status = Status::Aborted;
  size_t received = 0;
};

class Uart {
 public:
  Status start(UartExchange& exchange, Notify done) { return doStart(exchange, done); }
  Status ping(Duration low, Notify done) { return doPing(low, done); }
  void abort() { doAbort(); }
  uint32_t baudRate() const { return doBaudRate(); }

 protected:
  ~Uart() = default;

 private:
  virtual Status doStart(UartExchange& exchange, Notify done) = 0;
  virtual Status doPing(Duration low, Notify done) = 0;
  virtual void doAbort() = 0;
  virtual uint32_t doBaudRate() const = 0;
};

}  // namespace fw::hal
