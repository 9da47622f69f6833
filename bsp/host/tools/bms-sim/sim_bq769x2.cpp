// bms-sim bindings of the BQ769x2-family images: each image's host board (bq769x2/board.hpp: the BQ76952 or
// BQ76907 emulator on a simulated 400 kHz I2C bus, ALERT on a simulated edge input, and SLCAN text on a
// simulated 115 200 Bd UART (L1306 images) or CAN on a simulated 500 kbit/s controller with the fault output
// (G3507 image)).
#include <cstdio>
#include <memory>

#include "app/protection/default_limits.hpp"
#include "bq769x2/board.hpp"
#include "image_sim.hpp"
#include "pack_figures.hpp"

namespace bmssim {
namespace {

namespace b769 = fw::drivers::bq769x2;
using Emulator = bsp::host::Bq769xEmulator;

// The emulated pack and its link, common to the three images: the image's board (bq769x2/board.hpp).
template <class Driver, class Measurement, class Publisher, class Output>
class Bq769xSim final : public ImageSim {
 public:
  using Board = bsp::host::Bq769xBoard<Driver, Measurement, Publisher, Output>;

  template <class... DriverArgs>
  Bq769xSim(Emulator::Model model, uint8_t cells, std::span<const b769::Setting> settings, bool faultOutput,
            const DriverArgs&... args)
      : board_(std::make_unique<Board>(model, settings, cells, faultOutput, args...)),
        cells_(cells),
        truth_(cells, 3700) {}

  int boards() const override { return 1; }
  int cellsPerBoard() const override { return cells_; }
  int tempsPerBoard() const override { return fw::app::tempsOf(static_cast<Measurement*>(nullptr)); }
  bool hasCurrent() const override { return true; }

  void setCellMv(int, int cell, int mv) override {
    truth_[static_cast<size_t>(cell - 1)] = mv;
    push(cell);
    push(cell - 1);  // an open wire below `cell` makes the cell below read this cell too
  }
  void setCurrentMa(int ma) override { board_->emu.setCurrentMa(ma); }
  void setCellCapacityMah(int mAh) override {
    auto model = board_->emu.cellModel();
    model.cellUvPerMah = bsp::host::CellModel::uvPerMah(static_cast<uint32_t>(mAh));
    board_->emu.setCellModel(model);
  }
  std::vector<uint16_t> balancingCells() override { return {board_->emu.balancing()}; }
  int cellSpreadMv() override {
    std::vector<int> mv;
    for (int c = 1; c <= cells_; ++c)
      mv.push_back(board_->emu.cellNowMv(static_cast<uint8_t>(c)));
    return spreadOf(mv);
  }
  // The monitor's own FETs (series CHG and DSG: the CHG FET blocks charging, its body diode still passes a
  // discharge, and the DSG FET the reverse; SLUUBY2B / SLUUBY1B "body diode protection", SLUSE97 for the
  // BQ7690x's CHG and DSG drivers). The G3507 image's fault output only indicates.
  Paths paths() const override { return {board_->emu.chgFet(), board_->emu.dsgFet()}; }
  void setTempDeciK(int, int sensor, int deciK) override {
    // Sensor 1 is the internal one (BQ7690x: whole degC), 2 and 3 are TS1 and TS3.
    if (sensor == 1) {
      const bool bq7690x = board_->emu.model() != Emulator::Model::Bq76952;
      board_->emu.setIntTemp(bq7690x ? b769::rawTemperature(b769::map7690x::cmd::IntTemperature, deciK)
                                     : b769::rawTemperature(b769::map::cmd::IntTemperature, deciK));
    } else {
      board_->emu.setTs(static_cast<uint8_t>(sensor == 2 ? 0 : 2), static_cast<int16_t>(deciK));
    }
  }
  void setCommLost(bool lost) override { board_->emu.setMuted(lost); }
  void openWire(int, int cell) override {
    openCell_ = cell;
    push(cell);
    push(cell - 1);
  }
  void setIntermittent(bool on) override { intermittent_ = on; }
  bool busOff() override {
    if constexpr (std::is_same_v<Output, bsp::host::SimCan>) {
      board_->output.injectBusOff();
      return true;
    } else {
      return false;
    }
  }
  std::vector<BusOffSpan> busOffLog() const override {
    if constexpr (std::is_same_v<Output, bsp::host::SimCan>) {
      return busOffSpans(board_->output);
    } else {
      return {};
    }
  }
  // Device faults (scenario.hpp), as the twin's board has them (bsp/twin/board/board.hpp).
  FaultLinks faultLinks() const override { return {true, false, std::is_same_v<Output, bsp::host::SimCan>}; }
  void i2cStretch(fw::Duration perByte) override { board_->bus.setDeviceStretch(perByte); }
  // The BQ76952 / BQ7690x resets its interface after SCL has been low 2 s (SLUSE13B 14).
  void stuckScl() override { board_->bus.holdSclLow(board_->h.nowUs() + 2000000); }
  void stuckSda() override { board_->bus.holdSdaLow(8); }
  void canErrorFrames(uint32_t attempts) override {
    if constexpr (std::is_same_v<Output, bsp::host::SimCan>) board_->output.injectErrorFrames(attempts);
  }

