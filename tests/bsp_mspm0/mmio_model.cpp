#include "mmio_model.hpp"

#include <algorithm>
#include <array>

#include "mmio.hpp"

namespace bsp::mspm0::test {

namespace {

// The peripherals whose registers the twin answers (bases and spans: bsp/twin/mspm0.cpp, from the tsv base
// rows). The rest are still scripted by the test's own models.
struct Range {
  uintptr_t base, size;
};
constexpr Range kTwinRanges[] = {
    {twin::Sysctl::kBase, twin::Sysctl::kSize},
    {twin::Pins::kBase, twin::Pins::kSize},  // IOMUX
    {0x400A0000, 0x4000},                    // GPIOA, GPIOB
    {twin::Cpuss::kBase, twin::Cpuss::kSize},
    {0x40100000, 0xA000},  // UART1 0x40100000, UART2 0x40102000 (G3507), UART0 0x40108000
    {twin::Dma::kBase, twin::Dma::kSize},
    {0x400F0000, 0x4000},  // I2C0, I2C1
    {0x40508000, 0x8000},  // CANFD0 (G3507)
    {0x40084000, 0xA000},  // TIMG0, TIMG1 0x40086000 / TIMG2 0x40088000 / TIMG4 0x4008C000 (L1306)
    {0x40090000, 0x2000},  // TIMG8 (G3507)
    {0x40868000, 0x4000},  // TIMG6, TIMG7 (G3507)
    {0x40080000, 0x2000},  // WWDT0
    {twin::Flashctl::kBase, twin::Flashctl::kSize},
};

// What one register access takes on the twin: a Cortex-M0+ LDR or STR is 2 cycles (ARM DDI 0484C, Cortex-M0+
// TRM, "Instruction set summary"), so a poll loop lets the peripheral's time pass as on the part.
constexpr uint64_t kAccessCycles = 2;

// The twin's CPU runs WFI; B .-2 from 0x100 (the reset vector), SP at the top of SRAM: it sleeps, and time
// passes from one peripheral event to the next while a test waits.
std::vector<uint8_t> idleImage(twin::Part part) {
  const bool g = part == twin::Part::G3507;
  const uint32_t sp = g ? 0x20208000 : 0x20001000;
  const uint32_t entry = 0x100 | 1;
  std::vector<uint8_t> flash(0x104, 0);
  for (int i = 0; i < 4; ++i) {
    flash[i] = static_cast<uint8_t>(sp >> (8 * i));
    flash[4 + i] = static_cast<uint8_t>(entry >> (8 * i));
  }
  const std::array<uint8_t, 4> loop{0x30, 0xBF, 0xFD, 0xE7};
  std::copy(loop.begin(), loop.end(), flash.begin() + 0x100);
  return flash;
}

}  // namespace

RegisterModel& RegisterModel::instance() {
  static RegisterModel model;
  return model;
}

void RegisterModel::reset(twin::Part part) {
  current_.clear();
  queued_.clear();
  hooks_.clear();
  readHooks_.clear();
  log_.clear();
  violations_.clear();
  chip_ = std::make_unique<twin::Mspm0>(part);
  chip_->machine().loadFlash(idleImage(part));
  chip_->machine().powerOn();
  // The power-on's RSTCAUSE (0x01) is taken: each test states the reset it starts from.
  chip_->machine().takeResetCause();
  stopFlagged_ = false;
  warningsFlagged_ = 0;
  dmaBuffers_.clear();
  nextSram_ = chip_->machine().layout().sramBase;
}

void RegisterModel::shareBuffer(const uint8_t* source, uint8_t* destination, size_t size) {
  twin::Machine& m = chip_->machine();
  dmaBuffers_.push_back({source, destination, size, nextSram_});
  nextSram_ += static_cast<uint32_t>((size + 3) & ~size_t{3});
  if (nextSram_ > m.layout().sramBase + m.layout().sramSize / 2)
    flag("dmaBuffer(): the buffers take more than half the twin's SRAM");
}

uint32_t RegisterModel::dmaAddress(uintptr_t address, uint32_t value) {
  // DMACHAN[n] at DMA_BASE + 0x1200 + 0x10 n: DMASA +4, DMADA +8 (hw_dma.h; dma.hpp).
  const uintptr_t offset = address - twin::Dma::kBase;
  if (offset < 0x1200 || offset >= 0x1300 || ((offset & 0xF) != 4 && (offset & 0xF) != 8)) return value;
  for (const DmaBuffer& b : dmaBuffers_) {
    const uint32_t hostLow = static_cast<uint32_t>(reinterpret_cast<uintptr_t>(b.source));
    if (value - hostLow >= b.size) continue;
    for (size_t i = 0; i < b.size; ++i)
      chip_->machine().busWrite(b.twinAddress + static_cast<uint32_t>(i), 1, b.source[i]);
    return b.twinAddress + (value - hostLow);
  }
  return value;
}

bool RegisterModel::runUntil(const std::function<bool()>& done, uint64_t maxUs) {
  for (uint64_t us = 0; us < maxUs; ++us) {
    if (done()) return true;
    advanceUs(1);
  }
  return done();
}

bool RegisterModel::runUntilEvent(const std::function<bool()>& done, uint64_t maxUs) {
  twin::Machine& m = chip_->machine();
  const uint64_t end = m.now() + maxUs * m.cyclesPerUs();
  while (!done()) {
    if (m.now() >= end) return false;
    const uint64_t next = std::min(std::max(m.timeline().next(), m.now() + 1), end);
    advance(next - m.now());
  }
  return true;
}

bool RegisterModel::bridged(uintptr_t address) {
  for (const Range& r : kTwinRanges)
    if (address - r.base < r.size) return true;
  return false;
}

void RegisterModel::set(uintptr_t address, uint32_t value) {
  if (bridged(address)) {
    flag("set() on a register the twin models (" + chip_->machine().map().describe(address) +
         "): make the twin produce the state");
    return;
  }
  current_[address] = value;
}

void RegisterModel::checkTwin() {
  const twin::Machine& m = chip_->machine();
  if (m.stopped() && !stopFlagged_) {
    stopFlagged_ = true;
    flag("twin: " + m.stopReason());
  }
  for (; warningsFlagged_ < m.ruleWarnings().size(); ++warningsFlagged_)
    flag("twin: " + m.ruleWarnings()[warningsFlagged_]);
}

uint32_t RegisterModel::twinRead(uintptr_t address) {
  uint32_t v = 0;
  twin::AddressMap& map = chip_->machine().map();
  if (!map.load(static_cast<uint32_t>(address), 4, v))
    flag("twin: a read of " + map.describe(static_cast<uint32_t>(address)) + ", which it does not model");
  checkTwin();
  return v;
}

void RegisterModel::twinWrite(uintptr_t address, uint32_t value) {
  twin::AddressMap& map = chip_->machine().map();
  if (!map.store(static_cast<uint32_t>(address), 4, value))
    flag("twin: a write to " + map.describe(static_cast<uint32_t>(address)) + ", which it does not model");
  checkTwin();
}

void RegisterModel::advance(uint64_t cycles) {
  twin::Machine& m = chip_->machine();
  const uint64_t end = m.now() + cycles;
  if (!m.stopped()) m.run(end);
  if (m.stopped()) {  // flagged already; its peripherals' events still run
    while (m.timeline().fireNext(end)) {
    }
    m.timeline().advanceTo(end);
  }
  for (const DmaBuffer& b : dmaBuffers_) {
    for (size_t i = 0; b.destination != nullptr && i < b.size; ++i) {
      uint32_t byte = 0;
      m.busRead(b.twinAddress + static_cast<uint32_t>(i), 1, byte);
      b.destination[i] = static_cast<uint8_t>(byte);
    }
  }
  checkTwin();
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
  } else if (bridged(address)) {
    v = twinRead(address);
  } else if (auto h = readHooks_.find(address); h != readHooks_.end()) {
    v = h->second();
  } else {
    v = value(address);
  }
  log_.push_back({Access::Kind::Read, address, v});
  advance(kAccessCycles);
  return v;
}

void RegisterModel::write(uintptr_t address, uint32_t v) {
  log_.push_back({Access::Kind::Write, address, v});
  current_[address] = v;
  if (bridged(address)) twinWrite(address, dmaAddress(address, v));
  advance(kAccessCycles);
  auto h = hooks_.find(address);
  if (h == hooks_.end()) return;
  const auto hooks = h->second;  // a copy: a hook may add hooks
  for (const auto& hook : hooks)
    hook(v);
}

void RegisterModel::spin(uint32_t iterations) {
  log_.push_back({Access::Kind::Spin, 0, iterations});
  advance(4ULL * iterations);  // SUB + BNE, 4 cycles per iteration (mmio.hpp)
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
