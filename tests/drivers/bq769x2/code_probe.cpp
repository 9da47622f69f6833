// Compiled for Cortex-M0+ by code_size.cmake with link.cpp and monitor.cpp: the parts of the driver that live
// in its headers (the constructors, the BQ76952 variant table and its checks), instantiated as the BQ76952
// image instantiates them, so that the code count includes them. The probe's own few instructions are
// counted too (an over-count of a few bytes, never an under-count).
#include <new>

#include "drivers/bq769x2/monitor.hpp"

namespace drv = fw::drivers::bq769x2;

drv::Bq769x2* bq769x2CodeProbe(fw::hal::I2cBus& bus, const fw::hal::Clock& clock,
                               const fw::drivers::DriverContext& context) {
  alignas(drv::Bq769x2) static unsigned char storage[sizeof(drv::Bq769x2)];
  return new (storage) drv::Bq769x2(bus, clock, context);
}
