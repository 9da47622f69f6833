// SerialTx / SerialRx: the two directions of an asynchronous byte stream (the L1306's UART0 back-channel:
// SLCAN text out, SLCAN commands in).
//
// SerialTx contract: write(bytes, done) starts sending and returns Ok, Busy (a write is running) or
// InvalidArgument (empty). `done` is called from ISR context when the last byte has left the shift register.
// The buffer must stay valid until then. Never blocks.
// SerialRx contract: bytes are received in the background (ISR) into a buffer of the BSP's; read(byte) takes
// the oldest (false when none; task context, one reader). onReceive(notify) registers the Notify called from
// ISR context when bytes have arrived. A byte that arrives with the buffer full, or with a framing or overrun
// error on the line, is dropped and counted in lost(): the reader sees a gap, never a corrupted byte as good.
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

class SerialRx {
 public:
  bool read(uint8_t& byte) { return doRead(byte); }
  void onReceive(const Notify& notify) { doOnReceive(notify); }
  uint32_t lost() const { return doLost(); }

 protected:
  ~SerialRx() = default;

 private:
  virtual bool doRead(uint8_t& byte) = 0;
  virtual void doOnReceive(const Notify& notify) = 0;
  virtual uint32_t doLost() const = 0;
};

// Both directions of one line (a UART that sends and receives).
class SerialPort : public SerialTx, public SerialRx {
 protected:
  ~SerialPort() = default;
};

}  // namespace fw::hal
