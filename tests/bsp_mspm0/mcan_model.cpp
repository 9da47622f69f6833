#include "mcan_model.hpp"

#include <string>

#include "mmio_model.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kRstctl = 0x6804;
constexpr uintptr_t kCccr = 0x7018;
constexpr uintptr_t kPsr = 0x7044;
constexpr uintptr_t kIr = 0x7050;
constexpr uintptr_t kIe = 0x7054;
constexpr uintptr_t kIls = 0x7058;
constexpr uintptr_t kIle = 0x705C;
constexpr uintptr_t kSsStat = 0x7208;
constexpr uintptr_t kSsEoi = 0x7220;
constexpr uintptr_t kWrapImask = 0x7828;
constexpr uintptr_t kWrapRis = 0x7830;
constexpr uintptr_t kWrapMis = 0x7838;
constexpr uintptr_t kWrapIset = 0x7840;
constexpr uintptr_t kWrapIclr = 0x7848;
constexpr uintptr_t kClkEn = 0x7900;
constexpr uintptr_t kClkDiv = 0x7904;

constexpr uint32_t kInit = 1U << 0;
constexpr uint32_t kPsrBusOff = 1U << 7;
constexpr uint32_t kIrBusOff = 1U << 25;
constexpr uint32_t kIntL0 = 1U << 0;
constexpr uint32_t kMemInitDone = 1U << 1;
constexpr uint32_t kEoiLine0 = 0x01;
// A written INIT value reads back from this read of CCCR on (any number > 1 makes a driver poll).
constexpr uint32_t kInitSyncReads = 2;

}  // namespace

void McanModel::attach() {
  noMessageRam_ = false;
  stayInInit_ = false;
  resetState();
  RegisterModel& m = model();
  m.onWrite(base_ + kRstctl, [this](uint32_t v) {
    if (v & 1U) resetState();  // RESETASSERT
  });
  m.onWrite(base_ + kClkEn, [this](uint32_t v) { clockOn_ = (v & 1U) != 0; });
  m.onWrite(base_ + kClkDiv, [this](uint32_t) {
    if (!clockOn_)
      model().flag(
          "MCAN: MCANSS_CLKDIV written before MCANSS_CLKEN.CLK_REQEN (hw_mcan.h MCAN_CLKEN; TI enables the "
          "module clock first)");
  });
  m.onRead(base_ + kSsStat, [this] { return clockOn_ && !noMessageRam_ ? kMemInitDone : 0U; });
  m.onWrite(base_ + kCccr, [this](uint32_t v) { onCccrWrite(v); });
  m.onRead(base_ + kCccr, [this] { return onCccrRead(); });
  m.onRead(base_ + kIr, [this] { return ir_; });
  m.onWrite(base_ + kIr, [this](uint32_t v) {
    ir_ &= ~v;  // write 1 to clear
    updateLine();
  });
  for (uintptr_t r : {kIe, kIls, kIle})
    m.onWrite(base_ + r, [this](uint32_t) { updateLine(); });
  m.onWrite(base_ + kSsEoi, [this](uint32_t v) {
    if (v != kEoiLine0) return;  // 0x00 external timestamp, 0x02 line 1, others ignored
    held_ = false;
    updateLine();  // a source still pending asserts the line again
  });
  m.onRead(base_ + kWrapRis, [this] { return latch_ || held_ ? kIntL0 : 0U; });
  m.onRead(base_ + kWrapMis, [this] { return interruptPending() ? kIntL0 : 0U; });
  m.onWrite(base_ + kWrapIclr, [this](uint32_t v) {
    if (v & kIntL0) latch_ = false;
  });
  m.onWrite(base_ + kWrapIset, [this](uint32_t v) {
    if (v & kIntL0) latch_ = true;
  });
}

void McanModel::resetState() {
  ir_ = 0;
  held_ = latch_ = clockOn_ = false;
  initVisible_ = true;
  initPending_ = false;
  initSyncReads_ = 0;
  initReadAfterWrite_ = true;
  for (uintptr_t r : {kIe, kIls, kIle, kWrapImask, kClkEn, kCccr})
    model().set(base_ + r, 0);
}

void McanModel::raise(uint32_t irBits) {
  ir_ |= irBits;
  updateLine();
}

void McanModel::busOff() {
  model().set(base_ + kPsr, kPsrBusOff);
  initVisible_ = true;  // the controller sets INIT itself on bus-off (ISO 11898-1, M_CAN user manual)
  initPending_ = false;
  raise(kIrBusOff);
}

void McanModel::leaveBusOff() {
  model().set(base_ + kPsr, 0);
  raise(kIrBusOff);
}

bool McanModel::interruptPending() const {
  return (latch_ || held_) && (model().value(base_ + kWrapImask) & kIntL0) != 0;
}

void McanModel::updateLine() {
  const RegisterModel& m = model();
  const bool enabled = (m.value(base_ + kIle) & 1U) != 0;
  const uint32_t line0 = ir_ & m.value(base_ + kIe) & ~m.value(base_ + kIls);
  if (enabled && line0 != 0 && !held_) {
    held_ = true;
    latch_ = true;
  }
}

void McanModel::onCccrWrite(uint32_t value) {
  const bool init = (value & kInit) != 0;
  if (initPending_ && init != initTarget_) {
    model().flag(
        "MCAN: CCCR.INIT written again before its previous value read back (hw_mcan.h MCAN_CCCR INIT)");
  }
  initReadAfterWrite_ = false;
  if (init == initVisible_) {
    initPending_ = false;
    return;
  }
  initPending_ = true;
  initTarget_ = init;
  initSyncReads_ = 0;
}

uint32_t McanModel::onCccrRead() {
  if (initPending_ && ++initSyncReads_ >= kInitSyncReads && !(stayInInit_ && !initTarget_)) {
    initVisible_ = initTarget_;
    initPending_ = false;
  }
  if (!initPending_) initReadAfterWrite_ = true;
  return (model().value(base_ + kCccr) & ~kInit) | (initVisible_ ? kInit : 0U);
}

}  // namespace bsp::mspm0::test
