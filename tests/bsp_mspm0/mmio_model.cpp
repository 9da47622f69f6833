#include "mmio_model.hpp"

#include "mmio.hpp"

namespace bsp::mspm0::test {

RegisterModel& RegisterModel::instance() {
  static RegisterModel model;
  return model;
}

void RegisterModel::reset() {
  current_.clear();
  queued_.clear();
  hooks_.clear();
  readHooks_.clear();
  log_.clear();
  violations_.clear();
}

void RegisterModel::queueReads(uintptr_t address, std::initializer_list<uint32_t> values) {
  for (uint32_t v : values)
    queueRead(address, v);
}

uint32_t RegisterModel::value(uintptr_t address) const {
  auto it = current_.find(address);
  return it == current_.end() ? 0 : it->second;
}

uint32_t RegisterModel::read(uintptr_t address) {
  uint32_t v;
  auto q = queued_.find(address);
  if (q != queued_.end() && !q->second.empty()) {
    v = q->second.front();
    q->second.pop_front();
  } else if (auto h = readHooks_.find(address); h != readHooks_.end()) {
    v = h->second();
  } else {
    v = value(address);
  }
  log_.push_back({Access::Kind::Read, address, v});
  return v;
}

void RegisterModel::write(uintptr_t address, uint32_t v) {
  log_.push_back({Access::Kind::Write, address, v});
  current_[address] = v;
  auto h = hooks_.find(address);
  if (h == hooks_.end()) return;
  const auto hooks = h->second;  // a copy: a hook may add hooks
  for (const auto& hook : hooks)
    hook(v);
}

void RegisterModel::spin(uint32_t iterations) {
  log_.push_back({Access::Kind::Spin, 0, iterations});
}

std::vector<uint32_t> RegisterModel::writes(uintptr_t address) const {
  std::vector<uint32_t> out;
  for (const Access& a : log_)
    if (a.kind == Access::Kind::Write && a.address == address) out.push_back(a.value);
  return out;
}

std::optional<uint32_t> RegisterModel::lastWrite(uintptr_t address) const {
  for (auto it = log_.rbegin(); it != log_.rend(); ++it)
    if (it->kind == Access::Kind::Write && it->address == address) return it->value;
  return std::nullopt;
}

size_t RegisterModel::readCount(uintptr_t address) const {
  size_t n = 0;
  for (const Access& a : log_)
    if (a.kind == Access::Kind::Read && a.address == address) ++n;
  return n;
}

size_t RegisterModel::spinCount() const {
  size_t n = 0;
  for (const Access& a : log_)
    if (a.kind == Access::Kind::Spin) ++n;
  return n;
}

long RegisterModel::findWrite(uintptr_t address, uint32_t v, size_t from) const {
  for (size_t i = from; i < log_.size(); ++i) {
    const Access& a = log_[i];
    if (a.kind == Access::Kind::Write && a.address == address && a.value == v) return static_cast<long>(i);
  }
  return -1;
}

bool RegisterModel::wroteInOrder(const std::vector<std::pair<uintptr_t, uint32_t>>& writes) const {
  size_t from = 0;
  for (const auto& [address, v] : writes) {
    const long at = findWrite(address, v, from);
    if (at < 0) return false;
    from = static_cast<size_t>(at) + 1;
  }
  return true;
}

}  // namespace bsp::mspm0::test

// The mmio facade's host definitions.
namespace bsp::mspm0::mmio {

uint32_t read32(uintptr_t address) {
  return test::model().read(address);
}
void write32(uintptr_t address, uint32_t value) {
  test::model().write(address, value);
}
void spin(uint32_t iterations) {
  test::model().spin(iterations);
}

}  // namespace bsp::mspm0::mmio
