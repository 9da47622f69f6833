// bms-sim binding of the lp-mspm0g3507-bq79616 image: the BQ79616 chain emulator on a simulated 1 Mbaud UART,
// nFAULT on a simulated edge input, CAN on a simulated 500 kbit/s controller, the fault output on a pin.
#include <memory>

#include "app/bq79616_app.hpp"
#include "app/default_limits.hpp"
#include "bq79616/chain_emulator.hpp"
#include "drivers/bq79616/measurement.hpp"
#include "image_sim.hpp"
#include "pack_figures.hpp"
#include "sim/can.hpp"
#include "sim/peripherals.hpp"
#include "sim/uart.hpp"

namespace bmssim {
namespace {

class Bq79616Sim final : public ImageSim {
 public:
  Bq79616Sim(const SimOptions& o)
      : emulator_(h_.clock, uart_, static_cast<size_t>(o.devices)),
        nfault_(h_.irq, "nfault", bsp::host::SimEdgeInput::Edge::Falling, true),
        can_(h_.clock, h_.irq, 500000, 8),
        faultOut_(h_.clock, true) {  // the board asserts it from reset
    uart_.attach(emulator_);
    emulator_.attachFaultPin(nfault_);
    config_.chain.devices = static_cast<uint8_t>(o.devices);
    config_.layout = o.tiLayout ? fw::app::CanLayout::Ti : fw::app::CanLayout::Native;
    truth_.assign(static_cast<size_t>(o.devices) * 16, 3700);
    for (int b = 0; b < o.devices; ++b) {
      for (int c = 1; c <= 16; ++c)
        push(b, c);
      for (int t = 1; t <= 2; ++t)
        setTempDeciK(b, t, 2982);
    }
    app_ = std::make_unique<fw::app::Bq79616App>(
        h_.sched, fw::app::Bq79616App::Io{uart_, nfault_, can_, faultOut_}, config_, *storage_);
    app_->start();
  }

  int boards() const override { return config_.chain.devices; }
  int cellsPerBoard() const override { return 16; }
  int tempsPerBoard() const override { return 2; }
  bool hasCurrent() const override { return false; }

  void setCellMv(int board, int cell, int mv) override {
    truth_[static_cast<size_t>(board * 16 + cell - 1)] = mv;
    push(board, cell);
    push(board, cell - 1);  // an open wire below `cell` makes the cell below read this cell too
  }
  void setCurrentMa(int) override {}
  void setTempDeciK(int board, int sensor, int deciK) override {
    // DIETEMP: 0.025 degC per LSB around 0 degC = 273.15 K (measurement.hpp).
    emulator_.setDieTempRaw(static_cast<size_t>(board), sensor, static_cast<int16_t>(deciK * 4 - 10926));
  }
  void setCommLost(bool lost) override {
    for (size_t d = 0; d < emulator_.size(); ++d)
      emulator_.setMuted(d, lost);
  }
  void openWire(int board, int cell) override {
    openBoard_ = board, openCell_ = cell;
    push(board, cell);
    push(board, cell - 1);
  }
  void setIntermittent(bool on) override { intermittent_ = on; }
  bool busOff() override {
    can_.injectBusOff();
    return true;
  }

  void afterStep() override {
    if (intermittent_ && ++tick_ % 2 == 0) emulator_.corruptResponse(0, 6, 0x10, 3);
    // Bus time is the UART's byte count at its byte time; a scan across a re-bring-up is not measured.
    const auto& st = app_->monitor().stats();
    meter_.observe(st.scans, st.recoveries, (uart_.txBytes() + uart_.rxBytes()) * uart_.byteTimeUs(),
                   app_->monitor().chain().stats().commandFrames);
  }

  bsp::host::Harness& harness() override { return h_; }

  SimFigures figures() override {
    SimFigures f;
    const auto& st = app_->monitor().stats();
    fillScanFigures(f, st, config_.scanPeriod, meter_);
    const auto& link = app_->monitor().chain().stats();
    for (uint32_t e : link.errors)
      f.commErrors += e;
    f.recoveries = st.recoveries > 0 ? st.recoveries - 1 : 0;  // the first is the bring-up
    f.outputFrames = can_.sent().size();
    f.output = "can";
    fillPackFigures(f, app_->pack(), status(), fw::Instant{static_cast<uint32_t>(h_.nowUs())},
                    fw::app::kDefaultLimits.staleAfter);
    return f;
  }

  std::vector<fw::app::ProtectionRecord> protectionLog() const override { return protectionLogOf(*app_); }
  std::vector<SentFrame> frames() const override { return canFrames(can_); }

 private:
  const fw::app::PublishStatus& status() const { return app_->status(); }

  // The voltage the device measures across `cell`: its own, or with an open sense wire below it, nothing
  // (the wire is gone) and the cell below reads both.
  void push(int board, int cell) {
    if (cell < 1 || cell > 16) return;
    const auto truth = std::span<const int>(truth_).subspan(static_cast<size_t>(board) * 16, 16);
    const int mv = sensedMv(truth, cell, board == openBoard_ ? openCell_ : -1);
    emulator_.setCellMicrovolts(static_cast<size_t>(board), cell, mv * 1000);
  }

  bsp::host::Harness h_;
  bsp::host::SimUart uart_{h_.clock, h_.irq, 1000000};
  bsp::host::Bq79616ChainEmulator emulator_;
  bsp::host::SimEdgeInput nfault_;
  bsp::host::SimCan can_;
  bsp::host::SimDigitalOut faultOut_;
  fw::app::Bq79616AppConfig config_;
  std::unique_ptr<fw::app::Bq79616Storage> storage_ = std::make_unique<fw::app::Bq79616Storage>();
  std::unique_ptr<fw::app::Bq79616App> app_;
  std::vector<int> truth_;
  int openBoard_ = -1, openCell_ = -1;
  bool intermittent_ = false;
  uint64_t tick_ = 0;
  ScanMeter meter_;
};

std::unique_ptr<ImageSim> make(const SimOptions& o, std::string& error) {
  if (o.devices < 1 || o.devices > 64) {
    error = "--devices must be 1..64 for a BQ79616 chain";
    return nullptr;
  }
  return std::make_unique<Bq79616Sim>(o);
}

const ImageRegistrar kRegistrar{
    {"lp-mspm0g3507-bq79616", "BQ79616 daisy chain over UART, CAN out", 2, &make}};

}  // namespace
}  // namespace bmssim
