// Composition root of every image: bring the board up, let the image's application hook
// (images/<preset>/app_init.cpp) add its tasks, supervise the watchdog (unless the image leaves it out:
// FW_WATCHDOG_SUPERVISION=0 in images.cmake) and run the scheduler forever.
#include "board.hpp"
#include "sched/scheduler.hpp"

#ifndef FW_WATCHDOG_SUPERVISION
#define FW_WATCHDOG_SUPERVISION 1
#endif

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
