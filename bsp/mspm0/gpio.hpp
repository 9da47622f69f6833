// GPIO for the MSPM0: pin muxing helpers, a push-pull output (fw::hal::DigitalOut), edge-interrupt inputs
// (fw::hal::EdgeInput) and the INT_GROUP1 dispatcher that routes GPIO interrupts to them.
//
// Contract
// - muxPeripheral/muxGpioInput and GpioOut::init write the pin's IOMUX PINCM register once; call them before
//   the peripheral or pin is used. They are not thread-safe against each other on the same pin.
// - GpioOut::set() is callable from any context (DOUTSET/DOUTCLR are single writes, no read-modify-write).
// - GpioEdgeInput::enable(notify) clears a stale edge, then unmasks the pin; `notify` runs in ISR context
//   (INT_GROUP1) once per serviced edge. enable()/disable() are for task context.
// - GpioInterrupts::onInterrupt() is the body of GROUP1_IRQHandler: it reads the group's IIDX to find the
//   port, reads that port's MIS, clears exactly those bits (ICLR), notifies the inputs and returns. If more
//   than one port is pending, the NVIC line stays asserted and the handler runs again.
//   onPortInterrupt() does the same for a part whose INT_GROUP1 has a single GPIO member, `port` (the L1306:
//   GPIOA, IIDX 1), with every input on that port, without the port look-up.
#pragma once

#include <cstdint>
#include <span>

#include "hal/gpio.hpp"
#include "hal/notify.hpp"
#include "mmio.hpp"
#include "pin.hpp"
#include "regs/cpuss.hpp"
#include "regs/gpio.hpp"

namespace bsp::mspm0 {

enum class Pull : uint8_t { None, Up, Down };
enum class Edge : uint8_t { Rising = 1, Falling = 2, Both = 3 };  // GPIO POLARITY encodings

// IOMUX PINCM writes. `extra` adds PINCM bits (input enable, pulls, open drain) to PC|PF.
void muxPeripheral(const PinFunction& function, uint32_t extra = 0);
inline void muxGpioInput(const Pin& pin, Pull pull) {
  namespace iomux = reg::iomux;
  const uint32_t pullBits = pull == Pull::Up ? iomux::kPullUp : pull == Pull::Down ? iomux::kPullDown : 0;
  reg::gpio::data(pin.portBase()).doeclr.write(pin.mask());
  iomux::pincm(pin.pincm).write(iomux::kPc | iomux::kPfGpio | iomux::kInputEnable | pullBits);
}
// Powers a GPIO port (GPRCM reset + enable).
inline void powerGpioPort(uintptr_t port) {
  reg::resetAndPowerUp(reg::gprcm(port));
}

class GpioOut final : public fw::hal::DigitalOut {
 public:
  constexpr explicit GpioOut(Pin pin) : pin_(pin) {}
  void init(bool high);

 private:
  void doSet(bool high) override;
  bool doLevel() const override { return level_; }

  Pin pin_;
  volatile bool level_ = false;
};

class GpioEdgeInput final : public fw::hal::EdgeInput {
 public:
  constexpr GpioEdgeInput(Pin pin, Edge edge, Pull pull) : pin_(pin), edge_(edge), pull_(pull) {}
  // Muxes the pin as an input and selects its edge; the interrupt stays masked until enable(). Inline and
  // const: a board calls it on a constexpr copy of its input, and the register writes fold to constants.
  void init() const {
    muxGpioInput(pin_, pull_);
    // POLARITY15_0 / POLARITY31_16 hold two bits per pin (TRM GPIO "Interrupt polarity").
    reg::gpio::Input& in = reg::gpio::input(pin_.portBase());
    const uint32_t shift = 2U * (pin_.bit & 15U);
    mmio::modify(pin_.bit < 16 ? in.polarity15_0 : in.polarity31_16, reg::gpio::kPolarityMask << shift,
                 static_cast<uint32_t>(edge_) << shift);
  }
  const Pin& pin() const { return pin_; }
  // ISR context, from GpioInterrupts.
  void onEdge() const { notify_(); }

 private:
  void doEnable(const fw::hal::Notify& notify) override;
  void doDisable() override;
  bool doLevel() const override;

  Pin pin_;
  Edge edge_;
  Pull pull_;
  fw::hal::Notify notify_{};
};

// GROUP1_IRQHandler body of a single-port part (see the contract above). Inline: the handler's constant
// port and input list fold into it.
inline void onPortInterrupt(uintptr_t cpuss, uintptr_t port, std::span<GpioEdgeInput* const> inputs) {
  // IIDX 1 is the part's only GPIO port (anything else is not a GPIO event).
  if (reg::cpuss::group(cpuss, 1).iidx.read() != 1) return;
  reg::EventBlock& events = reg::cpuInt(port);
  const uint32_t pending = events.mis.read();
  events.iclr.write(pending);
  for (const GpioEdgeInput* input : inputs) {
    if ((pending & input->pin().mask()) != 0) input->onEdge();
  }
}

class GpioInterrupts {
 public:
  // `ports[i]` is the GPIO base that INT_GROUP1 IIDX value i+1 names (1 = GPIOA, 2 = GPIOB).
  constexpr GpioInterrupts(uintptr_t cpuss, std::span<const uintptr_t> ports,
                           std::span<GpioEdgeInput* const> inputs)
      : cpuss_(cpuss), ports_(ports), inputs_(inputs) {}
  void onInterrupt() const;

 private:
  uintptr_t cpuss_;
  std::span<const uintptr_t> ports_;
  std::span<GpioEdgeInput* const> inputs_;
};

}  // namespace bsp::mspm0
