// Application of the lp-mspm0g3507-bq76907 image: the BQ76907 monitor (probe, FET enable, scans), the
// firmware protection (FETs through the BQ76907, the fault output PB26 high while it holds a path off) and
// CAN publishing (firmware/app/monitors/bq769x_app.hpp). The BQ7690x has no CFETOFF/DFETOFF inputs.
#include <string_view>

#include "app/monitors/bq769x_app.hpp"
#include "app/monitors/bq769x_settings.hpp"
#include "board.hpp"
#include "common/construct_once.hpp"
#include "common/startup_info.hpp"
#include "packs/selected.hpp"
#include "sched/scheduler.hpp"

namespace {

// The device settings of the pack this image is built from (BMS_PACK: regmaps/CMakeLists.txt).
static_assert(std::string_view(fw::pack::kDevice) == "bq76907", "BMS_PACK names a pack for another device");
constexpr auto kSettingRows = fw::app::bq7690xSettings(fw::pack::kDeviceSettings);
// Packed as the driver walks it (drivers/bq769x2 SettingsTable): only the packed bytes are in the image.
constexpr auto& kSettings = fw::drivers::bq769x2::packedSettings<kSettingRows>;

using App = fw::app::Bq769xApp<fw::drivers::bq769x2::Bq7690x, fw::drivers::bq769x2::Bq7690xMeasurement,
                               fw::app::CanPublisher>;

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  // The board holds the fault output asserted from reset until protection first decides (bringUp()).
  static constinit fw::app::Bq769xAppConfig config{.settings = kSettings,
                                                   .cells = fw::pack::kCells,
                                                   .soc = fw::app::kSoc ? &fw::pack::kSoc : nullptr,
                                                   .currentLsbTenthMa = fw::pack::kCurrentLsbTenthMa};
  config.faultIndicator = &board.faultOut;
  App& app = image::constructOnce<App>(scheduler, board.i2c, board.alert, board.can, board.system, config,
                                       fw::drivers::bq769x2::kBq76907);
  // Startup message: the reset cause the board read, version, fault record
  app.announceStartup(image::startupInfo(board.system.identity().resetCause));
  app.start();
}
