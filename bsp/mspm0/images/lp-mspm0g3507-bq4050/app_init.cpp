// Application of the lp-mspm0g3507-bq4050 image: the BQ4050 gauge monitor (probe with PEC detection, scans),
// the firmware protection (fault output on PB26) and CAN publishing (firmware/app/monitors/bq4050_app.hpp).
#include "app/monitors/bq4050_app.hpp"
#include "board.hpp"
#include "common/construct_once.hpp"
#include "common/kept_records.hpp"
#include "packs/selected.hpp"
#include "sched/scheduler.hpp"

namespace {

const fw::app::Bq4050AppConfig kConfig{.storage = fw::pack::kStorage};

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  using App = fw::app::Bq4050App;
  App& app = image::constructOnce<App>(scheduler, App::Io{board.i2c, board.can, board.faultOut, board.system},
                                       kConfig);
  // Records kept in flash restored, this reset's fault record written; the Startup message: the reset cause
  // the board read, version, fault record, protection-log entries
  image::startKeptRecords(app, scheduler, board.system.identity().resetCause);
  app.start();
}
