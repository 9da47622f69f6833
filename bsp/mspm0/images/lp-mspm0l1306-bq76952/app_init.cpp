// Application of the lp-mspm0l1306-bq76952 image: the BQ76952 monitor (probe, FET enable, scans), the
// firmware protection (FETs through the BQ76952, ALERT fast path) and SLCAN publishing on the back-channel
// UART (firmware/app/bq769x_app.hpp), built without what the 8 KiB budget has no room for (images.cmake,
// bsp/mspm0/README.md "What the L1306 images leave out"): PackSummary is the only SLCAN message, and the
// start-up CONFIG_UPDATE of seed 000's configuration is left out, so the table below is empty unless it is
// built.
#include "app/bq769x_app.hpp"
#include "app/bq769x_settings.hpp"
#include "board.hpp"
#include "sched/scheduler.hpp"

namespace {

using App = fw::app::Bq769xApp<fw::drivers::bq769x2::Bq769x2, fw::drivers::bq769x2::Bq769x2Measurement,
                               fw::app::SlcanPublisher>;

// The settings table only where the image applies it (FW_BQ769X_CONFIG_UPDATE,
// bsp/mspm0/images/images.cmake).
const fw::app::Bq769xAppConfig kConfig{fw::app::kConfigUpdate
                                           ? std::span(fw::app::kBq76952Settings)
                                           : std::span<const fw::drivers::bq769x2::Setting>{},
                                       16};

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  static App app(scheduler, board.i2c, board.alert, board.serial, kConfig);
  app.start();
}
