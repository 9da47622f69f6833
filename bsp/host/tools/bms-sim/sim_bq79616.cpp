// bms-sim binding of the lp-mspm0g3507-bq79616 image: the BQ79616 chain emulator on a simulated 1 Mbaud UART,
// nFAULT on a simulated edge input, CAN on a simulated 500 kbit/s controller, the fault output on a pin.
#include <memory>

#include "app/monitors/bq79616_app.hpp"
#include "app/protection/default_limits.hpp"
#include "bq79616/board.hpp"
#include "can_board_sim.hpp"
#include "drivers/bq79616/measurement.hpp"
#include "image_sim.hpp"
#include "pack_figures.hpp"

namespace bmssim {
namespace {

class Bq79616Sim final : public CanBoardSim<bsp::host::Bq79616Board> {
 public:
  explicit Bq79616Sim(const SimOptions& o) : CanBoardSim(configFor(o)) {
    truth_.assign(static_cast<size_t>(o.devices) * 16, 3700);
    for (int b = 0; b < o.devices; ++b) {
      for (int c = 1; c <= 16; ++c)
        push(b, c);
      for (int t = 1; t <= 2; ++t)
        setTempDeciK(b, t, 2982);
    }
  }

  int boards() const override { return board_.config.chain.devices; }
  int cellsPerBoard() const override { return 16; }
  int tempsPerBoard() const override { return 2; }
  bool hasCurrent() const override { return false; }

  void setCellMv(int board, int cell, int mv) override {
    truth_[static_cast<size_t>(board * 16 + cell - 1)] = mv;
    push(board, cell);
    push(board, cell - 1);  // an open wire below `cell` makes the cell below read this cell too
  }
  void setCurrentMa(int) override {}  // no current sensor on the chain
  void setCellCapacityMah(int mAh) override {
    bsp::host::CellModel model;
    model.cellUvPerMah = bsp::host::CellModel::uvPerMah(static_cast<uint32_t>(mAh));
    board_.emu.setCellModel(model);
  }
  std::vector<uint16_t> balancingCells() override {
    std::vector<uint16_t> out;
    for (size_t d = 0; d < board_.emu.size(); ++d)
      out.push_back(board_.emu.balancingCells(d));
    return out;
  }
  int cellSpreadMv() override {
    std::vector<int> mv;
    for (size_t d = 0; d < board_.emu.size(); ++d) {
      for (int c = 1; c <= 16; ++c)
        mv.push_back(board_.emu.cellNowMicrovolts(d, c) / 1000);
    }
    return spreadOf(mv);
  }
  Paths paths() const override { return pathsOfFaultOutput(board_.faultOut.level()); }
  void setTempDeciK(int board, int sensor, int deciK) override {
    // DIETEMP: 0.025 degC per LSB around 0 degC = 273.15 K (measurement.hpp).
    board_.emu.setDieTempRaw(static_cast<size_t>(board), sensor, static_cast<int16_t>(deciK * 4 - 10926));
  }
  void setCommLost(bool lost) override {
    for (size_t d = 0; d < board_.emu.size(); ++d)
      board_.emu.setMuted(d, lost);
  }
  void openWire(int board, int cell) override {
    openBoard_ = board, openCell_ = cell;
    push(board, cell);
    push(board, cell - 1);
    // The wire below `cell` is VC(cell - 1): the devices' own open-wire check sees it too.
    board_.emu.setOpenWire(static_cast<size_t>(board), cell - 1, true);
  }
  void setIntermittent(bool on) override { intermittent_ = on; }
  // Device faults (scenario.hpp), as the twin's board has them (bsp/twin/board/board.hpp).
  FaultLinks faultLinks() const override { return {false, true, true}; }
  void uartNoise(uint32_t ppm) override { board_.uart.noise().setPpm(ppm); }
  bool sendsTiLayout() const override {
    return fw::app::kTiLayout && board_.config.layout == fw::app::CanLayout::Ti;
  }

  void afterStep() override {
    if (intermittent_ && ++tick_ % 2 == 0) board_.emu.corruptResponse(0, 6, 0x10, 3);
    // Bus time is the UART's byte count at its byte time; a scan across a re-bring-up is not measured.
    const auto& st = board_.app.monitor().stats();
    meter_.observe(st.scans, st.recoveries,
                   (board_.uart.txBytes() + board_.uart.rxBytes()) * board_.uart.byteTimeUs(),
                   board_.app.monitor().chain().stats().commandFrames);
  }

  SimFigures figures() override {
    SimFigures f;
    const auto& st = board_.app.monitor().stats();
    fillScanFigures(f, st, board_.config.scanPeriod, meter_);
    const auto& link = board_.app.monitor().chain().stats();
    for (uint32_t e : link.errors)
      f.commErrors += e;
    f.recoveries = st.recoveries > 0 ? st.recoveries - 1 : 0;  // the first is the bring-up
    f.outputFrames = board_.can.sent().size();
    f.output = "can";
    fillPackFigures(f, board_.app.pack(), status(), fw::Instant{static_cast<uint32_t>(board_.h.nowUs())},
                    fw::app::kDefaultLimits.staleAfter);
    f.balancingCells = balancingCells();
    f.cellSpreadMv = cellSpreadMv();
    return f;
  }

 private:
  const fw::app::PublishStatus& status() const { return board_.app.status(); }

  // The voltage the device measures across `cell`: its own, or with an open sense wire below it, nothing
  // (the wire is gone) and the cell below reads both.
  void push(int board, int cell) {
    if (cell < 1 || cell > 16) return;
    const auto truth = std::span<const int>(truth_).subspan(static_cast<size_t>(board) * 16, 16);
    const int mv = sensedMv(truth, cell, board == openBoard_ ? openCell_ : -1);
    board_.emu.setCellMicrovolts(static_cast<size_t>(board), cell, mv * 1000);
  }

  static fw::app::Bq79616AppConfig configFor(const SimOptions& o) {
    auto c = bsp::host::Bq79616Board::configFor(static_cast<size_t>(o.devices));
    c.layout = o.tiLayout ? fw::app::CanLayout::Ti : fw::app::CanLayout::Native;
    return c;
  }

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

// Every BQ79616 image: a chain on the G3507's UART with CAN out (the one board kind this family has).
ImageBinding bind(const ImageDescription& image) {
  if (image.board != "g3507_can")
    return {nullptr, "BQ79616 daisy chain over UART", "no host board of kind " + std::string(image.board)};
  return {&make, "BQ79616 daisy chain over UART", ""};
}

const ImageRegistrar kRegistrar{"bq79616", 2, &bind};

}  // namespace
}  // namespace bmssim
