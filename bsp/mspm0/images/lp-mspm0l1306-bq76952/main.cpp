// Composition root of the lp-mspm0l1306-bq76952 image: bring the board up, let the application hook
// (app_init.cpp) add its tasks, supervise the watchdog (unless the image leaves it out:
// FW_WATCHDOG_SUPERVISION in the board header) and run the scheduler forever.
#include "board.hpp"
#include "sched/scheduler.hpp"

void appInit(image::Board& board, fw::sched::Scheduler& scheduler);

int main() {
  image::bringUp();
  // The scheduler lives in this frame, which never ends: no global needs a constructor at start-up (the
  // reset handler runs none; linker/mspm0_sections.ld refuses any).
  fw::sched::Scheduler scheduler(image::board().clock);
  appInit(image::board(), scheduler);
#if FW_WATCHDOG_SUPERVISION
  scheduler.superviseWatchdog(image::board().watchdog, image::kWatchdogWindow);
#endif
  scheduler.run();
}
