// CanBus: a classic CAN 2.0 controller (MCAN on the MSPM0G3507) with a transmit queue.
//
// Contract
// - send(frame) queues one frame and returns Ok, Overflow (the TX queue is full: nothing queued),
//   BusOff (the controller is bus-off: nothing queued) or InvalidArgument (dlc > 8, id out of range).
//   Never blocks. Frames of equal priority leave in the order queued.
// - receive(frame) pops one received frame; false when none. Task context only. A controller with receive
//   filters hands over only the frames its filters accept.
// - onEvent(notify) registers the Notify called from ISR context when a queued frame has been transmitted or
//   when the error state changed; onReceive(notify) the one called when a frame was received (a controller
//   that never receives never calls it). The two go to different tasks: the publisher, the command task.
// - state() reports ErrorActive / ErrorPassive / BusOff. recover() starts the bus-off recovery sequence
//   (ISO 11898: 128 occurrences of 11 recessive bits); the state returns to ErrorActive when it completes.
// - Counters are monotonic and never reset by the controller.
#pragma once

#include <array>
#include <cstdint>

#include "core/status.hpp"
#include "hal/notify.hpp"

namespace fw::hal {

struct CanFrame {
  uint32_t id = 0;  // 11-bit (standard) or 29-bit (extended) identifier
  bool extended = false;
  uint8_t dlc = 0;
  std::array<uint8_t, 8> data{};
};

enum class CanState : uint8_t { ErrorActive, ErrorPassive, BusOff };

struct CanCounters {
  uint32_t txFrames = 0;
  uint32_t rxFrames = 0;
  uint32_t txOverflows = 0;  // send() refused because the queue was full
  uint32_t busOffEvents = 0;
  uint32_t rxLost = 0;  // received frames lost because the receive queue was full
};

class CanBus {
 public:
  Status send(const CanFrame& frame) { return doSend(frame); }
  bool receive(CanFrame& frame) { return doReceive(frame); }
  void onEvent(const Notify& notify) { doOnEvent(notify); }
  void onReceive(const Notify& notify) { doOnReceive(notify); }
  CanState state() const { return doState(); }
  Status recover() { return doRecover(); }
  CanCounters counters() const { return doCounters(); }

 protected:
  ~CanBus() = default;

 private:
  virtual Status doSend(const CanFrame& frame) = 0;
  virtual bool doReceive(CanFrame& frame) = 0;
  virtual void doOnEvent(const Notify& notify) = 0;
  virtual void doOnReceive(const Notify& notify) = 0;
  virtual CanState doState() const = 0;
  virtual Status doRecover() = 0;
  virtual CanCounters doCounters() const = 0;
};

}  // namespace fw::hal
