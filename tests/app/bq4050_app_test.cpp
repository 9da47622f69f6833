// The lp-mspm0g3507-bq4050 board (firmware/app/bq4050_app.hpp) on the host BSP against the gauge emulator on
// a 100 kHz SMBus with the image's 25 ms stretch limit: issue 15's outage sweep. The gauge vanishes from the
// bus (a cable, a gauge in reset) for 50 ms .. 10 s starting at points across the 100 ms scan period, either
// coming back as it was or having reset in between; good scans must resume within the bound below after it
// returns, with the fault output and comm_loss/stale_data cleared, and no scan in between may be published as
// valid.
#include <gtest/gtest.h>

#include <memory>

#include "app/bq4050_app.hpp"
#include "bq4050/gauge_emulator.hpp"
#include "outage_sweep.hpp"
#include "sim/can.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"
#include "sim/peripherals.hpp"

namespace {

enum Outage : int { kVanish, kVanishAndReset };

struct Board {
  Board() {
    bus.attach(bsp::host::Bq4050Emulator::kAddress, gauge);
    app.start();
  }
  static const char* outageName(int kind) { return kind == kVanish ? "vanish" : "vanish+reset"; }
  void setOutage(int kind, bool on) {
    if (on) {
      bus.detach(bsp::host::Bq4050Emulator::kAddress);
      if (kind == kVanishAndReset) gauge.reset();
    } else {
      bus.attach(bsp::host::Bq4050Emulator::kAddress, gauge);
    }
  }

  bsp::host::Harness h;
  bsp::host::SimI2cBus bus{h.clock, h.irq, {100000, fw::ms(25), fw::us(4)}};
  bsp::host::Bq4050Emulator gauge;
  bsp::host::SimCan can{h.clock, h.irq, 500000, 8};
  bsp::host::SimDigitalOut faultOut{h.clock, true};  // the board asserts it from reset
  fw::app::Bq4050AppConfig config;
  fw::app::Bq4050App app{h.sched, fw::app::Bq4050App::Io{bus, can, faultOut}, config};
};

// The loss must first be noticed (three failed scans); once it is, the gauge is probed again within one scan
// period of answering again; then one probe and one scan run (`bootUs`, from power-on to the first good scan,
// is one of each). Fails on the code before, which waited a whole second between probes (worst 1005 ms).
uint64_t bound(const Board& b, uint64_t bootUs) {
  return 4 * b.config.scanPeriod.us + bootUs;
}

TEST(Bq4050Recovery, OutageSweep) {
  test::outageSweep<Board>(
      "app.bq4050.outage_recovery_worst_ms", [] { return std::make_unique<Board>(); },
      {{50, 250, 350, 500, 1000, 2500, 10000}, {0, 5, 30, 60, 90}, {kVanish, kVanishAndReset}}, bound);
}

}  // namespace
