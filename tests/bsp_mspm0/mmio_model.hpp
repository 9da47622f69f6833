// RegisterModel: the host stand-in for MSPM0 peripheral registers (the idea of OpenTitan's mock_mmio,
// written for this project). The MSPM0 drivers are compiled with BSP_MSPM0_MMIO_MODEL=1, so every
// mmio::Reg::read()/write() and mmio::spin() lands here with the register's address.
//
// Behaviour
// - Every access is appended to log() in program order: reads with the value returned, writes with the value
//   written, spins with their iteration count.
// - A read returns, in order of preference: the next value queued for that address (queueRead, consumed
//   one per read), else the value of the address's read hook (onRead: a peripheral model computes it), else
//   the address's current value. The current value is the last value written or set() (0 if neither), so
//   read-modify-write sequences behave as on plain registers. Status registers are scripted with set()
//   (held) or queueRead() (one-shot, e.g. a FIFO count that drops as it is drained).
// - onWrite(address, hook) runs `hook(value)` after a write to that address is logged and stored (e.g. to
//   model a DMA-done flag appearing when a channel is enabled); several hooks run in the order added. Hooks
//   may call set()/queueRead().
// - Peripheral models (mcan_model, i2c_model, uart_dma_model, sysctl_model, pin_model) attach hooks and
//   report a broken documented rule with flag(rule); every rule cites the TI source it enforces.
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
#include <optional>
#include <string>
#include <utility>
#include <vector>

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

  void reset();
  void set(uintptr_t address, uint32_t value) { current_[address] = value; }
  void queueRead(uintptr_t address, uint32_t value) { queued_[address].push_back(value); }
  void queueReads(uintptr_t address, std::initializer_list<uint32_t> values);
  void onWrite(uintptr_t address, std::function<void(uint32_t)> hook) {
    hooks_[address].push_back(std::move(hook));
  }
  void onRead(uintptr_t address, std::function<uint32_t()> hook) { readHooks_[address] = std::move(hook); }
  void flag(std::string rule) { violations_.push_back(std::move(rule)); }
  const std::vector<std::string>& violations() const { return violations_; }
  std::vector<std::string> takeViolations() { return std::exchange(violations_, {}); }
  uint32_t value(uintptr_t address) const;

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
};

inline RegisterModel& model() {
  return RegisterModel::instance();
}

}  // namespace bsp::mspm0::test
