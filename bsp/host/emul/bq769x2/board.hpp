// Bq769xBoard: the BQ769x2-family boards on the host BSP, as bms-sim, `bmsctl trace bq76952|bq76907|bq76905
// app-start` and the application tests run them: the image's application
// (firmware/app/monitors/bq769x_app.hpp) with the monitor emulator on a 400 kHz I2C bus (4 ms stretch limit),
// the device's ALERT line into a pulled-up falling-edge input (as the device's configuration drives it), the
// MCU outputs to the BQ76952's CFETOFF / DFETOFF inputs (asserted from reset, as the images drive them), the
// output (CAN at 500 kbit/s on the G3507, SLCAN text at 115 200 Bd both ways on the L1306), a fault output
// asserted from reset (the L1306 boards have none: the application is then given no pin), and the MCU's
// identity and bootloader entry (SimSystem). The CAN controller's receive filter takes the command
// identifiers only, as the G3507 BSP sets the MCAN's. Every cell at 3.700 V. The
// application is started by the constructor; nothing happens until the harness runs. Header-only: users link
// fw_app_bq769x2 and emul_bq769x2.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>

#include "app/monitors/bq769x_app.hpp"
#include "app/monitors/bq769x_settings.hpp"
#include "bq769x2/emulator.hpp"
#include "sim/can.hpp"
#include "sim/harness.hpp"
#include "sim/i2c_bus.hpp"
#include "sim/peripherals.hpp"

namespace bsp::host {

// An MCU output wired to the BQ769x2's CFETOFF or DFETOFF input.
class FetOffWire final : public fw::hal::DigitalOut {
 public:
  FetOffWire(Bq769xEmulator& emu, bool& level, const bool& other, bool charge)
      : emu_(emu), level_(level), other_(other), charge_(charge) {}

 private:
  void doSet(bool high) override {
    level_ = high;
    emu_.setFetOffPins(charge_ ? level_ : other_, charge_ ? other_ : level_);
  }
  bool doLevel() const override { return level_; }
  Bq769xEmulator& emu_;
  bool& level_;
  const bool& other_;
  bool charge_;
};

template <class Driver, class Measurement, class Publisher, class Output>
struct Bq769xBoard {
  using App = fw::app::Bq769xApp<Driver, Measurement, Publisher>;

  // `driverArgs` (the BQ7690x variant) must outlive the board: the driver keeps a reference.
  template <class... DriverArgs>
  Bq769xBoard(Bq769xEmulator::Model model, std::span<const fw::drivers::bq769x2::Setting> settings,
              uint8_t cells, bool faultOutput, const DriverArgs&... driverArgs)
      : emu(h.clock, model),
        rows(settings),
        packedSettings(settings),
        config(makeConfig(model, packedSettings, cells, faultOutput ? &faultOut : nullptr,
                          model == Bq769xEmulator::Model::Bq76952 ? &cfetoff : nullptr,
                          model == Bq769xEmulator::Model::Bq76952 ? &dfetoff : nullptr)),
        app(h.sched, bus, alert, output, system, config, driverArgs...) {
    if constexpr (std::is_same_v<Output, SimCan>) {
      output.setFilter({fw::can::bms::kReceivedIds.begin(), fw::can::bms::kReceivedIds.end()});
    }
    bus.attach(0x08, emu);
    emu.onAlertLine([this](bool high) { alert.drive(high); });
    // The FET-off pins start asserted, as the images' GPIO init drives them: the paths stay off until
    // protection's first request.
    if (model == Bq769xEmulator::Model::Bq76952) emu.setFetOffPins(cfetoffLevel, dfetoffLevel);
    for (uint8_t c = 1; c <= cells; ++c)
      emu.setCellMv(c, 3700);
    app.start();
  }
  Bq769xBoard(const Bq769xBoard&) = delete;
  Bq769xBoard& operator=(const Bq769xBoard&) = delete;

  const fw::app::BoardSample& sample() const { return app.pack().boards[0]; }