  bool canSend(const fw::hal::CanFrame& f) override {
    if constexpr (std::is_same_v<Output, bsp::host::SimCan>) {
      board_->output.peerSend(f);
      return true;
    } else {
      return false;
    }
  }
  bool canFlood(std::function<std::optional<fw::hal::CanFrame>()> source) override {
    if constexpr (std::is_same_v<Output, bsp::host::SimCan>) {
      board_->output.setPeerSource(std::move(source));
      return true;
    } else {
      return false;
    }
  }
  bool serialSend(std::string_view bytes) override {
    if constexpr (std::is_same_v<Output, bsp::host::SimSerial>) {
      board_->output.peerSend(bytes);
      return true;
    } else {
      return false;
    }
  }
  size_t serialBacklog() const override {
    if constexpr (std::is_same_v<Output, bsp::host::SimSerial>) {
      return board_->output.backlog();
    } else {
      return 0;
    }
  }

  void afterStep() override {
    pumpSerialFlood();
    // An intermittent link: the device drops off the bus for 250 ms of every 350 ms, so scans fail in runs
    // and the data ages past the stale limit between the good ones. (Silent bit flips are not used here:
    // without CRC they are undetectable by design; the CRC-mode tests cover them.)
    if (intermittent_) board_->emu.setMuted((tick_++ % 350) < 250);
    if (!intermittent_ && tick_ != 0) {
      board_->emu.setMuted(false);
      tick_ = 0;
    }
    meter_.observe(board_->app.monitor().stats().scans, 0, board_->bus.busTimeUs(),
                   board_->bus.transactions());
  }

  bsp::host::Harness& harness() override { return board_->h; }

  SimFigures figures() override {
    SimFigures f;
    const auto& st = board_->app.monitor().stats();
    fillScanFigures(f, st, board_->config.scanPeriod, meter_);
    for (uint16_t e : board_->app.monitor().driver().stats().errors)
      f.commErrors += e;
    f.recoveries = st.setupAttempts > 0 ? st.setupAttempts - 1 : 0;
    if constexpr (std::is_same_v<Output, bsp::host::SimCan>) {
      f.outputFrames = board_->output.sent().size();
      f.output = "can";
    } else {
      f.outputFrames = slcanFrames().size();
      f.output = "slcan";
    }
    fillPackFigures(f, board_->app.pack(), board_->app.status(),
                    fw::Instant{static_cast<uint32_t>(board_->h.nowUs())},
                    fw::app::kDefaultLimits.staleAfter);
    f.balancingCells = balancingCells();
    f.cellSpreadMv = cellSpreadMv();
    f.emulatorChargeMah = static_cast<double>(board_->emu.trueChargeMaUs()) / 3.6e9;
    return f;
  }

  std::vector<fw::app::ProtectionRecord> protectionLog() const override {
    return protectionLogOf(board_->app);
  }

  std::vector<SentFrame> frames() const override {
    if constexpr (std::is_same_v<Output, bsp::host::SimCan>) {
      return canFrames(board_->output);
    } else {
      return slcanFrames();
    }
  }
  std::optional<SentText> slcanText() const override {
    if constexpr (std::is_same_v<Output, bsp::host::SimSerial>) {
      return SentText{board_->output.text(), board_->output.writeTimes()};
    } else {
      return std::nullopt;
    }
  }

