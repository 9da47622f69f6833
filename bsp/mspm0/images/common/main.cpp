// Composition root of every image: bring the board up, let the image's application hook
// (images/<preset>/app_init.cpp) add its tasks, supervise the watchdog and run the scheduler forever.
#include "board.hpp"
#include "sched/scheduler.hpp"

void appInit(image::Board& board, fw::sched::Scheduler& scheduler);

int main() {
  image::bringUp();
  // The scheduler lives in this frame, which never ends: no global needs a constructor at start-up (the
  // reset handler runs none; linker/mspm0_sections.ld refuses any).
  image::Board& board = image::board();  // one call: board() lives in another translation unit
  fw::sched::Scheduler scheduler(board.clock);
  appInit(board, scheduler);
  scheduler.superviseWatchdog(board.watchdog, image::kWatchdogWindow);
  scheduler.run();
}
