// Balancer: host-controlled cell balancing of a BQ79616 chain, built on the Chain's raw frames (chain.hpp
// startWrite/startRead), so balancing adds no state to the chain's scripts.
//
// The device balances by itself once started: per-channel timers CB_CELLn_CTRL (0x0318 + 16 - n) sampled by
// BAL_CTRL2[BAL_GO] with the rest of the settings, and it stops a channel when its timer runs out (SLUSE81E /
// SLUSF21 "Cell Balancing", CB_CELLn_CTRL, BAL_CTRL2). The driver uses manual control (AUTO_BAL = 0: the
// host decides which cells, the device switches nothing itself), which turns on every channel with a timer at
// once, at most eight, and no two neighbours while DEV_CONF[NO_ADJ_CB] is set (its default, 0x54; SLUSF21
// 8.3.3.1.2, SLUSDT5B); a set that breaks either rule does not start (BAL_STAT[INVALID_CBCONF]). Every start
// sets FLTSTOP_EN, so an unmasked device fault stops balancing at once (BAL_STAT[ABORTFLT]); OTCB_EN stays 0
// (no NTC is configured on the GPIOs; the die's CB TWARN pauses balancing whatever it says). VCB_DONE_THRESH
// is not used (its encoding is unresolved, regmaps/README.md): the host stops cells itself.
//
// Operations (start*() returns Ok when the first frame went to the chain, Busy while another runs,
// InvalidArgument for a request the device would refuse, NotReady before the chain is up; the owner forwards
// the chain's completion to step(), which starts the next frame (true) or ends the operation (false);
// result() is then the final Status):
//   startApply(device, mask)  single writes to `device`: CB_CELL16..9_CTRL and CB_CELL8..1_CTRL (8 bytes
//                             each: kTimerCode for the cells in `mask`, 0 for the others), then BAL_CTRL2 =
//                             FLTSTOP_EN | BAL_GO. Mask 0 stops that device. InvalidArgument for cells beyond
//                             the chain's active cells, more than 8, or neighbours (the device's own rules).
//   startStopAll()            the same three writes broadcast with every timer 0: the whole chain stops in
//                             three frames, whatever its length ("set the timers to 0 and BAL_GO", the host's
//                             stop of SLUSE81E 9.3.3.3).
//   startStatus(out)          one broadcast read of BAL_STAT: out[d] for each device d in use; Ok only when
//                             every device's frame validated (CRC, length, device order, register), otherwise
//                             the first failure (out then holds only the frames before it).
// Thread mode only (the monitor task).
#pragma once

#include <cstdint>
#include <span>

#include "core/bits.hpp"
#include "core/status.hpp"
#include "drivers/bq79616/chain.hpp"

namespace fw::drivers::bq79616 {

class Balancer {
 public:
  // CB_CELLn_CTRL TIME code for a balanced cell: 0x02 = 30 s (SLUSE81E CB_CELLn_CTRL; TI's example uses the
  // same). The owner applies again well within it; a host that stops talking leaves balancing for 30 s at
  // most.
  static constexpr uint8_t kTimerCode = 0x02;
  static constexpr uint8_t kMaxChannels = 8;

  explicit Balancer(Chain& chain) : chain_(chain) {}
  Balancer(const Balancer&) = delete;
  Balancer& operator=(const Balancer&) = delete;

  // The masks the device takes in manual control with DEV_CONF[NO_ADJ_CB] (bit c = cell c + 1).
  static constexpr bool allowed(uint16_t mask, uint8_t cells) {
    return countBits(mask) <= kMaxChannels && (mask & (mask >> 1)) == 0 &&
           (cells >= 16 || (mask >> cells) == 0);
  }

  Status startApply(uint8_t device, uint16_t mask);
  Status startStopAll();
  Status startStatus(std::span<uint8_t> out);
  bool step(Status chainResult);
  Status result() const { return result_; }
  bool busy() const { return frame_ != 0; }

 private:
  Status send();

  Chain& chain_;
  std::span<uint8_t> status_;  // startStatus's output
  uint16_t mask_ = 0;
  uint8_t device_ = 0;
  uint8_t frame_ = 0;   // 1-based frame of the running operation; 0: idle
  uint8_t frames_ = 0;  // frames of the running operation
  bool broadcast_ = false;
  Status result_ = Status::Ok;
  uint8_t rx_[kMaxDevices * (1 + kResponseOverhead)];  // BAL_STAT of every device
};

}  // namespace fw::drivers::bq79616
