// Application hook of the lp-mspm0l1306-bq76907 image. HOOK POINT: replace this file with the BQ7690x
// driver, the measurement/protection tasks and the SLCAN publisher; main.cpp calls appInit() once, after
// bringUp() and before the scheduler runs.
//
// Until then it runs a 500 ms heartbeat: LED toggle and one SLCAN frame per beat,
// "t7FF4<beat as 8 hex digits>\r" (standard ID 0x7FF, 4 data bytes), so a PC CAN tool shows it.
#include "board.hpp"
#include "common/heartbeat.hpp"
#include "sched/scheduler.hpp"

namespace {

constexpr fw::sched::TaskId kHeartbeatTask = 0;
uint8_t gLine[14] = {'t', '7', 'F', 'F', '4'};
volatile bool gLineBusy = false;  // the UART still owns gLine; cleared by the write's done Notify

void lineSent(void*, uint32_t) {
  gLineBusy = false;
}

void emitSlcan(uint32_t beat) {
  if (gLineBusy) return;  // the previous line is still on the wire: skip this beat
  image::toHex(beat, &gLine[5], 8);
  gLine[13] = '\r';
  gLineBusy = true;
  if (image::board().serial.write(gLine, fw::hal::Notify{lineSent, nullptr, 0}) != fw::Status::Ok)
    gLineBusy = false;
}

constinit image::Heartbeat heartbeat(emitSlcan);

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  heartbeat.start(scheduler, kHeartbeatTask, board.led, fw::ms(500));
}
