// I2cTarget: the bus face of an emulated I2C/SMBus device (BQ769x2, BQ7690x, BQ4050 emulators implement it).
//
// The simulated bus calls these in wire order for every transaction addressed to the target:
//   onStart(read)      after a START or repeated START with this target's address; ACK or NACK it
//   onWrite(byte)      a byte written by the controller; ACK or NACK it
//   onRead(stretch)    the controller clocks out a byte; return it
//   onStop()           STOP (also after a NACK or a timeout, when the controller gives up)
//   onBusRecovery()    the controller clocked SCL to free a stuck bus, then sent STOP
// Each reply may stretch SCL (hold it low) before the byte completes; a stretch longer than the bus's limit
// makes the controller time out. The emulator reads virtual time from its SimClock to model latencies.
#pragma once

#include <cstdint>

#include "core/time.hpp"

namespace bsp::host {

struct I2cReply {
  bool ack = true;
  fw::Duration stretch{};
};

class I2cTarget {
 public:
  virtual ~I2cTarget() = default;
  virtual I2cReply onStart(bool read) = 0;
  virtual I2cReply onWrite(uint8_t byte) = 0;
  virtual uint8_t onRead(fw::Duration& stretch) = 0;
  virtual void onStop() = 0;
  virtual void onBusRecovery() { onStop(); }
};

}  // namespace bsp::host
