// ActiveLowInput: what the register model knows of a signal wired to an MSPM0 GPIO edge input, checked when
// the driver unmasks the pin's interrupt (a write of GPIO CPU_INT IMASK with the pin's bit set) and on
// check(). Addresses: IOMUX PINCMn at 0x40428000 + 4n (tsv note "PINCM index"); GPIO POLARITY15_0 at
// +0x1390, POLARITY31_16 at +0x13A0, IMASK at +0x1028 (tsv "GPIO.*" rows).
//
// Rules (TI source next to each)
// - The pin is a connected GPIO input: PINCM.PC (bit 7), PF = 1 (GPIO; tsv note "PINCM index"), INENA
//   (bit 18) (hw_iomux.h IOMUX_PINCM_PC / IOMUX_PINCM_INENA).
// - An active-low signal interrupts on its falling edge: POLARITY = 2 (FALL) for the pin (hw_gpio.h
//   GPIO_POLARITY15_0_DIO0_FALL).
// - An open-drain signal (the BQ76952 ALERT as the BQ769x2-family images configure it) needs the internal
//   pull-up: PINCM.PIPU (bit 17; hw_iomux.h IOMUX_PINCM_PIPU) set and PIPD (bit 16) clear. A driven signal
//   (BQ79616 nFAULT) needs no pull.
// A broken rule is flagged with the pin's name.
#pragma once

#include <cstdint>

namespace bsp::mspm0::test {

class ActiveLowInput {
 public:
  enum class Output : uint8_t { OpenDrain, Driven };
  ActiveLowInput(const char* name, uintptr_t port, uint32_t bit, uint32_t pincm, Output output)
      : name_(name), port_(port), bit_(bit), pincm_(pincm), output_(output) {}
  void attach();
  // Flags what is wrong with the pin's configuration now; returns true if nothing is.
  bool check() const;

 private:
  const char* name_;
  uintptr_t port_;
  uint32_t bit_;
  uint32_t pincm_;
  Output output_;
};

}  // namespace bsp::mspm0::test
