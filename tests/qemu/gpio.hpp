// Stand-in for bsp/mspm0/gpio.hpp in the QEMU cycle benchmark (app_cycle_bench.cpp): the image's app_init.cpp
// drives the BQ76952's CFETOFF/DFETOFF through bsp::mspm0::GpioOut, whose MSPM0 GPIO registers QEMU's
// Cortex-M0 machine does not have. This one keeps the level only; the benchmark counts instructions of the
// application, not of a pin write (the real one is a single store to DOUTSET31_0 or DOUTCLR31_0).
#pragma once

#include "hal/gpio.hpp"
#include "mspm0/pin.hpp"

namespace bsp::mspm0 {

class GpioOut final : public fw::hal::DigitalOut {
 public:
  constexpr explicit GpioOut(Pin) {}
  void init(bool high) { level_ = high; }

 private:
  void doSet(bool high) override { level_ = high; }
  bool doLevel() const override { return level_; }

  bool level_ = false;
};

}  // namespace bsp::mspm0
