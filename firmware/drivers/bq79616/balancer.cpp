// BQ79616 host-controlled balancing (see balancer.hpp for the contract and the TI sources).
#include "drivers/bq79616/balancer.hpp"

#include "regmap/bq79616.hpp"

namespace fw::drivers::bq79616 {

namespace {

namespace r = ::fw::regmap::bq79616::reg;
namespace b = ::fw::regmap::bq79616::bits;
using ::fw::regmap::code16;

// CB_CELL16_CTRL..CB_CELL1_CTRL: one block of 16 registers, cell n at 0x0318 + 16 - n, written as two
// 8-byte frames (a write frame carries at most 8 bytes, SLUSE81E 9.3.6.1.1).
constexpr uint16_t kCbCell16 = code16(r::CbCell16Ctrl);
constexpr uint16_t kCbCell8 = code16(r::CbCell8Ctrl);
static_assert(code16(r::CbCell1Ctrl) == kCbCell16 + 15 && kCbCell8 == kCbCell16 + 8,
              "CB_CELL16_CTRL..CB_CELL1_CTRL are one block of 16");
constexpr uint16_t kBalCtrl2 = code16(r::BalCtrl2);
constexpr uint16_t kBalStat = code16(r::BalStat);
// Manual control with the fault stop, and the start (SLUSE81E BAL_CTRL2: AUTO_BAL 0, FLTSTOP_EN bit 5, BAL_GO
// bit 1 self-clearing; OTCB_EN 0, BAL_ACT 00 no action when done, CB_PAUSE 0).
constexpr uint8_t kGo = b::BalCtrl2{}.with_fltstop_en(true).with_bal_go(true).raw();
static_assert(kGo == 0x22);
static_assert(Balancer::kTimerCode == b::CbCellCtrl{}.with_time(2).raw(), "TIME[4:0] = 2: 30 s");

enum : uint8_t { kHigh = 1, kLow = 2, kStart = 3 };  // the frames of apply and stop

}  // namespace

Status Balancer::startApply(uint8_t device, uint16_t mask) {
  if (busy() || chain_.busy()) return Status::Busy;
  if (chain_.devices() == 0) return Status::NotReady;
  if (device >= chain_.devices() || !allowed(mask, chain_.config().activeCells))
    return Status::InvalidArgument;
  device_ = device;
  mask_ = mask;
  broadcast_ = false;
  frames_ = kStart;
  frame_ = kHigh;
  return send();
}

Status Balancer::startStopAll() {
  if (busy() || chain_.busy()) return Status::Busy;
  if (chain_.devices() == 0) return Status::NotReady;
  mask_ = 0;
  broadcast_ = true;
  frames_ = kStart;
  frame_ = kHigh;
  return send();
}

Status Balancer::startStatus(std::span<uint8_t> out) {
  if (busy() || chain_.busy()) return Status::Busy;
  if (chain_.devices() == 0) return Status::NotReady;
  if (out.size() < chain_.devices()) return Status::InvalidArgument;
  status_ = out;
  frames_ = 1;
  frame_ = 1;
  const Status s = chain_.startRead(RequestType::BroadcastRead, 0, kBalStat, 1, rx_);
  if (s != Status::Ok) frame_ = 0;
  return s;
}

// The frame `frame_` of an apply or stop.
Status Balancer::send() {
  if (frame_ == kStart) {
    const uint8_t go = kGo;
    const Status s = broadcast_ ? chain_.startWrite(RequestType::BroadcastWrite, 0, kBalCtrl2, {&go, 1})
                                : chain_.startWrite(RequestType::SingleWrite, device_, kBalCtrl2, {&go, 1});
    if (s != Status::Ok) frame_ = 0;
    return s;
  }
  // Cells 16..9 in the first frame, 8..1 in the second: register i of a frame is cell (16 or 8) - i.
  uint8_t timers[8];
  const uint8_t top = frame_ == kHigh ? 16 : 8;
  for (uint8_t i = 0; i < 8; ++i)
    timers[i] = ((mask_ >> (top - 1 - i)) & 1U) != 0 ? kTimerCode : 0;
  const uint16_t reg = frame_ == kHigh ? kCbCell16 : kCbCell8;
  const Status s = broadcast_ ? chain_.startWrite(RequestType::BroadcastWrite, 0, reg, timers)
                              : chain_.startWrite(RequestType::SingleWrite, device_, reg, timers);
  if (s != Status::Ok) frame_ = 0;
  return s;
}

bool Balancer::step(Status chainResult) {
  if (!busy()) return false;
  if (chainResult == Status::Ok && frames_ == 1) {
    // BAL_STAT of every device, top of the stack first: each frame checked against the device it must
    // come from.
    const size_t size = responseSize(1);
    size_t left = chain_.received();
    const uint8_t* f = rx_;
    for (uint8_t d = chain_.devices(); d-- != 0; f += size, left -= size) {
      chainResult = left < size ? Status::Truncated : checkResponse(f, left, kBalStat, 1);
      if (chainResult == Status::Ok && f[1] != d) chainResult = Status::DeviceId;
      if (chainResult != Status::Ok) break;
      status_[d] = f[4];
    }
  }
  if (chainResult != Status::Ok || frame_ == frames_) {
    result_ = chainResult;
    frame_ = 0;
    return false;
  }
  ++frame_;
  const Status s = send();
  if (s == Status::Ok) return true;
  result_ = s;
  return false;
}

}  // namespace fw::drivers::bq79616
