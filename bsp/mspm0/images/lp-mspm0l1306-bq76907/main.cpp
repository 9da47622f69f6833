// Composition root of the lp-mspm0l1306-bq76907 image: bring the board up, let the application hook
// (app_init.cpp) add its tasks, supervise the watchdog (unless the image leaves it out:
// FW_WATCHDOG_SUPERVISION in the board header) and run the scheduler forever.
#include "board.hpp"
#include "sched/scheduler.hpp"

void appInit(image::Board& board, fw::sched::Scheduler& scheduler);

namespace {
fw::sched::Scheduler scheduler(image::board().clock);
}

int main() {
  image::bringUp();
  appInit(image::board(), scheduler);
#if FW_WATCHDOG_SUPERVISION
  scheduler.superviseWatchdog(image::board().watchdog, image::kWatchdogWindow);
#endif
  scheduler.run();
}
