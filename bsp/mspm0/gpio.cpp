#include "gpio.hpp"

#include <atomic>

#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/gpio.hpp"

namespace bsp::mspm0 {

namespace gpio = reg::gpio;
namespace iomux = reg::iomux;

void muxPeripheral(const PinFunction& function, uint32_t extra) {
  iomux::pincm(function.pin.pincm).write(iomux::kPc | function.pf | extra);
}

void GpioOut::init(bool high) {
  // Set the level before enabling the driver so the pin never glitches to the other level.
  doSet(high);
  gpio::data(pin_.portBase()).doeset.write(pin_.mask());
  iomux::pincm(pin_.pincm).write(iomux::kPc | iomux::kPfGpio);
}

void GpioOut::doSet(bool high) {
  level_ = high;
  gpio::Data& data = gpio::data(pin_.portBase());
  (high ? data.doutset : data.doutclr).write(pin_.mask());
}

void GpioEdgeInput::doEnable(const fw::hal::Notify& notify) {
  notify_ = notify;
  // The ISR reads notify_ once the pin is unmasked: keep the compiler from sinking the store below the
  // unmask (a single core needs no hardware barrier).
  std::atomic_signal_fence(std::memory_order_release);
  reg::EventBlock& events = reg::cpuInt(pin_.portBase());
  events.iclr.write(pin_.mask());  // forget an edge from before enable()
  mmio::setBits(events.imask, pin_.mask());
}

void GpioEdgeInput::doDisable() {
  mmio::clearBits(reg::cpuInt(pin_.portBase()).imask, pin_.mask());
}

bool GpioEdgeInput::doLevel() const {
  return (gpio::input(pin_.portBase()).din.read() & pin_.mask()) != 0;
}

void GpioInterrupts::onInterrupt() const {
  // INT_GROUP1 IIDX names the highest-priority pending member (tsv group_iidx rows): 1 GPIOA, 2 GPIOB.
  const uint32_t member = reg::cpuss::group(cpuss_, 1).iidx.read();
  if (member == 0 || member > ports_.size()) return;
  const uintptr_t port = ports_[member - 1];
  reg::EventBlock& events = reg::cpuInt(port);
  const uint32_t pending = events.mis.read();
  events.iclr.write(pending);
  for (const GpioEdgeInput* input : inputs_) {
    if (input->pin().portBase() == port && (pending & input->pin().mask()) != 0) input->onEdge();
  }
}

}  // namespace bsp::mspm0
