// Application of the lp-mspm0l1306-bq76952 image: the BQ76952 monitor (probe, FET enable, scans), the
// firmware protection (FETs through the BQ76952, ALERT fast path) and SLCAN publishing on the back-channel
// UART (firmware/app/monitors/bq769x_app.hpp), with the start-up CONFIG_UPDATE of its settings table: the
// whole application, as the G3507 images run it.
// The BQ76952's CFETOFF and DFETOFF inputs on PA10 and PA11 (bsp/mspm0/README.md "Connections"; PINCM11 and
// PINCM12, mspm0l130x.h IOMUX_PINCMn_PF_GPIOA_DIO(n-1)): protection drives them high while it holds that path
// off, so a path opens without I2C (app/monitors/fet_mailbox.hpp). Asserted from start-up until protection's
// first request.
#include <string_view>

#include "app/config.hpp"
#include "app/monitors/bq769x_app.hpp"
#include "app/monitors/bq769x_settings.hpp"
#include "board.hpp"
#include "common/construct_once.hpp"
#if FW_RECORD_STORE
#include "common/kept_records.hpp"
#else
#include "common/startup_info.hpp"
#endif
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
                               fw::app::SlcanPublisher>;

constinit bsp::mspm0::GpioOut chargeOff(bsp::mspm0::Pin{0, 10, 11});     // PA10 -> CFETOFF
constinit bsp::mspm0::GpioOut dischargeOff(bsp::mspm0::Pin{0, 11, 12});  // PA11 -> DFETOFF

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
#if BSP_DEEP_IDLE
  // STANDBY1 between scans (options.cmake BSP_DEEP_IDLE; a board without the policy leaves it null).
  if (board.power != nullptr) scheduler.setPowerPolicy(*board.power);
#endif
  chargeOff.init(true);
  dischargeOff.init(true);
  static constinit fw::app::Bq769xAppConfig config{.settings = kSettings,
                                                   .cells = fw::pack::kCells,
                                                   .soc = fw::app::kSoc ? &fw::pack::kSoc : nullptr,
                                                   .currentLsbTenthMa = fw::pack::kCurrentLsbTenthMa,
                                                   .storage = fw::pack::kStorage};
  config.chargeOffPin = &chargeOff;
  config.dischargeOffPin = &dischargeOff;
  App& app = image::constructOnce<App>(scheduler, board.i2c, board.alert, board.serial, board.system, config);
  // Startup message: the reset cause the board read, version, fault record. With the record store
  // (FW_RECORD_STORE, off in options.cmake until it fits): the records kept in flash restored first, this
  // reset's fault record written, the protection-log entries announced too.
#if FW_RECORD_STORE
  image::startKeptRecords(app, scheduler, board.system.identity().resetCause);
#else
  app.announceStartup(image::startupInfo(board.system.identity().resetCause));
#endif
  app.start();
}
