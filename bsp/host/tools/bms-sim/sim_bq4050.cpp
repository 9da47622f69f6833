// bms-sim binding of the lp-mspm0g3507-bq4050 image: the BQ4050 gauge emulator on a simulated 100 kHz SMBus,
// CAN on a simulated 500 kbit/s controller, the fault output on a pin.
#include <memory>

#include "app/monitors/bq4050_app.hpp"
#include "app/protection/default_limits.hpp"
#include "bq4050/board.hpp"
#include "can_board_sim.hpp"
#include "image_sim.hpp"
#include "pack_figures.hpp"

namespace bmssim {
namespace {

class Bq4050Sim final : public CanBoardSim<bsp::host::Bq4050Board> {
 public:
  Bq4050Sim() {
    for (int c = 1; c <= 4; ++c)
      setCellMv(0, c, 3700);
    setTempDeciK(0, 1, 2982);
  }

  int boards() const override { return 1; }
  int cellsPerBoard() const override { return 4; }
  int tempsPerBoard() const override { return 1; }
  bool hasCurrent() const override { return true; }

  void setCellMv(int, int cell, int mv) override {
    truth_[static_cast<size_t>(cell - 1)] = mv;
    push();
  }
  void setCurrentMa(int ma) override { board_.gauge.setCurrent(static_cast<int16_t>(ma)); }
  // The gauge balances on its own (not modelled): the cells are what the scenario set.
  int cellSpreadMv() override { return spreadOf(truth_); }
  // The gauge's own FETs, and the image's fault output, which stands for both paths.
  Paths paths() const override {
    const Paths out = pathsOfFaultOutput(board_.faultOut.level());
    return {out.charge && board_.gauge.chgFet(), out.discharge && board_.gauge.dsgFet()};
  }
  void setTempDeciK(int, int, int deciK) override {
    board_.gauge.setTemperature(static_cast<uint16_t>(deciK));
  }
  void setCommLost(bool lost) override { board_.attachGauge(!lost); }
  void openWire(int, int cell) override {
    openCell_ = cell;
    push();
  }
  void setIntermittent(bool on) override {
    intermittent_ = on;
    if (!on) board_.attachGauge(true);
  }
  // Device faults (scenario.hpp), as the twin's board has them (bsp/twin/board/board.hpp).
  FaultLinks faultLinks() const override { return {true, false, true}; }
  void i2cStretch(fw::Duration perByte) override { board_.bus.setDeviceStretch(perByte); }
  // The gauge resets its SMBus interface at the end of tTIMEOUT, 25..35 ms (SLUSC67A).
  void stuckScl() override { board_.bus.holdSclLow(board_.h.nowUs() + 35000); }
  void stuckSda() override { board_.bus.holdSdaLow(8); }

  void afterStep() override {
    // An intermittent link: the gauge drops off the bus for 250 ms of every 350 ms.
    if (intermittent_) board_.attachGauge((tick_++ % 350) >= 250);
    meter_.observe(board_.app.monitor().stats().scans, 0, board_.bus.busTimeUs(), board_.bus.transactions());
  }

  SimFigures figures() override {
    SimFigures f;
    const auto& st = board_.app.monitor().stats();
    fillScanFigures(f, st, board_.config.scanPeriod, meter_);
    const auto& gs = board_.app.monitor().gauge().stats();
    for (uint32_t e : gs.failures)
      f.commErrors += e;
    f.recoveries = st.probes > 0 ? st.probes - 1 : 0;
    f.outputFrames = board_.can.sent().size();
    f.output = "can";
    fillPackFigures(f, board_.app.pack(), board_.app.status(),
                    fw::Instant{static_cast<uint32_t>(board_.h.nowUs())}, fw::app::kDefaultLimits.staleAfter);
    f.cellSpreadMv = cellSpreadMv();
    return f;
  }

 private:
  // The gauge measures each cell across its sense lines: an open line reads 0 below and the sum above.
  void push() {
    int pack = 0;
    for (int c = 1; c <= 4; ++c) {
      board_.gauge.setCell(c, static_cast<uint16_t>(sensedMv(truth_, c, openCell_)));
      pack += truth_[static_cast<size_t>(c - 1)];
    }
    board_.gauge.setVoltage(static_cast<uint16_t>(pack));
  }

  std::vector<int> truth_ = std::vector<int>(4, 3700);
  int openCell_ = -1;
  bool intermittent_ = false;
  uint64_t tick_ = 0;
  ScanMeter meter_;
};

std::unique_ptr<ImageSim> make(const SimOptions&, std::string&) {
  return std::make_unique<Bq4050Sim>();
}

// Every BQ4050 image: the gauge on the G3507's SMBus with CAN out (the one board kind this family has).
ImageBinding bind(const ImageDescription& image) {
  if (image.board != "g3507_can")
    return {nullptr, "BQ4050 gas gauge over SMBus", "no host board of kind " + std::string(image.board)};
  return {&make, "BQ4050 gas gauge over SMBus", ""};
}

const ImageRegistrar kRegistrar{"bq4050", 1, &bind};

}  // namespace
}  // namespace bmssim
