// Application of the lp-mspm0l1306-bq76907 image: the BQ76907 monitor (probe, FET enable, scans), the
// firmware protection (FETs through the BQ76907, ALERT fast path) and SLCAN publishing on the back-channel
// UART (firmware/app/bq769x_app.hpp), built without what the 8 KiB budget has no room for (images.cmake,
// bsp/mspm0/README.md "What the L1306 images leave out"): PackSummary is the only SLCAN message, and the
// start-up CONFIG_UPDATE of its settings table is left out, so the table below is empty unless it is built.
#include "app/bq769x_app.hpp"
#include "app/bq769x_settings.hpp"
#include "board.hpp"
#include "sched/scheduler.hpp"

namespace {

using App = fw::app::Bq769xApp<fw::drivers::bq769x2::Bq7690x, fw::drivers::bq769x2::Bq7690xMeasurement,
                               fw::app::SlcanPublisher>;

// The settings table only where the image applies it (FW_BQ769X_CONFIG_UPDATE,
// bsp/mspm0/images/images.cmake).
const fw::app::Bq769xAppConfig kConfig{fw::app::kConfigUpdate
                                           ? std::span(fw::app::kBq76907Settings)
                                           : std::span<const fw::drivers::bq769x2::Setting>{},
                                       7};

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  static App app(scheduler, board.i2c, board.alert, board.serial, kConfig, fw::drivers::bq769x2::kBq76907);
  app.start();
}
