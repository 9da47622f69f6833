// SimCan: the host's classic CAN controller (implements fw::hal::CanBus) on a simulated bus.
//
// Frames leave one at a time in queue order; each occupies the wire for its real length at the bit rate,
// computed from the actual bit stream (SOF..CRC with stuff bits, then ACK, EOF and intermission), so the
// timing figures printed by bms-sim are those of a real 500 kbit/s bus. The controller has a TX queue of
// `txDepth` frames (the MCAN dedicated buffers/FIFO the BSP configures).
// Other nodes (the PC, a vehicle controller) send with peerSend(), or keep the bus busy with a peer source
// (a flood): whenever the bus goes idle, the waiting frame with the lowest identifier wins arbitration
// (ISO 11898-1: a dominant 0 bit wins), ours or a peer's. A peer frame that has left the wire passes the
// receive filter (setFilter: the standard identifiers the image's MCAN filter elements accept, every other
// frame rejected, as the G3507 BSP configures it; without a filter every data frame is accepted) into an
// RX FIFO of `rxDepth` frames (a full FIFO loses the frame, counted in rxLost), and raises the receive
// interrupt (onReceive). A frame the filter rejects raises nothing.
// Fault injection: injectBusOff() puts the controller bus-off (queued frames are discarded, as MCAN does when
// it enters Bus_Off with INIT set); recover() takes 128 x 11 recessive bits to return to ErrorActive.
// Every frame sent is recorded with the time its transmission completed, for candump output and tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include "hal/can_bus.hpp"

namespace bsp::host {

class SimClock;
class SimIrq;

struct SentCanFrame {
  uint64_t timeUs;
  fw::hal::CanFrame frame;
};

// Bits on the wire for `frame` including stuff bits and the 10-bit ACK/EOF tail plus 3-bit intermission.
uint32_t canFrameBits(const fw::hal::CanFrame& frame);

class SimCan final : public fw::hal::CanBus {
 public:
  SimCan(SimClock& clock, SimIrq& irq, uint32_t bitRate = 500000, size_t txDepth = 8, size_t rxDepth = 8);

  const std::vector<SentCanFrame>& sent() const { return sent_; }
  void injectBusOff();
  uint64_t busTimeUs() const { return busTimeUs_; }  // time our own frames took on the wire

  // Another node sends `frame` (it competes for the bus from now).
  void peerSend(const fw::hal::CanFrame& frame);
  // While set, another node always has a frame waiting: `source` gives the next one each time its last has
  // won the bus (nullopt: none this time). Clear it with {}.
  void setPeerSource(std::function<std::optional<fw::hal::CanFrame>()> source);
  void setFilter(std::vector<uint32_t> standardIds);
  uint64_t peerFrames() const { return peerFrames_; }    // peer frames that went over the wire
  uint64_t filteredOut() const { return filteredOut_; }  // of those, rejected by the filter
  uint64_t receiveInterrupts() const { return rxInterrupts_; }
  // Each bus-off: when it began and when the controller was error active again (0: not yet), for reports.
  struct BusOffSpan {
    uint64_t startUs = 0, recoveredUs = 0;
  };
  const std::vector<BusOffSpan>& busOffLog() const { return busOffLog_; }

 private:
  fw::Status doSend(const fw::hal::CanFrame& frame) override;
  bool doReceive(fw::hal::CanFrame& frame) override;
  void doOnEvent(const fw::hal::Notify& notify) override { notify_ = notify; }
  void doOnReceive(const fw::hal::Notify& notify) override { rxNotify_ = notify; }
  fw::hal::CanState doState() const override { return state_; }
  fw::Status doRecover() override;
  fw::hal::CanCounters doCounters() const override { return counters_; }

  void startNext();
  void signal();
  void finished();
  bool accepts(const fw::hal::CanFrame& frame) const;

  SimClock& clock_;
  SimIrq& irq_;
  uint32_t bitRate_;
  size_t txDepth_;
  size_t rxDepth_;
  int line_;
  int rxLine_;
  fw::hal::Notify notify_;
  fw::hal::Notify rxNotify_;
  fw::hal::CanState state_ = fw::hal::CanState::ErrorActive;
  fw::hal::CanCounters counters_;
  std::deque<fw::hal::CanFrame> txQueue_;
  std::deque<fw::hal::CanFrame> rxQueue_;
  std::deque<fw::hal::CanFrame> peerQueue_;
  std::function<std::optional<fw::hal::CanFrame>()> peerSource_;
  std::optional<std::vector<uint32_t>> filter_;
  std::vector<SentCanFrame> sent_;
  bool transmitting_ = false;
  bool peerOnWire_ = false;  // the frame on the wire is a peer's
  fw::hal::CanFrame onWire_{};
  uint64_t peerFrames_ = 0, filteredOut_ = 0, rxInterrupts_ = 0;
  uint64_t txEvent_ = 0;
  uint64_t busTimeUs_ = 0;
  bool recovering_ = false;
  std::vector<BusOffSpan> busOffLog_;
};

}  // namespace bsp::host
