// Outboxes: what the command task (app/command) gives a publisher to send besides its own cycle: the answers
// to commands. The publisher owns the outbox (it is the one sender on its bus or line) and sends what waits
// there between its own frames, never two answers in a row while a frame of its own is due, so a flood of
// commands cannot starve the published messages.
//
// Protocol (thread mode, both tasks on one scheduler): the command task fills an outbox only when it is
// empty, then posts the publisher's kReply event. The publisher empties it as the items leave; when the last
// one has, and the command task has marked itself `waiting`, it posts the command task's
// command_event::kOutboxFree.
#pragma once

#include <cstdint>

#include "app/tasks.hpp"
#include "hal/can_bus.hpp"

namespace fw::app {

// CAN: up to three frames (an acknowledgement and a command's data).
struct CanOutbox {
  static constexpr uint8_t kFrames = 3;
  hal::CanFrame frames[kFrames];
  uint8_t count;  // frames waiting, from `next`
  uint8_t next;
  bool waiting;  // the command task waits for the outbox to empty
};

// SLCAN: the adapter's answer to a line and up to three answer frames as text lines ("z\r" + 3 x 22 bytes),
// sent in one write.
struct SlcanOutbox {
  static constexpr uint8_t kBytes = 72;
  uint8_t text[kBytes];
  uint8_t length;  // bytes waiting (0: empty)
  bool inFlight;   // handed to the serial line; the buffer is the line's until it has left
  bool waiting;
};

}  // namespace fw::app
