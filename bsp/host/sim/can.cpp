#include "sim/can.hpp"

#include "sim/sim_clock.hpp"
#include "sim/sim_irq.hpp"

namespace bsp::host {

using fw::Status;
using fw::hal::CanFrame;
using fw::hal::CanState;

namespace {

// CRC-15/CAN over the unstuffed bits, polynomial 0x4599 (ISO 11898-1).
uint16_t crc15(const std::vector<uint8_t>& bits) {
  uint16_t crc = 0;
  for (uint8_t bit : bits) {
    const bool next = ((crc >> 14) & 1U) ^ bit;
    crc = static_cast<uint16_t>((crc << 1) & 0x7FFF);
    if (next) crc ^= 0x4599;
  }
  return crc;
}

void pushBits(std::vector<uint8_t>& bits, uint32_t value, int count) {
  for (int i = count - 1; i >= 0; --i)
    bits.push_back(static_cast<uint8_t>((value >> i) & 1U));
}

}  // namespace

uint32_t canFrameBits(const CanFrame& frame) {
  std::vector<uint8_t> bits;
  bits.push_back(0);  // SOF
  if (frame.extended) {
    pushBits(bits, frame.id >> 18, 11);
    bits.push_back(1);  // SRR
    bits.push_back(1);  // IDE
    pushBits(bits, frame.id & 0x3FFFF, 18);
    bits.push_back(0);     // RTR
    pushBits(bits, 0, 2);  // r1, r0
  } else {
    pushBits(bits, frame.id, 11);
    bits.push_back(0);  // RTR
    bits.push_back(0);  // IDE
    bits.push_back(0);  // r0
  }
  pushBits(bits, frame.dlc, 4);
  for (uint8_t i = 0; i < frame.dlc && i < 8; ++i)
    pushBits(bits, frame.data[i], 8);
  pushBits(bits, crc15(bits), 15);

  // Stuff bits: after five equal bits the transmitter inserts one of opposite value (SOF through CRC).
  uint32_t stuffed = 0;
  int run = 0;
  uint8_t last = 2;
  for (uint8_t bit : bits) {
    if (bit == last) {
      ++run;
    } else {
      last = bit;
      run = 1;
    }
    if (run == 5) {
      ++stuffed;
      last = static_cast<uint8_t>(!bit);
      run = 1;
    }
  }
  // CRC delimiter, ACK slot, ACK delimiter, 7-bit EOF, 3-bit intermission.
  return static_cast<uint32_t>(bits.size()) + stuffed + 1 + 2 + 7 + 3;
}

SimCan::SimCan(SimClock& clock, SimIrq& irq, uint32_t bitRate, size_t txDepth, size_t rxDepth)
    : clock_(clock),
      irq_(irq),
      bitRate_(bitRate),
      txDepth_(txDepth),
      rxDepth_(rxDepth),
      line_(irq.attach("can", [this] { notify_(); })),
      rxLine_(irq.attach("can-rx", [this] { rxNotify_(); })) {}

void SimCan::signal() {
  irq_.raise(line_);
}

Status SimCan::doSend(const CanFrame& frame) {
  if (frame.dlc > 8 || (!frame.extended && frame.id > 0x7FF) || frame.id > 0x1FFFFFFF) {
    return Status::InvalidArgument;
  }
  if (state_ == CanState::BusOff) return Status::BusOff;
  if (txQueue_.size() >= txDepth_) {
    ++counters_.txOverflows;
    return Status::Overflow;
  }
  txQueue_.push_back(frame);
  if (!transmitting_) startNext();
  return Status::Ok;
}

void SimCan::peerSend(const CanFrame& frame) {
  peerQueue_.push_back(frame);
  if (!transmitting_) startNext();
}

void SimCan::setPeerSource(std::function<std::optional<CanFrame>()> source) {
  peerSource_ = std::move(source);
  if (!transmitting_) startNext();
}

void SimCan::setFilter(std::vector<uint32_t> standardIds) {
  filter_ = std::move(standardIds);
}

// Arbitration at bus idle: the lowest identifier among our queue's head and the peers' waiting frame wins
// (an extended identifier's base part decides first; equal ones are not sent by two nodes here).
void SimCan::startNext() {
  if (peerQueue_.empty() && peerSource_) {
    if (auto f = peerSource_()) peerQueue_.push_back(*f);
  }
  const bool ours = !txQueue_.empty() && state_ != CanState::BusOff;
  const bool peers = !peerQueue_.empty();
  if (!ours && !peers) {
    transmitting_ = false;
    return;
  }
  auto priority = [](const CanFrame& f) { return f.extended ? (f.id >> 18) * 2 + 1 : f.id * 2; };
  peerOnWire_ = peers && (!ours || priority(peerQueue_.front()) < priority(txQueue_.front()));
  onWire_ = peerOnWire_ ? peerQueue_.front() : txQueue_.front();
  transmitting_ = true;
  const uint64_t durationUs = (static_cast<uint64_t>(canFrameBits(onWire_)) * 1000000ULL) / bitRate_;
  if (!peerOnWire_) busTimeUs_ += durationUs;
  txEvent_ = clock_.scheduleIn(fw::us(static_cast<uint32_t>(durationUs)), [this] {
    txEvent_ = 0;
    finished();
  });
}

bool SimCan::accepts(const CanFrame& f) const {
  if (!filter_) return true;
  if (f.extended) return false;
  for (uint32_t id : *filter_) {
    if (id == f.id) return true;
  }
  return false;
}

void SimCan::finished() {
  if (!peerOnWire_) {
    sent_.push_back(SentCanFrame{clock_.nowUs(), txQueue_.front()});
    txQueue_.pop_front();
    ++counters_.txFrames;
    startNext();
    signal();
    return;
  }
  const CanFrame f = peerQueue_.front();
  peerQueue_.pop_front();
  ++peerFrames_;
  startNext();
  if (state_ == CanState::BusOff) return;  // INIT is set: the controller takes no part in the bus
  if (!accepts(f)) {
    ++filteredOut_;
    return;
  }
  if (rxQueue_.size() >= rxDepth_) {
    ++counters_.rxLost;
    return;
  }
  rxQueue_.push_back(f);
  ++counters_.rxFrames;
  ++rxInterrupts_;
  irq_.raise(rxLine_);
}

bool SimCan::doReceive(CanFrame& frame) {
  if (rxQueue_.empty()) return false;
  frame = rxQueue_.front();
  rxQueue_.pop_front();
  return true;
}

void SimCan::injectBusOff() {
  if (txEvent_ != 0 && !peerOnWire_) {
    clock_.cancel(txEvent_);
    txEvent_ = 0;
    transmitting_ = false;
  }
  txQueue_.clear();
  if (state_ != CanState::BusOff) busOffLog_.push_back({clock_.nowUs(), 0});
  state_ = CanState::BusOff;
  ++counters_.busOffEvents;
  if (!transmitting_) startNext();
  signal();
}

Status SimCan::doRecover() {
  if (state_ != CanState::BusOff) return Status::Ok;
  if (recovering_) return Status::Busy;
  recovering_ = true;
  // ISO 11898-1: 128 occurrences of 11 consecutive recessive bits.
  const uint64_t us = (128ULL * 11ULL * 1000000ULL) / bitRate_;
  clock_.scheduleIn(fw::us(static_cast<uint32_t>(us)), [this] {
    recovering_ = false;
    state_ = CanState::ErrorActive;
    busOffLog_.back().recoveredUs = clock_.nowUs();
    if (!transmitting_) startNext();
    signal();
  });
  return Status::Ok;
}

}  // namespace bsp::host
