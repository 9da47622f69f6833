// I2cBus: an asynchronous I2C / SMBus controller that runs a list of transactions back to back.
//
// A transaction is: START, address+W, the `write` bytes, then (if `read` is not empty) a repeated START,
// address+R and the `read` bytes, then STOP. With `write` empty it is a plain read; with `read` empty a plain
// write. With `pec` set the controller appends the SMBus PEC (CRC-8 over every byte on the wire including
// the address bytes) to a write-only transaction, or reads one extra byte after `read` and checks it.
// With `blockRead` set the read is an SMBus block read: its first byte is a count N and the controller reads
// exactly N more bytes (then the PEC when `pec` is set); N must fit in `read` after the count byte.
//
// Contract
// - start(list, done) starts the transactions in order and returns Ok, or returns without starting anything:
//   Busy (a list is already running) or InvalidArgument (empty list, empty transaction, too long).
// - The list runs without task involvement (ISR/DMA). It stops at the first transaction that fails; that
//   transaction's status says why and every later one is left as Status::Aborted. Then `done` is called from
//   ISR context, exactly once. Every transaction's `status` and `readCount` are final before `done` runs.
// - Per-transaction statuses: Ok; Nack (address not acknowledged); DataNack (a written byte refused);
//   Timeout (SCL held low longer than the bus's stretch limit, or the transaction exceeded its time bound;
//   the bus has already been recovered when this is reported); ArbitrationLost; BusStuck (recovery failed);
//   Pec (only with pec set: the read PEC did not match); Length (only with blockRead: the count byte was 0 or
//   larger than the buffer; the controller NACKed it and stopped, and readCount is 1).
// - No wait is unbounded: every transaction ends within its wire time plus the configured stretch limit.
// - The transaction list and all buffers must stay valid and untouched until `done` runs.
// - recover() clocks SCL up to 9 times until SDA is released, then sends STOP (for use when a device is
//   believed to hold the bus). Returns Ok or BusStuck. Only when idle.
#pragma once

#include <cstdint>
#include <span>

#include "core/status.hpp"
#include "hal/notify.hpp"

namespace fw::hal {

struct I2cTransaction {
  uint8_t address = 0;                  // 7-bit target address
  std::span<const uint8_t> write = {};  // bytes after address+W (may be empty)
  std::span<uint8_t> read = {};         // bytes to read after address+R (may be empty)
  bool pec = false;                     // SMBus PEC appended (write-only) or checked (read)
  bool blockRead = false;               // SMBus block read: read[0] counts the bytes that follow
  // Results, written by the bus before `done` runs.
  Status status = Status::Aborted;
  uint8_t readCount = 0;  // bytes actually received into `read`
};

class I2cBus {
 public:
  Status start(std::span<I2cTransaction> list, const Notify& done) { return doStart(list, done); }
  Status recover() { return doRecover(); }
  // Bus clock in Hz (100 000 or 400 000), for timing figures.
  uint32_t bitRate() const { return doBitRate(); }

 protected:
  ~I2cBus() = default;

 private:
  virtual Status doStart(std::span<I2cTransaction> list, const Notify& done) = 0;
  virtual Status doRecover() = 0;
  virtual uint32_t doBitRate() const = 0;
};

}  // namespace fw::hal
