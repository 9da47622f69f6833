#include "sim/i2c_bus.hpp"

#include <cstdio>

#include "core/crc.hpp"
#include "sim/sim_clock.hpp"
#include "sim/sim_irq.hpp"

namespace bsp::host {

using fw::Status;

namespace {

void appendHex(std::string& text, uint8_t byte) {
  char buf[4];
  std::snprintf(buf, sizeof buf, " %02X", byte);
  text += buf;
}

}  // namespace

SimI2cBus::SimI2cBus(SimClock& clock, SimIrq& irq, SimI2cConfig config)
    : clock_(clock), irq_(irq), config_(config), line_(irq.attach("i2c", [this] { finish(); })) {}

void SimI2cBus::attach(uint8_t address7, I2cTarget& target) {
  targets_[address7] = &target;
}
void SimI2cBus::detach(uint8_t address7) {
  targets_.erase(address7);
}

Status SimI2cBus::doStart(std::span<fw::hal::I2cTransaction> list, const fw::hal::Notify& done) {
  if (busy_) return Status::Busy;
  if (list.empty()) return Status::InvalidArgument;
  for (const auto& txn : list) {
    if (txn.address > 0x7F || (txn.write.empty() && txn.read.empty()) || txn.read.size() > 255) {
      return Status::InvalidArgument;
    }
  }
  for (auto& txn : list) {
    txn.status = Status::Aborted;
    txn.readCount = 0;
  }
  busy_ = true;
  list_ = list;
  done_ = done;
  clock_.scheduleIn(fw::us(0), [this] { runTransaction(0); });
  return Status::Ok;
}

void SimI2cBus::runTransaction(size_t index) {
  auto& txn = list_[index];
  I2cWireRecord record;
  record.startUs = clock_.nowUs();
  const uint64_t wireNs = execute(txn, record.text);
  ++transactions_;
  busTimeNs_ += wireNs;
  record.status = txn.status;
  // Bus-free time between STOP and the next START (I2C spec tBUF).
  const uint64_t tBufNs = config_.bitRate > 100000 ? 1300 : 4700;
  record.endUs = record.startUs + (wireNs + 999) / 1000;
  log_.push_back(record);
  if (sink_) sink_(log_.back());

  const uint64_t nextUs = record.startUs + (wireNs + tBufNs + 999) / 1000;
  if (txn.status == Status::Ok && index + 1 < list_.size()) {
    clock_.schedule(nextUs + config_.restartGap.us, [this, index] { runTransaction(index + 1); });
  } else {
    clock_.schedule(nextUs, [this] { irq_.raise(line_); });
  }
}

uint64_t SimI2cBus::recoverNs(I2cTarget* target, std::string& text) {
  // 9 SCL pulses (or fewer, once SDA is seen high) then STOP.
  const uint64_t bitNs = 1000000000ULL / config_.bitRate;
  ++recoveries_;
  int clocks = 9;
  if (sdaHeldClocks_ > 0 && sdaHeldClocks_ <= 9) {
    clocks = sdaHeldClocks_;
    sdaHeldClocks_ = 0;
  }
  if (target != nullptr) target->onBusRecovery();
  text += " RECOVERY";
  return bitNs * static_cast<uint64_t>(clocks + 1);
}

uint64_t SimI2cBus::execute(fw::hal::I2cTransaction& txn, std::string& text) {
  const uint64_t bitNs = 1000000000ULL / config_.bitRate;
  const uint64_t limitNs = static_cast<uint64_t>(config_.stretchLimit.us) * 1000;
  uint64_t ns = 0;
  auto it = targets_.find(txn.address);
  I2cTarget* target = it == targets_.end() ? nullptr : it->second;

  if (sdaHeldClocks_ != 0) {
    // A device holds SDA low: no START is possible. The controller times out, then tries to recover.
    text = "BUS LOW TIMEOUT";
    ns += limitNs;
    ns += recoverNs(target, text);
    if (sdaHeldClocks_ != 0) {
      text += " FAILED";
      txn.status = Status::BusStuck;
    } else {
      txn.status = Status::Timeout;
    }
    return ns;
  }

  uint8_t pec = 0;
  auto fail = [&](Status status, const char* token) {
    text += ' ';
    text += token;
    text += " P";
    ns += bitNs;  // STOP
    txn.status = status;
    if (target != nullptr) target->onStop();
  };
  // Accounts a target reply; false when the stretch exceeded the limit (the controller timed out).
  auto stretched = [&](fw::Duration stretch) {
    const uint64_t sNs = static_cast<uint64_t>(stretch.us) * 1000;
    if (sNs > limitNs) {
      ns += limitNs;
      text += " TIMEOUT";
      ns += recoverNs(target, text);
      text += " P";
      txn.status = Status::Timeout;
      return false;
    }
    ns += sNs;
    return true;
  };
  auto sendAddress = [&](bool read) -> bool {
    const uint8_t byte = static_cast<uint8_t>((txn.address << 1) | (read ? 1 : 0));
    appendHex(text, byte);
    pec = fw::crc::crc8Update(pec, byte);
    ns += 9 * bitNs;
    I2cReply reply = target != nullptr ? target->onStart(read) : I2cReply{false, {}};
    if (!stretched(reply.stretch)) return false;
    if (!reply.ack) {
      fail(Status::Nack, "NACK");
      return false;
    }
    return true;
  };

  text = "S";
  ns += bitNs;
  const bool writePhase = !txn.write.empty() || txn.read.empty();
  if (writePhase) {
    if (!sendAddress(false)) return ns;
    const size_t total = txn.write.size() + ((txn.pec && txn.read.empty()) ? 1 : 0);
    for (size_t i = 0; i < total; ++i) {
      const uint8_t byte = i < txn.write.size() ? txn.write[i] : pec;
      appendHex(text, byte);
      pec = fw::crc::crc8Update(pec, byte);
      ns += 9 * bitNs;
      I2cReply reply = target->onWrite(byte);
      if (!stretched(reply.stretch)) return ns;
      if (!reply.ack) {
        fail(Status::DataNack, "NACK");
        return ns;
      }
    }
  }
  if (!txn.read.empty()) {
    if (writePhase) {
      text += " Sr";
      ns += bitNs;
    }
    if (!sendAddress(true)) return ns;
    text += " [";
    const size_t pecBytes = txn.pec ? 1 : 0;
    size_t dataEnd = txn.read.size();  // a block read's count byte shortens it
    for (size_t i = 0; i < dataEnd + pecBytes; ++i) {
      fw::Duration stretch{};
      const uint8_t byte = target->onRead(stretch);
      if (!stretched(stretch)) {
        text.insert(text.rfind(" TIMEOUT"), "]");
        return ns;
      }
      ns += 9 * bitNs;
      if (i != 0) text += ' ';
      char buf[3];
      std::snprintf(buf, sizeof buf, "%02X", byte);
      text += buf;
      if (i < dataEnd) {
        txn.read[i] = byte;
        txn.readCount = static_cast<uint8_t>(i + 1);
        pec = fw::crc::crc8Update(pec, byte);
        if (i == 0 && txn.blockRead) {
          // SMBus block read: the count byte decides how many bytes follow. One that does not fit the
          // buffer is refused (NACK, STOP) rather than trusted (PX4's SMBus driver once copied it unbounded:
          // PX4 PR #16872).
          if (byte == 0 || byte > txn.read.size() - 1) {
            text += "] NACK P";
            ns += bitNs;
            txn.status = Status::Length;
            target->onStop();
            return ns;
          }
          dataEnd = 1 + byte;
        }
      } else if (byte != pec) {
        text += "] P";
        ns += bitNs;
        txn.status = Status::Pec;
        target->onStop();
        return ns;
      }
    }
    text += ']';
  }
  text += " P";
  ns += bitNs;
  txn.status = Status::Ok;
  target->onStop();
  return ns;
}

void SimI2cBus::finish() {
  busy_ = false;
  fw::hal::Notify done = done_;
  done_ = {};
  done();
}

Status SimI2cBus::doRecover() {
  if (busy_) return Status::Busy;
  std::string text;
  const uint64_t ns = recoverNs(nullptr, text);
  busTimeNs_ += ns;
  I2cWireRecord record{clock_.nowUs(), clock_.nowUs() + ns / 1000, Status::Ok, "RECOVERY"};
  if (sdaHeldClocks_ != 0) record.status = Status::BusStuck;
  log_.push_back(record);
  if (sink_) sink_(log_.back());
  return record.status;
}

}  // namespace bsp::host