 private:
  // The SLCAN text the firmware wrote, decoded back into frames ("t<iii><l><dd..>\r", other lines skipped);
  // each frame's time is
  // when the write that carried it left the wire (the publisher writes one line at a time; an answer to a
  // command is one write of several lines). The text and its writes only grow (bms-sim never clears them),
  // so each call parses only the lines completed since the last one.
  const std::vector<SentFrame>& slcanFrames() const {
    if constexpr (std::is_same_v<Output, bsp::host::SimSerial>) {
      const std::string& text = board_->output.text();
      const auto& starts = board_->output.writeStarts();
      const auto& times = board_->output.writeTimes();
      size_t pos = slcanParsed_;
      // Lines end with CR, or with BEL (the answer to a line the board refused, which has no CR).
      for (size_t end; (end = text.find_first_of("\r\a", pos)) != std::string::npos; pos = end + 1) {
        const std::string line = text.substr(pos, end - pos);
        if (line.size() < 5 || (line[0] != 't' && line[0] != 'T')) continue;
        const bool ext = line[0] == 'T';
        const size_t idLen = ext ? 8 : 3;
        SentFrame f{0, static_cast<uint32_t>(std::stoul(line.substr(1, idLen), nullptr, 16)), ext, {}};
        const int dlc = line[1 + idLen] - '0';
        for (int i = 0; i < dlc; ++i) {
          f.data.push_back(static_cast<uint8_t>(std::stoul(line.substr(2 + idLen + 2 * i, 2), nullptr, 16)));
        }
        while (slcanWrite_ + 1 < starts.size() && starts[slcanWrite_ + 1] <= pos)
          ++slcanWrite_;
        f.timeUs = times[slcanWrite_];
        slcan_.push_back(f);
      }
      slcanParsed_ = pos;
    }
    return slcan_;
  }

  void push(int cell) {
    if (cell < 1 || cell > cells_) return;
    board_->emu.setCellMv(static_cast<uint8_t>(cell),
                          static_cast<int16_t>(sensedMv(truth_, cell, openCell_)));
  }

  std::unique_ptr<Board> board_;
  int cells_;
  std::vector<int> truth_;
  int openCell_ = -1;
  bool intermittent_ = false;
  uint64_t tick_ = 0;
  ScanMeter meter_;
  // slcanFrames()' cache: the frames decoded so far, how much of the text they cover, the write the last one
  // came in.
  mutable std::vector<SentFrame> slcan_;
  mutable size_t slcanParsed_ = 0;
  mutable size_t slcanWrite_ = 0;
};

// The host board of an image: its board kind picks the output (SLCAN on the L1306 boards, CAN with the fault
// output on the G3507), its device the driver, emulator, cells and settings (the device's EVM pack, as
// bq769x2/board.hpp builds them).
template <class Publisher, class Output>
struct BoardKind {
  static constexpr bool kFaultOutput = std::is_same_v<Output, bsp::host::SimCan>;
#if FW_BQ769X_FAMILY != 2
  static std::unique_ptr<ImageSim> bq76952(const SimOptions&, std::string&) {
    return std::make_unique<Bq769xSim<b769::Bq769x2, b769::Bq769x2Measurement, Publisher, Output>>(
        Emulator::Model::Bq76952, 16, fw::app::kBq76952Settings, kFaultOutput);
  }
#endif
#if FW_BQ769X_FAMILY != 1
  static std::unique_ptr<ImageSim> bq76907(const SimOptions&, std::string&) {
    return std::make_unique<Bq769xSim<b769::Bq7690x, b769::Bq7690xMeasurement, Publisher, Output>>(
        Emulator::Model::Bq76907, 7, fw::app::kBq76907Settings, kFaultOutput, b769::kBq76907);
  }
#endif
  static ImageBinding bind(std::string_view device) {
#if FW_BQ769X_FAMILY != 2
    if (device == "bq76952") return {&bq76952, "BQ76952 over I2C", ""};
#endif
#if FW_BQ769X_FAMILY != 1
    if (device == "bq76907") return {&bq76907, "BQ76907 over I2C", ""};
#endif
    // A build for one device family (FW_BQ769X_FAMILY, an image's simulator) has only that family's front
    // end.
    return {nullptr, std::string(device), "this build's driver does not serve the " + std::string(device)};
  }
};

ImageBinding bind(const ImageDescription& image) {
  if (image.board == "l1306_i2c_slcan")
    return BoardKind<fw::app::SlcanPublisher, bsp::host::SimSerial>::bind(image.device);
  if (image.board == "g3507_can")
    return BoardKind<fw::app::CanPublisher, bsp::host::SimCan>::bind(image.device);
  return {nullptr, std::string(image.device), "no host board of kind " + std::string(image.board)};
}

const ImageRegistrar kRegistrar{"bq769x2", 1, &bind};

}  // namespace
}  // namespace bmssim
