// The BQ79616's VC open-wire diagnostic (see open_wire.hpp for the contract, the sequence and its sources).
#include "drivers/bq79616/open_wire.hpp"

#include "drivers/bq79616/registers.hpp"

namespace fw::drivers::bq79616 {

Status OpenWireCheck::start(std::span<uint16_t> failing) {
  if (busy() || chain_.busy()) return Status::Busy;
  if (chain_.devices() == 0) return Status::NotReady;
  if (failing.size() < chain_.devices()) return Status::InvalidArgument;
  failing_ = failing;
  polls_ = 0;
  retried_ = false;
  verdict_ = false;
  failure_ = Status::Ok;
  result_ = Status::Ok;
  const Status s = write(regs::kBalCtrl2, regs::kBalCtrl2Pause);
  if (s == Status::Ok) stage_ = Stage::PauseBalancing;
  return s;
}

Status OpenWireCheck::write(uint16_t reg, uint8_t value) {
  return chain_.startWrite(RequestType::BroadcastWrite, 0, reg, {&value, 1});
}

// The stage `stage` was started with `started`: on the bus (true), or the check ends.
bool OpenWireCheck::next(Stage stage, Status started) {
  stage_ = stage;
  if (started == Status::Ok) return true;
  // Nothing went out: the sinks go off and balancing resumes before the check ends (each only once).
  if (failure_ == Status::Ok) failure_ = started;
  if (stage == Stage::Resume) return end(failure_);
  if (stage == Stage::SinksOff) return next(Stage::Resume, write(regs::kBalCtrl2, regs::kBalCtrl2Resume));
  return next(Stage::SinksOff, write(regs::kDiagCompCtrl3, 0));
}

bool OpenWireCheck::end(Status status) {
  result_ = status;
  stage_ = Stage::Idle;
  return false;
}

bool OpenWireCheck::step(Status r) {
  switch (stage_) {
    case Stage::Idle:
      return false;
    case Stage::SinksOff:
      if (r != Status::Ok) {
        if (failure_ == Status::Ok) failure_ = r;
        if (!retried_) {
          retried_ = true;
          return next(Stage::SinksOff, write(regs::kDiagCompCtrl3, 0));
        }
      }
      return next(Stage::Resume, write(regs::kBalCtrl2, regs::kBalCtrl2Resume));
    case Stage::Resume:
      if (r != Status::Ok && failure_ == Status::Ok) failure_ = r;
      if (failure_ != Status::Ok) return end(failure_);
      return next(Stage::Read,
                  chain_.startRead(RequestType::BroadcastRead, 0, regs::kFaultCompVcow1, 2, rx()));
    case Stage::Read:
      if (r != Status::Ok || !readVerdict()) return end(r != Status::Ok ? r : result_);
      return next(Stage::Clear, write(regs::kFaultRst1, regs::kFaultRst1Comp));
    case Stage::Clear:
      return end(r);  // the verdict stands whether the latch reset went through or not
    default:
      break;
  }
  // The stages from the balancing pause to the last poll: a failure turns the sinks off, resumes balancing
  // and ends the check.
  if (r != Status::Ok) {
    failure_ = r;
    return next(Stage::SinksOff, write(regs::kDiagCompCtrl3, 0));
  }
  switch (stage_) {
    case Stage::PauseBalancing:
      return next(Stage::Threshold, write(regs::kDiagCompCtrl2, kThresholdCode));
    case Stage::Threshold:
      return next(Stage::SinksOn, write(regs::kDiagCompCtrl3, regs::kDiagOwSinksVc));
    case Stage::SinksOn:
      return next(Stage::Deplete, chain_.startPause(kDeplete));
    case Stage::Deplete:
      return next(Stage::Go,
                  write(regs::kDiagCompCtrl3, regs::kDiagOwSinksVc | regs::kDiagSelVcOw | regs::kDiagCompGo));
    case Stage::Go:
      return next(Stage::Wait, chain_.startPause(kPollInterval));
    case Stage::Wait:
      ++polls_;
      return next(Stage::Poll, chain_.startRead(RequestType::BroadcastRead, 0, regs::kAdcStat2, 1, rx()));
    default:  // Poll
      return polled();
  }
}

// ADC_STAT2 of every device, top of the stack first: done when every device reports DRDY_VCOW; otherwise
// another poll, or Timeout after the last one. Either way the sinks go off next, unless another poll is due.
bool OpenWireCheck::polled() {
  const size_t size = responseSize(1);
  size_t left = chain_.received();
  const uint8_t* f = rx().data();
  bool done = true;
  Status r = Status::Ok;
  for (uint8_t d = chain_.devices(); d-- != 0; f += size, left -= size) {
    r = left < size ? Status::Truncated : checkResponse(f, left, regs::kAdcStat2, 1);
    if (r == Status::Ok && f[1] != d) r = Status::DeviceId;
    if (r != Status::Ok) break;
    done = done && (f[4] & regs::kAdcStat2DrdyVcow) != 0;
  }
  if (r == Status::Ok && !done && polls_ < kPolls) return next(Stage::Wait, chain_.startPause(kPollInterval));
  if (r == Status::Ok && !done) r = Status::Timeout;
  failure_ = r;
  return next(Stage::SinksOff, write(regs::kDiagCompCtrl3, 0));
}

// FAULT_COMP_VCOW1 (cells 16..9, bit 0 = cell 9) and VCOW2 (cells 8..1, bit 0 = cell 1) of every device, top
// first; every frame checked before any verdict is taken.
bool OpenWireCheck::readVerdict() {
  const size_t size = responseSize(2);
  size_t left = chain_.received();
  const uint8_t* f = rx().data();
  for (uint8_t d = chain_.devices(); d-- != 0; f += size, left -= size) {
    Status r = left < size ? Status::Truncated : checkResponse(f, left, regs::kFaultCompVcow1, 2);
    if (r == Status::Ok && f[1] != d) r = Status::DeviceId;
    if (r != Status::Ok) {
      result_ = r;
      return false;
    }
  }
  f = rx().data();
  for (uint8_t d = chain_.devices(); d-- != 0; f += size)
    failing_[d] = static_cast<uint16_t>(f[4] << 8 | f[5]);
  verdict_ = true;
  return true;
}

}  // namespace fw::drivers::bq79616
