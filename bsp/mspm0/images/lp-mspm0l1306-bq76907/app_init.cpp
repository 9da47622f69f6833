// Application of the lp-mspm0l1306-bq76907 image: the BQ76907 monitor (probe, FET enable, scans), the
// firmware protection (FETs through the BQ76907, ALERT fast path) and SLCAN publishing on the back-channel
// UART (firmware/app/monitors/bq769x_app.hpp), with the start-up CONFIG_UPDATE of its settings table: the
// whole application, as the G3507 images run it.
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
#include "packs/selected.hpp"
#include "sched/scheduler.hpp"

namespace {

// The device settings of the pack this image is built from (BMS_PACK: regmaps/CMakeLists.txt).
static_assert(std::string_view(fw::pack::kDevice) == "bq76907", "BMS_PACK names a pack for another device");
constexpr auto kSettingRows = fw::app::bq7690xSettings(fw::pack::kDeviceSettings);
// Packed as the driver walks it (drivers/bq769x2 SettingsTable): only the packed bytes are in the image.
constexpr auto& kSettings = fw::drivers::bq769x2::packedSettings<kSettingRows>;

using App = fw::app::Bq769xApp<fw::drivers::bq769x2::Bq7690x, fw::drivers::bq769x2::Bq7690xMeasurement,
                               fw::app::SlcanPublisher>;

const fw::app::Bq769xAppConfig kConfig{.settings = kSettings,
                                       .cells = fw::pack::kCells,
                                       .soc = fw::app::kSoc ? &fw::pack::kSoc : nullptr,
                                       .currentLsbTenthMa = fw::pack::kCurrentLsbTenthMa,
                                       .storage = fw::pack::kStorage};

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
#if BSP_DEEP_IDLE
  // STANDBY1 between scans (options.cmake BSP_DEEP_IDLE; a board without the policy leaves it null).
  if (board.power != nullptr) scheduler.setPowerPolicy(*board.power);
#endif
  App& app = image::constructOnce<App>(scheduler, board.i2c, board.alert, board.serial, board.system, kConfig,
                                       fw::drivers::bq769x2::kBq76907);
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
