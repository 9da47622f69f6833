// Composition root of the lp-mspm0g3507-bq76952 image: bring the board up, let the application hook
// (app_init.cpp) add its tasks, supervise the watchdog and run the scheduler forever.
#include "board.hpp"
#include "sched/scheduler.hpp"

void appInit(image::Board& board, fw::sched::Scheduler& scheduler);

namespace {
fw::sched::Scheduler scheduler(image::board().clock);
}

int main() {
  image::bringUp();
  appInit(image::board(), scheduler);
  scheduler.superviseWatchdog(image::board().watchdog, image::kWatchdogWindow);
  scheduler.run();
}
