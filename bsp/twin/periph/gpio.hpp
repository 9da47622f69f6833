// Gpio: one MSPM0 GPIO port (GPIOA 0x400A0000, GPIOB 0x400A2000; tsv base rows), registers and fields from
// mspm0-sdk hw_gpio.h: DOUT31_0 0x1280 with DOUTSET/CLR/TGL 0x1290/0x12A0/0x12B0, DOE31_0 0x12C0 with
// DOESET/CLR 0x12D0/0x12E0, DIN31_0 0x1380, POLARITY15_0 0x1390 / POLARITY31_16 0x13A0 (two bits per pin:
// 1 rising, 2 falling, 3 both, GPIO_POLARITY15_0_DIO0_*), the common GPRCM and CPU_INT blocks
// (peripheral.hpp).
//
// Edge detection: an edge of the pin's input (a GPIO pin with INENA; pins.hpp) that matches POLARITY sets the
// pin's RIS bit (SLAU846B/SLAU847D GPIO chapter, "GPIO interrupt"); the port's interrupt output is MIS != 0
// and goes to INT_GROUP1 (cpuss.hpp), not to an NVIC line of its own.
#pragma once

#include <cstdint>

#include "periph/peripheral.hpp"
#include "periph/pins.hpp"

namespace twin {

class Gpio final : public Peripheral {
 public:
  Gpio(Machine& machine, const char* name, int port, Pins& pins);
  uint32_t dout() const { return dout_; }
  uint32_t doe() const { return doe_; }
  // The edges of `bit` that set its RIS bit (POLARITY: 0 none, 1 rising, 2 falling, 3 both) and whether its
  // interrupt is unmasked (IMASK): the board's SIGNAL-EDGE rule asks.
  uint32_t edgePolarity(int bit) const { return (polarity_[bit / 16] >> (2 * (bit % 16))) & 3U; }
  bool edgeUnmasked(int bit) const { return (cpuInt_.imask >> bit) & 1U; }
  // Pins: the pad level of `bit` changed.
  void padChanged(int bit, bool level);

 private:
  bool readRegister(uint32_t offset, uint32_t& value) override;
  bool writeRegister(uint32_t offset, uint32_t value) override;
  void resetRegisters() override;
  void outputsChanged() { pins_.refreshPort(port_); }

  int port_;
  Pins& pins_;
  uint32_t dout_ = 0, doe_ = 0;
  uint32_t polarity_[2] = {0, 0};
};

}  // namespace twin
