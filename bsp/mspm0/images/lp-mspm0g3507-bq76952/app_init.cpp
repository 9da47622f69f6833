// Application of the lp-mspm0g3507-bq76952 image: the BQ76952 monitor (probe, one CONFIG_UPDATE, FET enable,
// scans), the firmware protection (FETs through the BQ76952, the fault output PB26 high while it holds a
// path off) and CAN publishing (firmware/app/monitors/bq769x_app.hpp).
// The BQ76952's CFETOFF and DFETOFF inputs on PB2 and PB3 (bsp/mspm0/README.md "Connections"; PINCM15 and
// PINCM16, mspm0g350x.h IOMUX_PINCM15_PF_GPIOB_DIO02 / PINCM16_PF_GPIOB_DIO03): protection drives them high
// while it holds that path off, so a path opens without I2C (app/monitors/fet_mailbox.hpp). Asserted from
// start-up until protection's first request.
#include <string_view>

#include "app/monitors/bq769x_app.hpp"
#include "app/monitors/bq769x_settings.hpp"
#include "board.hpp"
#include "common/construct_once.hpp"
#include "common/kept_records.hpp"
#include "gpio.hpp"
#include "packs/selected.hpp"
#include "sched/scheduler.hpp"

namespace {

// The device settings of the pack this image is built from (BMS_PACK: regmaps/CMakeLists.txt).
static_assert(std::string_view(fw::pack::kDevice) == "bq76952", "BMS_PACK names a pack for another device");
constexpr auto kSettingRows = fw::app::bq76952Settings(fw::pack::kDeviceSettings);
// Packed as the driver walks it (drivers/bq769x2 SettingsTable): only the packed bytes are in the image.
constexpr auto& kSettings = fw::drivers::bq769x2::packedSettings<kSettingRows>;

using App = fw::app::Bq769xApp<fw::drivers::bq769x2::Bq769x2, fw::drivers::bq769x2::Bq769x2Measurement,
                               fw::app::CanPublisher>;

constinit bsp::mspm0::GpioOut chargeOff(bsp::mspm0::Pin{1, 2, 15});     // PB2 -> CFETOFF
constinit bsp::mspm0::GpioOut dischargeOff(bsp::mspm0::Pin{1, 3, 16});  // PB3 -> DFETOFF

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  chargeOff.init(true);
  dischargeOff.init(true);
  // The board holds the fault output asserted from reset until protection first decides (bringUp()).
  static constinit fw::app::Bq769xAppConfig config{.settings = kSettings,
                                                   .cells = fw::pack::kCells,
                                                   .soc = fw::app::kSoc ? &fw::pack::kSoc : nullptr,
                                                   .currentLsbTenthMa = fw::pack::kCurrentLsbTenthMa,
                                                   .storage = fw::pack::kStorage};
  config.faultIndicator = &board.faultOut;
  config.chargeOffPin = &chargeOff;
  config.dischargeOffPin = &dischargeOff;
  App& app = image::constructOnce<App>(scheduler, board.i2c, board.alert, board.can, board.system, config);
  // Records kept in flash restored, this reset's fault record written; the Startup message: the reset cause
  // the board read, version, fault record, protection-log entries
  image::startKeptRecords(app, scheduler, board.system.identity().resetCause);
  app.start();
}
