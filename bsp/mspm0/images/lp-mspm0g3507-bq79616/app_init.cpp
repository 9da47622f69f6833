// Application hook of the lp-mspm0g3507-bq79616 image. HOOK POINT: replace this file with the
// BQ79616 daisy-chain driver (wake, auto-address, chain reads), the measurement/protection tasks and the CAN
// publisher; main.cpp calls appInit() once, after bringUp() and before the scheduler runs.
//
// Until then it runs a 500 ms heartbeat: LED toggle and one CAN frame per beat (standard ID 0x7FF, DLC 4,
// the beat count big-endian), so a CAN tool on the bus shows the board is alive.
#include "board.hpp"
#include "common/heartbeat.hpp"
#include "core/bytes.hpp"
#include "sched/scheduler.hpp"

namespace {

constexpr fw::sched::TaskId kHeartbeatTask = 0;

void emitCan(uint32_t beat) {
  fw::hal::CanFrame frame;
  frame.id = 0x7FF;
  frame.dlc = 4;
  fw::bytes::storeBe32(frame.data.data(), beat);
  // Overflow, BusOff or NotReady: the heartbeat frame is dropped; the LED still shows the beat.
  (void)image::board().can.send(frame);
}

constinit image::Heartbeat heartbeat(emitCan);

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  heartbeat.start(scheduler, kHeartbeatTask, board.led, fw::ms(500));
}
