// SerialTx: an asynchronous byte-stream transmitter (the L1306's UART0 back-channel, used for SLCAN text).
//
// Contract: write(bytes, done) starts sending and returns Ok, Busy (a write is running) or InvalidArgument
// (empty). `done` is called from ISR context when the last byte has left the shift register. The buffer must
// stay valid until then. Never blocks.
#pragma once

#include <cstdint>
#include <span>

#include "core/status.hpp"
#include "hal/notify.hpp"

namespace fw::hal {

class SerialTx {
 public:
  Status write(std::span<const uint8_t> bytes, const Notify& done) { return doWrite(bytes, done); }

 protected:
  ~SerialTx() = default;

 private:
  virtual Status doWrite(std::span<const uint8_t> bytes, const Notify& done) = 0;
};

}  // namespace fw::hal
