// Application of the lp-mspm0g3507-bq76952 image: the BQ76952 monitor (probe, one CONFIG_UPDATE, FET enable,
// scans), the firmware protection (FETs through the BQ76952, the fault output PB26 high while it holds a
// path off) and CAN publishing (firmware/app/monitors/bq769x_app.hpp).
#include "app/monitors/bq769x_app.hpp"
#include "app/monitors/bq769x_settings.hpp"
#include "board.hpp"
#include "common/construct_once.hpp"
#include "common/startup_info.hpp"
#include "sched/scheduler.hpp"

namespace {

using App = fw::app::Bq769xApp<fw::drivers::bq769x2::Bq769x2, fw::drivers::bq769x2::Bq769x2Measurement,
                               fw::app::CanPublisher>;

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  // The board holds the fault output asserted from reset until protection first decides (bringUp()).
  static constinit fw::app::Bq769xAppConfig config{fw::app::kBq76952Settings, 16};
  config.faultIndicator = &board.faultOut;
  App& app = image::constructOnce<App>(scheduler, board.i2c, board.alert, board.can, board.system, config);
  // Startup message: the reset cause the board read, version, fault record
  app.announceStartup(image::startupInfo(board.system.identity().resetCause));
  app.start();
}
