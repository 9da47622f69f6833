// Bq79616Board: the lp-mspm0g3507-bq79616 board on the host BSP, as bms-sim, `bmsctl trace bq79616 app-start`
// and the application tests run it: the image's application (firmware/app/monitors/bq79616_app.hpp) with the
// chain on a 1 Mbaud UART, nFAULT, CAN at 500 kbit/s and the fault output (asserted from reset), against the
// chain emulator with every cell at 3.700 V and every die at 25 degC, the MCU's identity and bootloader entry
// (SimSystem); the CAN controller's receive filter takes the command identifiers only, as the G3507 BSP sets
// the MCAN's. The application is started by the
// constructor; nothing happens until the harness runs. Header-only: users link fw_app_bq79616 and
// emul_bq79616.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "app/monitors/bq79616_app.hpp"
#include "bq79616/chain_emulator.hpp"
#include "sim/can.hpp"
#include "sim/harness.hpp"
#include "sim/peripherals.hpp"
#include "sim/uart.hpp"

namespace bsp::host {

struct Bq79616Board {
  // `config.chain.devices` devices in the application's configuration and on the emulated chain.
  explicit Bq79616Board(const fw::app::Bq79616AppConfig& appConfig)
      : emu(h.clock, uart, appConfig.chain.devices), config(appConfig) {
    can.setFilter({fw::can::bms::kReceivedIds.begin(), fw::can::bms::kReceivedIds.end()});
    uart.attach(emu);
    emu.attachFaultPin(nfault);
    for (size_t d = 0; d < emu.size(); ++d) {
      for (int c = 1; c <= 16; ++c)
        emu.setCellMicrovolts(d, c, 3700000);
      for (int t = 1; t <= 2; ++t)
        emu.setDieTempRaw(d, t, static_cast<int16_t>(2982 * 4 - 10926));  // 25 degC, 0.025 degC per LSB
    }
    app.start();
  }
  explicit Bq79616Board(size_t devices) : Bq79616Board(configFor(devices)) {}

  static fw::app::Bq79616AppConfig configFor(size_t devices) {
    fw::app::Bq79616AppConfig c;
    c.chain.devices = static_cast<uint8_t>(devices);
    return c;
  }

  Harness h;
  SimUart uart{h.clock, h.irq, 1000000};
  Bq79616ChainEmulator emu;
  SimEdgeInput nfault{h.irq, "nfault", SimEdgeInput::Edge::Falling, true};
  SimCan can{h.clock, h.irq, 500000, 8};
  SimDigitalOut faultOut{h.clock, true};
  SimSystem system{h.clock};
  fw::app::Bq79616AppConfig config;
  std::unique_ptr<fw::app::Bq79616Storage> storage = std::make_unique<fw::app::Bq79616Storage>();
  fw::app::Bq79616App app{h.sched, fw::app::Bq79616App::Io{uart, nfault, can, faultOut, system}, config,
                          *storage};
};

}  // namespace bsp::host
