#include "periph/i2c.hpp"

#include <cstdio>

#include "machine.hpp"

namespace twin {

namespace {

constexpr uint32_t kClksel = 0x1004, kGfctl = 0x1200, kTimeoutCtl = 0x1204;
constexpr uint32_t kTimeoutCnt = 0x1208, kMsa = 0x1210, kMctr = 0x1214, kMsr = 0x1218, kMrxdata = 0x121C;
constexpr uint32_t kMtxdata = 0x1220, kMtpr = 0x1224, kMcr = 0x1228, kMbmon = 0x1234, kMfifoctl = 0x1238;
constexpr uint32_t kMfifosr = 0x123C, kPecctl = 0x1240, kPecsr = 0x1244;

constexpr uint32_t kBurstRun = 1U << 0, kStart = 1U << 1, kStop = 1U << 2, kAck = 1U << 3;
constexpr uint32_t kAckOverride = 1U << 4;  // MCTR.MACKOEN
constexpr uint32_t kMsrBusy = 1U << 0, kMsrErr = 1U << 1, kMsrAdrAck = 1U << 2, kMsrDatAck = 1U << 3;
constexpr uint32_t kMsrIdle = 1U << 5, kMsrBusBusy = 1U << 6;
constexpr uint32_t kMcrActive = 1U << 0, kMcrClkStretch = 1U << 2;
constexpr uint32_t kGfctlAgfen = 1U << 8, kGfctlChain = 1U << 11;  // hw_i2c.h GFCTL.AGFEN, CHAIN
constexpr uint32_t kTxFlush = 1U << 7, kRxFlush = 1U << 15;
constexpr uint32_t kTimeoutAEnable = 1U << 15;
constexpr uint32_t kPecEnable = 1U << 12, kPecsrError = 1U << 17;
constexpr size_t kFifoDepth = 8;  // I2C_SYS_FENTRIES (tsv param rows)

uint8_t crc8Step(uint8_t crc, uint8_t byte) {
  crc ^= byte;
  for (int i = 0; i < 8; ++i)
    crc = static_cast<uint8_t>((crc & 0x80) ? (crc << 1) ^ 0x07 : crc << 1);
  return crc;
}

std::string hex2(uint8_t b) {
  char buf[4];
  std::snprintf(buf, sizeof buf, "%02X", b);
  return buf;
}

}  // namespace

I2c::I2c(Machine& machine, const char* name, Pins& pins)
    : Peripheral(machine, name),
      pins_(pins),
      step_(machine.timeline(), [this] { step(); }),
      timeout_(machine.timeline(), [this] { onTimeout(); }),
      flush_(machine.timeline(), [this] {
        if (flushStuck_) return;  // the fault holdFlush(): only a GPRCM reset empties the FIFOs
        if (mfifoctl_ & kTxFlush) tx_.clear();
        if ((mfifoctl_ & kRxFlush) && rxDelivered_ && !rx_.empty()) {
          machine_.violate(
              Rule::I2cRxUnread,
              this->name() + std::string(": RXFLUSH empties ") + std::to_string(rx_.size()) +
                  " byte(s) of a read that ended with STOP, no NACK and no error, never read from "
                  "MRXDATA: the transfer's data are lost, the read comes back short");
        }
        if (mfifoctl_ & kRxFlush) rx_.clear();
        txChanged();
      }) {}

void I2c::setPins(int sdaPincm, uint32_t sdaPf, int sclPincm, uint32_t sclPf) {
  sdaPincm_ = sdaPincm, sdaPf_ = sdaPf, sclPincm_ = sclPincm, sclPf_ = sclPf;
  pins_.onChange(sdaPincm, [this](bool) { watchRecovery(true); });
  pins_.onChange(sclPincm, [this](bool) { watchRecovery(false); });
}

void I2c::resetRegisters() {
  clock_ = ClockRegs(kClksel);
  gfctl_ = timeoutCtl_ = msa_ = mctr_ = mtpr_ = mcr_ = 0;
  mfifoctl_ = pecctl_ = pecsr_ = 0;
  adrNack_ = dataNack_ = err_ = false;
  tx_.clear();
  rx_.clear();
  // A reset mid-transaction leaves the target where it was; the bus recovery (or the next START) resolves it.
  if (phase_ != Phase::Idle && phase_ != Phase::TimedOut && busOwned_) endTransaction(true);
  phase_ = Phase::Idle;
  busOwned_ = false;
  target_ = nullptr;
  step_.cancel();
  timeout_.cancel();
  flush_.cancel();
  flushSeenDone_ = true;
}

uint32_t I2c::sclHz() const {
  return machine_.clockHz() / clock_.divider() / (((mtpr_ & 0x7F) + 1) * 10);
}

void I2c::checkWire(uint8_t address7) {
  char buf[200];
  const uint32_t tpr = mtpr_ & 0x7F, scl = sclHz();
  // The device's range first (it names the partner that would misread the bus), then the controller's own.
  auto range = ranges_.find(address7);
  if (tpr != 0 && range != ranges_.end()) {
    const TargetRange& r = range->second;
    if (scl < r.minHz || scl > r.maxHz) {
      std::snprintf(buf, sizeof buf,
                    "%s: SCL %u Hz (MTPR.TPR %u, CLKDIV /%u) to the %s, which accepts %u..%u Hz (%s)", name(),
                    scl, tpr, clock_.divider(), r.device.c_str(), r.minHz, r.maxHz, r.source.c_str());
      machine_.violate(Rule::I2cScl, buf);
      return;
    }
    // A device that may stretch SCL, addressed without CLKSTRETCH: the first stretch it makes is clocked over
    // (hw_i2c.h MCR.CLKSTRETCH), even if no stretch comes in this run.
    if (!r.stretchSource.empty() && (mcr_ & kMcrClkStretch) == 0) {
      std::snprintf(buf, sizeof buf,
                    "%s: addressing the %s with MCR.CLKSTRETCH clear, but the %s may stretch SCL (%s): the "
                    "controller would clock over the stretch",
                    name(), r.device.c_str(), r.device.c_str(), r.stretchSource.c_str());
      machine_.violate(Rule::I2cClockStretch, buf);
      return;
    }
    // The same device with the clock-low timeout A off: a held SCL is waited on without a bound (SLAU846B
    // 20.2 / SLAU847D 21.2 clock low timeout; hw_i2c.h TIMEOUT_CTL.TCLKAEN).
    if (!r.stretchSource.empty() && timeoutCycles() == 0) {
      std::snprintf(buf, sizeof buf,
                    "%s: addressing the %s with the clock-low timeout A off (TIMEOUT_CTL 0x%08X)", name(),
                    r.device.c_str(), timeoutCtl_);
      machine_.violate(Rule::I2cNoTimeout, std::string(buf) + ", but the " + r.device +
                                               " may hold SCL low (" + r.stretchSource +
                                               "): the controller would wait on it without a bound");
    }
  }
  if (tpr == 0 || scl > 1000000) {
    std::snprintf(
        buf, sizeof buf,
        "%s: SCL %u Hz (MTPR.TPR %u, CLKDIV /%u) is outside the controller's own range (TPR 1..127, at "
        "most 1 MHz Fast-mode Plus)",
        name(), scl, tpr, clock_.divider());
    machine_.violate(Rule::I2cTpr, buf);
  }
}

bool I2c::checkStretch(uint64_t stretchCycles, const char* byte) {
  if (stretchCycles == 0 || (mcr_ & kMcrClkStretch) != 0) return true;
  machine_.violate(Rule::I2cClockStretch,
                   name() + std::string(": the target stretched SCL on ") + byte +
                       " with MCR.CLKSTRETCH clear: the controller does not wait for it");
  return false;
}

uint64_t I2c::bitCycles() const {
  return static_cast<uint64_t>((mtpr_ & 0x7F) + 1) * 10 * clock_.divider();
}

uint64_t I2c::timeoutCycles() const {
  if ((timeoutCtl_ & kTimeoutAEnable) == 0 || (timeoutCtl_ & 0xFF) <= 1) return 0;
  const uint64_t counts = static_cast<uint64_t>(timeoutCtl_ & 0xFF) << 4;  // upper 8 of 12 bits
  return counts * ((mtpr_ & 0x7F) + 1) * 12 * clock_.divider();
}

bool I2c::routed() const {
  return sdaPincm_ != 0 && pins_.routed(sdaPincm_, sdaPf_) && pins_.routed(sclPincm_, sclPf_);
}

void I2c::log(const std::string& token) {
  if (!current_.text.empty()) current_.text += ' ';
  current_.text += token;
}

void I2c::endTransaction(bool failed) {
  if (readOpen_) {
    current_.text += ']';
    readOpen_ = false;
  }
  current_.endCycle = machine_.now();
  current_.failed = failed;
  ++transactions_;
  busCycles_ += current_.endCycle - current_.startCycle;
  if (sink_) sink_(current_);
  current_ = {};
}

void I2c::pecAdd(uint8_t byte) {
  crc_ = crc8Step(crc_, byte);
}

void I2c::holdSclLow(uint64_t from) {
  const uint64_t limit = timeoutCycles();
  if (limit != 0) timeout_.at(from + limit);
}

void I2c::onTimeout() {
  if (phase_ == Phase::Idle && busOwned_) {
    machine_.violate(
        Rule::I2cNoStop,
        name() + std::string(": the clock-low timeout expired with the controller holding SCL after "
                             "a burst that ended without STOP (MCTR.STOP clear) and was never "
                             "continued: the transaction was left open"));
  }
  step_.cancel();
  phase_ = Phase::TimedOut;
  log("TIMEOUT");
  endTransaction(true);
  raise(kTimeoutA);
}

void I2c::txChanged() {
  const uint32_t trig = mfifoctl_ & 7U;
  if (tx_.size() <= trig) raise(kMtxFifoTrg);
  if (tx_.empty()) raise(kMtxEmpty);
}

void I2c::rxChanged() {
  const uint32_t trig = ((mfifoctl_ >> 8) & 7U) + 1;
  if (rx_.size() >= trig) raise(kMrxFifoTrg);
  if (rx_.size() >= kFifoDepth) raise(kMrxFifoFull);
}

void I2c::startBurst() {
  if ((mcr_ & kMcrActive) == 0) {
    stop("MCTR.BURSTRUN written while the controller is not active (MCR.ACTIVE)");
    return;
  }
  if (phase_ != Phase::Idle) {
    stop("MCTR.BURSTRUN written while a burst is running (MSR.BUSY)");
    return;
  }
  if (mfifoctl_ & (kTxFlush | kRxFlush)) {
    machine_.violate(Rule::I2cFlush, name() + std::string(": a burst started with MFIFOCTL.") +
                                         ((mfifoctl_ & kTxFlush) ? "TXFLUSH" : "RXFLUSH") +
                                         " still set: the flush goes on and its FIFO's bytes are lost");
    return;
  }
  if (mctr_ & kAckOverride) {
    stop("MCTR.MACKOEN (controller ACK override): no TI example or library uses it, not modelled");
    return;
  }
  const bool continuesRead = read_ && ackLast_;  // the previous burst's direction and last ACK
  read_ = (msa_ & 1U) != 0;
  remaining_ = (mctr_ >> 16) & 0xFFF;
  stopAfter_ = (mctr_ & kStop) != 0;
  ackLast_ = (mctr_ & kAck) != 0;
  adrNack_ = dataNack_ = err_ = false;
  if (read_ && stopAfter_ && ackLast_ && remaining_ != 0) {
    machine_.violate(
        Rule::I2cReadNack,
        name() + std::string(": a read burst ends with STOP and MCTR.ACK set: its last byte is "
                             "ACKed, so the target drives SDA for one more and the STOP can fail"));
    return;
  }
  if ((mctr_ & kStart) == 0 && !busOwned_) {
    stop("MCTR.BURSTRUN without START while the controller does not own the bus");
    return;
  }
  releaseScl();
  if ((mctr_ & kStart) == 0) {
    // The receive goes on where the last burst stopped: no START, no address.
    if (!read_ || !continuesRead) {
      stop("MCTR.BURSTRUN without START after a transmit burst or a NACKed byte, not modelled");
      return;
    }
    nextByte();
    return;
  }
  phase_ = Phase::Start;
  if (!busOwned_) {
    // Leaving IDLE: the PEC CRC and byte count start again (hw_i2c.h CONTROLLER_I2CPECCTL.PECEN).
    crc_ = 0;
    pecDataBytes_ = 0;
    pecsr_ = 0;
    current_ = {};
    current_.startCycle = machine_.now();
    log("S");
  } else {
    if (readOpen_) {
      current_.text += ']';
      readOpen_ = false;
    }
    log("Sr");
  }
  busOwned_ = true;
  step_.after(bitCycles());
}

// Where the burst goes next, at the end of each timed phase.
void I2c::step() {
  switch (phase_) {
    case Phase::Start: {
      // A device holding SCL low: the controller waits, its clock-low timeout running; one holding SDA low:
      // the START is lost (arbitration).
      if (routed() && !pins_.level(sclPincm_)) {
        if (!timeout_.armed()) holdSclLow(machine_.now());
        step_.after(bitCycles());
        return;
      }
      releaseScl();
      if (routed() && !pins_.level(sdaPincm_)) {
        log("ARBLOST");
        busOwned_ = false;
        phase_ = Phase::Idle;
        err_ = true;
        endTransaction(true);
        raise(kMarbLost);
        return;
      }
      raise(kMstart);
      const auto address = static_cast<uint8_t>((msa_ >> 1) & 0x7F);
      if (routed()) {
        if (!pins_.requireInput(sdaPincm_, name() + std::string(" SDA")) ||
            !pins_.requireInput(sclPincm_, name() + std::string(" SCL")))
          return;
      }
      checkWire(address);
      const uint8_t wire = static_cast<uint8_t>(address << 1 | (read_ ? 1 : 0));
      log(hex2(wire));
      pecAdd(wire);
      auto it = targets_.find(address);
      target_ = (routed() && it != targets_.end()) ? it->second : nullptr;
      bsp::host::I2cReply reply{false, {}};
      if (target_ != nullptr) reply = target_->onStart(read_);
      byteAck_ = reply.ack;
      const uint64_t stretch = static_cast<uint64_t>(reply.stretch.us) * machine_.cyclesPerUs();
      if (!checkStretch(stretch, "the address byte")) return;
      phase_ = Phase::Address;
      // The target holds SCL low after the eighth bit, before it releases the acknowledge clock.
      if (stretch != 0) holdSclLow(machine_.now() + 8 * bitCycles());
      step_.after(9 * bitCycles() + stretch);
      return;
    }
    case Phase::Address:
      releaseScl();
      if (!byteAck_) {
        adrNack_ = err_ = true;
        log("NACK");
        raise(kMnack);
        sendStop();
        return;
      }
      nextByte();
      return;
    case Phase::Data:
      releaseScl();
      byteDone();
      return;
    case Phase::Stop:
      if (target_ != nullptr) target_->onStop();
      log("P");
      busOwned_ = false;
      phase_ = Phase::Idle;
      endTransaction(adrNack_ || dataNack_);
      raise(kMstop);
      return;
    default:
      return;
  }
}

void I2c::nextByte() {
  if (remaining_ == 0) {
    finishBurst();
    return;
  }
  const bool pecByte = (pecctl_ & kPecEnable) && pecDataBytes_ + 1 == (pecctl_ & 0x1FF);
  if (!read_) {
    if (tx_.empty()) {
      phase_ = Phase::WaitFifo;  // the controller holds SCL low until the firmware writes a byte
      holdSclLow(machine_.now());
      return;
    }
    byte_ = tx_.front();
    tx_.pop_front();
    txChanged();
    if (pecByte) byte_ = crc_;  // the dummy's place on the wire
    pecAdd(byte_);
    if ((pecctl_ & 0x1FF) != 0) ++pecDataBytes_;
    if (pecByte) pecDataBytes_ = 0;
    log(hex2(byte_));
    const bsp::host::I2cReply reply =
        target_ != nullptr ? target_->onWrite(byte_) : bsp::host::I2cReply{false, {}};
    byteAck_ = reply.ack;
    const uint64_t stretch = static_cast<uint64_t>(reply.stretch.us) * machine_.cyclesPerUs();
    if (!checkStretch(stretch, "a written byte")) return;
    if (stretch != 0) holdSclLow(machine_.now() + 8 * bitCycles());
    phase_ = Phase::Data;
    step_.after(9 * bitCycles() + stretch);
    return;
  }
  if (rx_.size() >= kFifoDepth) {
    phase_ = Phase::WaitFifo;  // RX FIFO full: SCL held low until the firmware reads
    holdSclLow(machine_.now());
    return;
  }
  fw::Duration stretch{};
  byte_ = target_ != nullptr ? target_->onRead(stretch) : 0xFF;
  const uint64_t stretchCycles = static_cast<uint64_t>(stretch.us) * machine_.cyclesPerUs();
  if (!checkStretch(stretchCycles, "a read byte")) return;
  if (stretchCycles != 0) holdSclLow(machine_.now());
  pecFail_ = pecByte && byte_ != crc_;  // checked after the byte's last bit (byteDone)
  pecAdd(byte_);
  if ((pecctl_ & 0x1FF) != 0) ++pecDataBytes_;
  if (pecByte) pecDataBytes_ = 0;             // "the byte count = PEC CNT, the byte count is reset to 0"
  log((readOpen_ ? "" : "[") + hex2(byte_));  // target-driven bytes inside [ ]
  readOpen_ = true;
  phase_ = Phase::Data;
  step_.after(9 * bitCycles() + stretchCycles);
}

void I2c::byteDone() {
  --remaining_;
  if (read_) {
    rx_.push_back(byte_);
    rxChanged();
    if (pecFail_) {
      pecsr_ |= kPecsrError;
      raise(kMpecRxErr);
    }
    nextByte();
    return;
  }
  if (!byteAck_) {
    dataNack_ = err_ = true;
    log("NACK");
    raise(kMnack);
    sendStop();
    return;
  }
  nextByte();
}

void I2c::finishBurst() {
  raise(read_ ? kMrxDone : kMtxDone);
  rxDelivered_ = read_ && stopAfter_ && !adrNack_ && !dataNack_ && !err_;
  if (stopAfter_) {
    sendStop();
  } else {
    // The controller keeps the bus, SCL low, for a repeated START or a continuation.
    phase_ = Phase::Idle;
    holdSclLow(machine_.now());
  }
}

void I2c::sendStop() {
  phase_ = Phase::Stop;
  if (readOpen_) {
    current_.text += ']';
    readOpen_ = false;
  }
  step_.after(bitCycles());
}

void I2c::watchRecovery(bool sdaChanged) {
  // Only lines the firmware drives as GPIOs: SCL clocks, then SDA rising while SCL is high (STOP).
  if (pins_.routed(sdaPincm_, Pins::kPfGpio) == false || pins_.routed(sclPincm_, Pins::kPfGpio) == false)
    return;
  if (!sdaChanged) {
    if (!pins_.level(sclPincm_)) sawGpioClock_ = true;
    return;
  }
  if (sawGpioClock_ && pins_.level(sdaPincm_) && pins_.level(sclPincm_)) {
    sawGpioClock_ = false;
    for (auto& [address, target] : targets_)
      target->onBusRecovery();
    if (phase_ == Phase::TimedOut) phase_ = Phase::Idle;
  }
}

bool I2c::readRegister(uint32_t offset, uint32_t& value) {
  if (clock_.read(offset, value)) return true;
  switch (offset) {
    case kGfctl:
      value = gfctl_;
      return true;
    case kTimeoutCtl:
      value = timeoutCtl_;
      return true;
    case kTimeoutCnt:
      value = 0;
      return true;
    case kMsa:
      value = msa_;
      return true;
    case kMctr:
      value = mctr_;
      return true;
    case kMtpr:
      value = mtpr_;
      return true;
    case kMcr:
      value = mcr_;
      return true;
    case kMfifoctl:
      value = mfifoctl_;
      return true;
    case kPecctl:
      value = pecctl_;
      return true;
    case kPecsr:
      value = pecsr_ | (pecDataBytes_ & 0x1FF);
      return true;
    case kMtxdata:
      value = 0;
      return true;
    case kMsr: {
      const bool running = phase_ != Phase::Idle;
      value = (running ? kMsrBusy : 0) | (err_ ? kMsrErr : 0) | (adrNack_ ? kMsrAdrAck : 0) |
              (dataNack_ ? kMsrDatAck : 0) | (!running && !busOwned_ ? kMsrIdle : 0) |
              (busOwned_ ? kMsrBusBusy : 0) | (remaining_ << 16);
      return true;
    }
    case kMbmon:
      value = (pins_.level(sclPincm_) ? 1U : 0U) | (pins_.level(sdaPincm_) ? 2U : 0U);
      return true;
    case kMfifosr:
      value = static_cast<uint32_t>(rx_.size()) | static_cast<uint32_t>(kFifoDepth - tx_.size()) << 8 |
              ((mfifoctl_ & kRxFlush) ? 1U << 7 : 0) | ((mfifoctl_ & kTxFlush) ? 1U << 15 : 0);
      // The firmware has now seen whether the flushes it asked for are complete (TXFIFOCNT 8, RXFIFOCNT 0).
      if ((!(mfifoctl_ & kTxFlush) || tx_.empty()) && (!(mfifoctl_ & kRxFlush) || rx_.empty()))
        flushSeenDone_ = true;
      return true;
    case kMrxdata: {
      if (rx_.empty()) {
        value = 0;
        return true;
      }
      value = rx_.front();
      rx_.pop_front();
      rxChanged();
      if (phase_ == Phase::WaitFifo && read_) {
        releaseScl();
        nextByte();
      }
      return true;
    }
    default:
      return false;
  }
}

bool I2c::writeRegister(uint32_t offset, uint32_t value) {
  if (clock_.write(offset, value)) {
    if (offset == kClksel && !clock_.busclk()) stop("CLKSEL selects a clock other than BUSCLK, not modelled");
    return true;
  }
  switch (offset) {
    case kGfctl:
      // "When 0, chaining is disabled and only digital filter output is available to IP logic" (hw_i2c.h
      // GFCTL.CHAIN): the analog filter enabled without CHAIN filters nothing the controller sees.
      if ((value & kGfctlAgfen) && !(value & kGfctlChain))
        stop("GFCTL.AGFEN without GFCTL.CHAIN: the analog glitch filter is not in the path (hw_i2c.h CHAIN)");
      gfctl_ = value;
      return true;
    case kTimeoutCtl:
      // The clock-low timeout is configured during initialisation, not in the active state (SLAU847D 21.2 /
      // SLAU846B 20.2, "clock low timeout").
      if (mcr_ & kMcrActive)
        stop("TIMEOUT_CTL written while MCR.ACTIVE is set (SLAU846B 20.2: configured during initialisation)");
      timeoutCtl_ = value;
      return true;
    case kTimeoutCnt:
    case kMsr:
    case kMbmon:
    case kMfifosr:
    case kMrxdata:
    case kPecsr:
      return true;  // read-only
    case kMsa:
      msa_ = value;
      return true;
    case kMtpr:
      mtpr_ = value;
      return true;
    case kMcr:
      mcr_ = value;
      return true;
    case kMctr:
      mctr_ = value;
      if (value & kBurstRun) startBurst();
      return true;
    case kMfifoctl: {
      const uint32_t cleared = mfifoctl_ & ~value & (kTxFlush | kRxFlush);
      if (cleared != 0 && !flushSeenDone_) {
        machine_.violate(Rule::I2cFlush,
                         name() + std::string(": MFIFOCTL.") +
                             ((cleared & kTxFlush) ? "TXFLUSH" : "RXFLUSH") +
                             " cleared before MFIFOSR showed the flush complete (TXFIFOCNT 8 / RXFIFOCNT 0)");
        return true;
      }
      if ((value & ~mfifoctl_) & (kTxFlush | kRxFlush)) flushSeenDone_ = false;
      mfifoctl_ = value;
      if (value & (kTxFlush | kRxFlush)) flush_.after(clock_.divider());
      return true;
    }
    case kPecctl:
      pecctl_ = value;
      pecDataBytes_ = 0;  // "any write ... will clear the current PEC Byte Count"; the CRC runs on
      return true;
    case kMtxdata:
      if (mfifoctl_ & kTxFlush) {
        machine_.violate(Rule::I2cFlush,
                         name() + std::string(": MTXDATA written while MFIFOCTL.TXFLUSH is set: "
                                              "the flush goes on and the byte is lost"));
        return true;
      }
      if (tx_.size() >= kFifoDepth) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "MTXDATA written (0x%02X) with the TX FIFO full: the byte is dropped",
                      value & 0xFF);
        stop(buf);
        return true;
      }
      tx_.push_back(static_cast<uint8_t>(value));
      txChanged();
      if (phase_ == Phase::WaitFifo && !read_) {
        releaseScl();
        nextByte();
      }
      return true;
    default:
      return false;
  }
}

}  // namespace twin
