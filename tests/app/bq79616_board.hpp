// The lp-mspm0g3507-bq79616 board on the host BSP: the BQ79616 application as the image composes it (chain on
// a 1 Mbaud UART, nFAULT, CAN out, fault output) against the chain emulator with `devices` devices, every
// cell at 3.700 V and every die at 25 degC. For the application tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "app/bq79616_app.hpp"
#include "bq79616/chain_emulator.hpp"
#include "sim/can.hpp"
#include "sim/harness.hpp"
#include "sim/peripherals.hpp"
#include "sim/uart.hpp"

namespace test {

struct Bq79616Board {
  explicit Bq79616Board(size_t devices)
      : emu(h.clock, uart, devices), config([devices] {
          fw::app::Bq79616AppConfig c;
          c.chain.devices = static_cast<uint8_t>(devices);
          return c;
        }()) {
    uart.attach(emu);
    emu.attachFaultPin(nfault);
    for (size_t d = 0; d < devices; ++d) {
      for (int c = 1; c <= 16; ++c)
        emu.setCellMicrovolts(d, c, 3700000);
      for (int t = 1; t <= 2; ++t)
        emu.setDieTempRaw(d, t, static_cast<int16_t>(2982 * 4 - 10926));  // 25 degC, 0.025 degC per LSB
    }
    app.start();
  }
  // When the fault output was last driven high at or after `fromUs`, or 0.
  uint64_t assertedAt(uint64_t fromUs) const {
    for (const auto& [t, level] : faultOut.history())
      if (t >= fromUs && level) return t;
    return 0;
  }

  bsp::host::Harness h;
  bsp::host::SimUart uart{h.clock, h.irq, 1000000};
  bsp::host::Bq79616ChainEmulator emu;
  bsp::host::SimEdgeInput nfault{h.irq, "nfault", bsp::host::SimEdgeInput::Edge::Falling, true};
  bsp::host::SimCan can{h.clock, h.irq, 500000, 8};
  bsp::host::SimDigitalOut faultOut{h.clock, true};  // the board asserts it from reset
  fw::app::Bq79616AppConfig config;
  std::unique_ptr<fw::app::Bq79616Storage> storage = std::make_unique<fw::app::Bq79616Storage>();
  fw::app::Bq79616App app{h.sched, fw::app::Bq79616App::Io{uart, nfault, can, faultOut}, config, *storage};
};

}  // namespace test
