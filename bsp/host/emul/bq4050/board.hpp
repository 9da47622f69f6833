// Bq4050Board: the lp-mspm0g3507-bq4050 board on the host BSP, as bms-sim, `bmsctl trace bq4050 app-start`
// and the application tests run it: the image's application (firmware/app/monitors/bq4050_app.hpp) with the
// gauge emulator on a 100 kHz SMBus with the image's 25 ms stretch limit, CAN at 500 kbit/s and the fault
// output (asserted from reset), the MCU's identity and bootloader entry (SimSystem); the CAN controller's
// receive filter takes the command identifiers only, as the G3507 BSP sets the MCAN's. The application is
// started by the constructor; nothing happens until the harness runs. Header-only: users link fw_app_bq4050
// and emul_bq4050.
#pragma once

#include "app/monitors/bq4050_app.hpp"
#include "bq4050/gauge_emulator.hpp"
#include "packs/bq4050-evm.hpp"
#include "sim/can.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"
#include "sim/peripherals.hpp"

namespace bsp::host {

struct Bq4050Board {
  Bq4050Board() {
    can.setFilter({fw::can::bms::kReceivedIds.begin(), fw::can::bms::kReceivedIds.end()});
    gauge.attachClock(h.clock);  // its charge state follows the current (gauge_emulator.hpp)
    bus.attach(Bq4050Emulator::kAddress, gauge);
    app.start();
  }
  // The gauge on the bus, or gone from it (a cable, a gauge in reset): its address is then NACKed.
  void attachGauge(bool present) {
    if (present) {
      bus.attach(Bq4050Emulator::kAddress, gauge);
    } else {
      bus.detach(Bq4050Emulator::kAddress);
    }
  }

  Harness h;
  SimI2cBus bus{h.clock, h.irq, {100000, fw::ms(25), fw::us(4)}};
  Bq4050Emulator gauge;
  SimCan can{h.clock, h.irq, 500000, 8};
  SimDigitalOut faultOut{h.clock, true};
  SimSystem system{h.clock};
  fw::app::Bq4050AppConfig config{.storage = fw::packs::bq4050_evm::kStorage};  // the image's pack
  fw::app::Bq4050App app{h.sched, fw::app::Bq4050App::Io{bus, can, faultOut, system}, config};
};

}  // namespace bsp::host
