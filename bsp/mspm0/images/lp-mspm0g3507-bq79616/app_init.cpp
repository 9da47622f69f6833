// Application of the lp-mspm0g3507-bq79616 image: the BQ79616 chain monitor, the firmware protection (fault
// output on PB26) and the CAN publisher (firmware/app/monitors/bq79616_app.hpp), on this board's UART, nFAULT
// and CAN.
#include "app/monitors/bq79616_app.hpp"
#include "board.hpp"
#include "board_config.hpp"
#include "common/construct_once.hpp"
#include "common/kept_records.hpp"
#include "sched/scheduler.hpp"

namespace {

// Zero-initialised: no start-up code touches the 7 KB of per-device buffers.
constinit fw::app::Bq79616Storage storage{};

const fw::app::Bq79616AppConfig kConfig{.chain = {.devices = image::config::kBq79616Devices}};

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  using App = fw::app::Bq79616App;
  App& app = image::constructOnce<App>(
      scheduler, App::Io{board.bq79616, board.nfault, board.can, board.faultOut, board.system}, kConfig,
      storage);
  // Records kept in flash restored, this reset's fault record written; the Startup message: the reset cause
  // the board read, version, fault record, protection-log entries
  image::startKeptRecords(app, scheduler, board.system.identity().resetCause);
  app.start();
}
