// Application of the lp-mspm0g3507-bq79616 image: the BQ79616 chain monitor, the firmware protection (fault
// output on PB26) and the CAN publisher (firmware/app/monitors/bq79616_app.hpp), on this board's UART, nFAULT
// and CAN. While the record store programs or erases the flash, its driver's wait watches nFAULT (PB0's edge)
// and asserts the fault output itself (bsp/mspm0/flashctl.hpp).
#include "app/monitors/bq79616_app.hpp"
#include "board.hpp"
#include "board_config.hpp"
#include "chip/mspm0g3507.hpp"
#include "common/construct_once.hpp"
#include "common/kept_records.hpp"
#include "sched/scheduler.hpp"

namespace {

// Zero-initialised: no start-up code touches the 7 KB of per-device buffers.
constinit fw::app::Bq79616Storage storage{};

const fw::app::Bq79616AppConfig kConfig{.chain = {.devices = image::config::kBq79616Devices}};

// nFAULT (PB0) during a flash program or erase: the fault output (PB26, high = fault: board_g3507_can.hpp)
// asserted, as protection does on the fault line (FaultPinActuator). In SRAM (the driver's wait reads it).
using Chip = bsp::mspm0::chip::Mspm0g3507;
constinit bsp::mspm0::FlashFaultWatch nfaultWatch =
    bsp::mspm0::faultLineWatch(Chip::kPb0, Chip::kPb26.port, Chip::kPb26.mask());

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  using App = fw::app::Bq79616App;
  App& app = image::constructOnce<App>(
      scheduler, App::Io{board.bq79616, board.nfault, board.can, board.faultOut, board.system}, kConfig,
      storage);
  // Records kept in flash restored, this reset's fault record written; the Startup message: the reset cause
  // the board read, version, fault record, protection-log entries
  nfaultWatch.armed = &app.pack().monitorRunning;  // the fault line is a fault exactly then (ProtectionTask)
  image::startKeptRecords(app, scheduler, board.system.identity().resetCause, &nfaultWatch);
  app.start();
}
