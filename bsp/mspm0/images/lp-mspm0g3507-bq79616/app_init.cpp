// Application of the lp-mspm0g3507-bq79616 image: the BQ79616 chain monitor, the firmware protection (fault
// output on PB26) and the CAN publisher (firmware/app/monitors/bq79616_app.hpp), on this board's UART, nFAULT
// and CAN.
#include "app/monitors/bq79616_app.hpp"
#include "board.hpp"
#include "board_config.hpp"
#include "common/construct_once.hpp"
#include "common/startup_info.hpp"
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
  // Startup message: the reset cause the board read, version, fault record
  app.announceStartup(image::startupInfo(board.system.identity().resetCause));
  app.start();
}
