// GPIO for the MSPM0: pin muxing helpers, a push-pull output (fw::hal::DigitalOut), edge-interrupt inputs
// (fw::hal::EdgeInput) and the INT_GROUP1 dispatcher that routes GPIO interrupts to them.
//
// Contract
// - muxPeripheral/muxGpioOutput/muxGpioInput write the pin's IOMUX PINCM register once; call them before the
//   peripheral or pin is used. They are not thread-safe against each other on the same pin.
// - GpioOut::set() is callable from any context (DOUTSET/DOUTCLR are single writes, no read-modify-write).
// - GpioEdgeInput::enable(notify) clears a stale edge, then unmasks the pin; `notify` runs in ISR context
//   (INT_GROUP1) once per serviced edge. enable()/disable() are for task context.
// - GpioInterrupts::onInterrupt() is the body of GROUP1_IRQHandler: it reads the group's IIDX to find the
//   port, reads that port's MIS, clears exactly those bits (ICLR), notifies the inputs and returns. If more
//   than one port is pending, the NVIC line stays asserted and the handler runs again.
#pragma once

#include <cstdint>
#include <span>

#include "hal/gpio.hpp"
#include "hal/notify.hpp"
#include "pin.hpp"

namespace bsp::mspm0 {

enum class Pull : uint8_t { None, Up, Down };
enum class Edge : uint8_t { Rising = 1, Falling = 2, Both = 3 };  // GPIO POLARITY encodings

// IOMUX PINCM writes. `extra` adds PINCM bits (input enable, pulls, open drain) to PC|PF.
void muxPeripheral(const PinFunction& function, uint32_t extra = 0);
// (inline, defined in gpio.cpp: each has one caller there, GpioOut::init / GpioEdgeInput::init)
inline void muxGpioOutput(const Pin& pin, bool high);
inline void muxGpioInput(const Pin& pin, Pull pull);
// Powers a GPIO port (GPRCM reset + enable).
void powerGpioPort(uintptr_t port);

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
  // Muxes the pin as an input and selects its edge; the interrupt stays masked until enable().
  void init();
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
