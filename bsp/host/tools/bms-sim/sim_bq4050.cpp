// bms-sim binding of the lp-mspm0g3507-bq4050 image: the BQ4050 gauge emulator on a simulated 100 kHz SMBus,
// CAN on a simulated 500 kbit/s controller, the fault output on a pin.
#include <memory>

#include "app/bq4050_app.hpp"
#include "app/default_limits.hpp"
#include "bq4050/gauge_emulator.hpp"
#include "image_sim.hpp"
#include "pack_figures.hpp"
#include "sim/can.hpp"
#include "sim/i2c_bus.hpp"
#include "sim/peripherals.hpp"

namespace bmssim {
namespace {

class Bq4050Sim final : public ImageSim {
 public:
  Bq4050Sim() {
    bus_.attach(bsp::host::Bq4050Emulator::kAddress, emulator_);
    for (int c = 1; c <= 4; ++c)
      setCellMv(0, c, 3700);
    setTempDeciK(0, 1, 2982);
    app_ = std::make_unique<fw::app::Bq4050App>(h_.sched, fw::app::Bq4050App::Io{bus_, can_, faultOut_},
                                                config_);
    app_->start();
  }

  int boards() const override { return 1; }
  int cellsPerBoard() const override { return 4; }
  int tempsPerBoard() const override { return 1; }
  bool hasCurrent() const override { return true; }

  void setCellMv(int, int cell, int mv) override {
    truth_[static_cast<size_t>(cell - 1)] = mv;
    push();
  }
  void setCurrentMa(int ma) override { emulator_.setCurrent(static_cast<int16_t>(ma)); }
  void setTempDeciK(int, int, int deciK) override { emulator_.setTemperature(static_cast<uint16_t>(deciK)); }
  void setCommLost(bool lost) override { attach(!lost); }
  void openWire(int, int cell) override {
    openCell_ = cell;
    push();
  }
  void setIntermittent(bool on) override {
    intermittent_ = on;
    if (!on) attach(true);
  }
  bool busOff() override {
    can_.injectBusOff();
    return true;
  }

  void afterStep() override {
    // An intermittent link: the gauge drops off the bus for 250 ms of every 350 ms.
    if (intermittent_) attach((tick_++ % 350) >= 250);
    meter_.observe(app_->monitor().stats().scans, 0, bus_.busTimeUs(), bus_.transactions());
  }

  bsp::host::Harness& harness() override { return h_; }

  SimFigures figures() override {
    SimFigures f;
    const auto& st = app_->monitor().stats();
    fillScanFigures(f, st, config_.scanPeriod, meter_);
    const auto& gs = app_->monitor().gauge().stats();
    for (uint32_t e : gs.failures)
      f.commErrors += e;
    f.recoveries = st.probes > 0 ? st.probes - 1 : 0;
    f.outputFrames = can_.sent().size();
    f.output = "can";
    fillPackFigures(f, app_->pack(), app_->status(), fw::Instant{static_cast<uint32_t>(h_.nowUs())},
                    fw::app::kDefaultLimits.staleAfter);
    return f;
  }

  std::vector<fw::app::ProtectionRecord> protectionLog() const override { return protectionLogOf(*app_); }
  std::vector<SentFrame> frames() const override { return canFrames(can_); }

 private:
  void attach(bool present) {
    if (present) {
      bus_.attach(bsp::host::Bq4050Emulator::kAddress, emulator_);
    } else {
      bus_.detach(bsp::host::Bq4050Emulator::kAddress);
    }
  }
  // The gauge measures each cell across its sense lines: an open line reads 0 below and the sum above.
  void push() {
    int pack = 0;
    for (int c = 1; c <= 4; ++c) {
      emulator_.setCell(c, static_cast<uint16_t>(sensedMv(truth_, c, openCell_)));
      pack += truth_[static_cast<size_t>(c - 1)];
    }
    emulator_.setVoltage(static_cast<uint16_t>(pack));
  }

  bsp::host::Harness h_;
  bsp::host::SimI2cBus bus_{h_.clock, h_.irq, {100000, fw::ms(25), fw::us(4)}};
  bsp::host::Bq4050Emulator emulator_;
  bsp::host::SimCan can_{h_.clock, h_.irq, 500000, 8};
  bsp::host::SimDigitalOut faultOut_{h_.clock, true};  // the board asserts it from reset
  fw::app::Bq4050AppConfig config_;
  std::unique_ptr<fw::app::Bq4050App> app_;
  std::vector<int> truth_ = std::vector<int>(4, 3700);
  int openCell_ = -1;
  bool intermittent_ = false;
  uint64_t tick_ = 0;
  ScanMeter meter_;
};

std::unique_ptr<ImageSim> make(const SimOptions&, std::string&) {
  return std::make_unique<Bq4050Sim>();
}

const ImageRegistrar kRegistrar{{"lp-mspm0g3507-bq4050", "BQ4050 gas gauge over SMBus, CAN out", 1, &make}};

}  // namespace
}  // namespace bmssim