  // The state of charge as the images compute it, with their EVM packs' parameters.
  static fw::app::Bq769xAppConfig makeConfig(Bq769xEmulator::Model model,
                                             fw::drivers::bq769x2::SettingsTable settings, uint8_t cells,
                                             fw::hal::DigitalOut* faultIndicator,
                                             fw::hal::DigitalOut* chargeOff,
                                             fw::hal::DigitalOut* dischargeOff) {
    fw::app::Bq769xAppConfig c{settings, cells};
    c.faultIndicator = faultIndicator;
    c.chargeOffPin = chargeOff;
    c.dischargeOffPin = dischargeOff;
    const bool bq76952 = model == Bq769xEmulator::Model::Bq76952;
    c.soc = bq76952 ? &fw::packs::bq76952_evm::kSoc : &fw::packs::bq76907_evm::kSoc;
    c.currentLsbTenthMa =
        bq76952 ? fw::packs::bq76952_evm::kCurrentLsbTenthMa : fw::packs::bq76907_evm::kCurrentLsbTenthMa;
    c.storage = bq76952 ? fw::packs::bq76952_evm::kStorage : fw::packs::bq76907_evm::kStorage;
    return c;
  }

  Harness h;
  SimI2cBus bus{h.clock, h.irq, {400000, fw::ms(4), fw::us(4)}};
  Bq769xEmulator emu;
  SimEdgeInput alert{h.irq, "alert", SimEdgeInput::Edge::Falling, true};
  SimDigitalOut faultOut{h.clock, true};
  // CFETOFF / DFETOFF (BQ76952 boards): MCU outputs into the emulator, asserted from reset.
  bool cfetoffLevel = true;
  bool dfetoffLevel = true;
  FetOffWire cfetoff{emu, cfetoffLevel, dfetoffLevel, true};
  FetOffWire dfetoff{emu, dfetoffLevel, cfetoffLevel, false};
  Output output{h.clock, h.irq};
  SimSystem system{h.clock};
  std::span<const fw::drivers::bq769x2::Setting> rows;  // the settings table as given
  fw::drivers::bq769x2::SettingsBuffer packedSettings;  // ... and packed, as the application takes it
  fw::app::Bq769xAppConfig config;
  App app;
};

// The boards of the images whose family this build's driver serves (FW_BQ769X_FAMILY; the host: both), with
// their images' settings tables (as the application builds with the host defaults).
#if FW_BQ769X_FAMILY != 2
// lp-mspm0g3507-bq76952: BQ76952, CAN, fault output.
using G3507Bq76952Board = Bq769xBoard<fw::drivers::bq769x2::Bq769x2, fw::drivers::bq769x2::Bq769x2Measurement,
                                      fw::app::CanPublisher, SimCan>;
inline std::unique_ptr<G3507Bq76952Board> makeG3507Bq76952Board() {
  return std::make_unique<G3507Bq76952Board>(Bq769xEmulator::Model::Bq76952, fw::app::kBq76952Settings, 16,
                                             true);
}
#endif
#if FW_BQ769X_FAMILY != 1
// lp-mspm0l1306-bq76907 (also with a BQ76905): SLCAN, no fault output.
using L1306Bq7690xBoard = Bq769xBoard<fw::drivers::bq769x2::Bq7690x, fw::drivers::bq769x2::Bq7690xMeasurement,
                                      fw::app::SlcanPublisher, SimSerial>;
inline std::unique_ptr<L1306Bq7690xBoard> makeL1306Bq7690xBoard(Bq769xEmulator::Model model) {
  const bool bq76907 = model == Bq769xEmulator::Model::Bq76907;
  return std::make_unique<L1306Bq7690xBoard>(
      model, bq76907 ? std::span(fw::app::kBq76907Settings) : std::span(fw::app::kBq76905Settings),
      bq76907 ? 7 : 5, false, bq76907 ? fw::drivers::bq769x2::kBq76907 : fw::drivers::bq769x2::kBq76905);
}
#endif

}  // namespace bsp::host
