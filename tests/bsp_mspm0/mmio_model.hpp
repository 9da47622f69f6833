// RegisterModel: the host stand-in for MSPM0 peripheral registers (the idea of OpenTitan's mock_mmio,
// written for this project). The MSPM0 drivers are compiled with BSP_MSPM0_MMIO_MODEL=1, so every
// mmio::Reg::read()/write() and mmio::spin() lands here with the register's address.
//
// The twin (bsp/twin): the peripherals the twin models are answered by a twin chip, the same peripheral
// models that run the exact images (one copy of TI's facts). Each test gets a fresh chip (reset(part): a
// G3507 unless the test asks for an L1306) whose CPU sleeps in a WFI loop; chip() lets a test act on the
// world outside the chip (a pin driven low, a crystal missing) and advance() lets time pass, as spin() does
// (4 CPU cycles per iteration, mmio.hpp). Which peripherals are bridged: twinRanges() (mmio_model.cpp).
// DMA buffers: a driver gives the DMA a buffer's address (mmio::address(): the low 32 bits of the host
// pointer), the twin's DMA works on the twin's SRAM. dmaBuffer() gives a host buffer a place in that SRAM: a
// DMASA/DMADA write of an address inside it reaches the twin as the address of its SRAM copy (the log keeps
// the driver's value); the copy is refreshed from the host buffer at that write, and a writable buffer gets
// the SRAM copy back after every advance() (the DMA moves data only as time passes).
// A bridged access that the twin refuses (no such register), a rule of the twin's models that stops the run
// and a rule that warns (rules.hpp) are each flagged as a broken rule, with the twin's message.
//
// Behaviour
// - Every access is appended to log() in program order: reads with the value returned, writes with the value
//   written, spins with their iteration count.
// - A read returns, in order of preference: the next value queued for that address (queueRead, consumed
//   one per read), else, for a bridged address, the twin's register, else the value of the address's read
//   hook (onRead: a peripheral model computes it), else the address's current value. The current value is
//   the last value written or set() (0 if neither), so read-modify-write sequences behave as on plain
//   registers. Status registers are scripted with set() (held) or queueRead() (one-shot, e.g. a FIFO count
//   that drops as it is drained). On a bridged address queueRead() is only for what the twin never
//   produces (reserved bits read as 1), and set() is refused (flagged): the twin computes the status.
// - onWrite(address, hook) runs `hook(value)` after a write to that address is logged and stored (e.g. to
//   model a DMA-done flag appearing when a channel is enabled); several hooks run in the order added. Hooks
//   may call set()/queueRead().
// - A test's own peripheral model (for what the twin does not model) attaches hooks and reports a broken
//   documented rule with flag(rule), citing the TI source it enforces.
//   violations() lists them; the test fixture fails any test that leaves one (a test that provokes one on
//   purpose takes it with takeViolations()).
// - Addresses are whatever the driver computes from its configured base: tests use the tsv bases, so an
//   expected address reads like the datasheet (0x400F1214 is I2C0 MCTR).
// Not thread-safe; one model per process (instance()), reset by each test's fixture.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "mspm0.hpp"

namespace bsp::mspm0::test {

struct Access {
  enum class Kind : uint8_t { Read, Write, Spin };
  Kind kind;
  uintptr_t address;
  uint32_t value;
};

class RegisterModel {
 public:
  static RegisterModel& instance();

  // A fresh model and twin chip of `part`.
  void reset(twin::Part part = twin::Part::G3507);
  void set(uintptr_t address, uint32_t value);
  void queueRead(uintptr_t address, uint32_t value) { queued_[address].push_back(value); }
  void queueReads(uintptr_t address, std::initializer_list<uint32_t> values);
  void onWrite(uintptr_t address, std::function<void(uint32_t)> hook) {
    hooks_[address].push_back(std::move(hook));
  }
  void onRead(uintptr_t address, std::function<uint32_t()> hook) { readHooks_[address] = std::move(hook); }
  void flag(std::string rule) { violations_.push_back(std::move(rule)); }
  const std::vector<std::string>& violations() const { return violations_; }
  std::vector<std::string> takeViolations() { return std::exchange(violations_, {}); }
  // The last value written or set() (on a bridged address: written by the driver, not read from the twin).
  uint32_t value(uintptr_t address) const;

  // The twin chip behind the bridged addresses.
  twin::Mspm0& chip() { return *chip_; }
  // A bridged register as the twin reads it now, without a log entry (what a test checks after the driver).
  uint32_t peek(uintptr_t address) { return twinRead(address); }
  // True if `address` is answered by the twin.
  static bool bridged(uintptr_t address);
  // Lets `cycles` CPU cycles (32 MHz) pass on the twin: its peripherals' events fire in order.
  void advance(uint64_t cycles);
  void advanceUs(uint64_t us) { advance(us * 32); }
  // Advances 1 us at a time until `done()` (true) or `maxUs` have passed (false).
  bool runUntil(const std::function<bool()>& done, uint64_t maxUs);
  // The same, from one of the twin's peripheral events to the next (exact to the cycle, and fast over long
  // waits): for a `done()` that only an event can change, such as an interrupt flag.
  bool runUntilEvent(const std::function<bool()>& done, uint64_t maxUs);
  // A buffer the DMA reads (TX source) or writes (RX destination); valid until the next reset().
  void dmaBuffer(std::span<const uint8_t> source) { shareBuffer(source.data(), nullptr, source.size()); }
  void dmaBuffer(std::span<uint8_t> buffer) { shareBuffer(buffer.data(), buffer.data(), buffer.size()); }

  // Called by the mmio facade.
  uint32_t read(uintptr_t address);
  void write(uintptr_t address, uint32_t value);
  void spin(uint32_t iterations);

  const std::vector<Access>& log() const { return log_; }
  void clearLog() { log_.clear(); }
  std::vector<uint32_t> writes(uintptr_t address) const;
  std::optional<uint32_t> lastWrite(uintptr_t address) const;
  size_t readCount(uintptr_t address) const;
  size_t spinCount() const;
  // Index in log() of the first write of `value` to `address` at or after `from`, or -1.
  long findWrite(uintptr_t address, uint32_t value, size_t from = 0) const;
  // True if the writes appear in this order (other accesses may come in between).
  bool wroteInOrder(const std::vector<std::pair<uintptr_t, uint32_t>>& writes) const;

 private:
  std::map<uintptr_t, uint32_t> current_;
  std::map<uintptr_t, std::deque<uint32_t>> queued_;
  std::map<uintptr_t, std::vector<std::function<void(uint32_t)>>> hooks_;
  std::map<uintptr_t, std::function<uint32_t()>> readHooks_;
  std::vector<Access> log_;
  std::vector<std::string> violations_;

  uint32_t twinRead(uintptr_t address);
  void twinWrite(uintptr_t address, uint32_t value);
  void checkTwin();  // flags a stop or a warning of the twin's rules not flagged yet
  struct DmaBuffer {
    const uint8_t* source;
    uint8_t* destination;  // null: the DMA only reads it
    size_t size;
    uint32_t twinAddress;
  };
  void shareBuffer(const uint8_t* source, uint8_t* destination, size_t size);
  uint32_t dmaAddress(uintptr_t address, uint32_t value);  // the twin's view of a DMASA/DMADA value
  std::vector<DmaBuffer> dmaBuffers_;
  uint32_t nextSram_ = 0;
  std::unique_ptr<twin::Mspm0> chip_;
  bool stopFlagged_ = false;
  size_t warningsFlagged_ = 0;
};

inline RegisterModel& model() {
  return RegisterModel::instance();
}

}  // namespace bsp::mspm0::test
