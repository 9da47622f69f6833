#include "sim/uart.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "sim/sim_irq.hpp"

namespace bsp::host {

using fw::Status;

namespace {
std::string hexLine(const char* prefix, std::span<const uint8_t> bytes) {
  std::string text = prefix;
  char buf[4];
  for (uint8_t b : bytes) {
    std::snprintf(buf, sizeof buf, " %02X", b);
    text += buf;
  }
  return text;
}
}  // namespace

SimUart::SimUart(SimClock& clock, SimIrq& irq, uint32_t baud)
    : clock_(clock), irq_(irq), baud_(baud), line_(irq.attach("uart", [this] {
        busy_ = false;
        fw::hal::Notify done = done_;
        done_ = {};
        done();
      })) {}

void SimUart::emit(std::string line) {
  log_.push_back(std::move(line));
  if (sink_) sink_(log_.back());
}

Status SimUart::doStart(fw::hal::UartExchange& exchange, fw::hal::Notify done) {
  if (busy_) return Status::Busy;
  if (exchange.tx.empty() && exchange.rx.empty()) return Status::InvalidArgument;
  busy_ = true;
  exchange_ = &exchange;
  done_ = done;
  exchange.status = Status::Aborted;
  exchange.received = 0;
  rxLogged_.clear();
  txDone_ = false;
  if (!exchange.tx.empty()) emit(hexLine("TX", exchange.tx));
  txBytes_ += exchange.tx.size();
  const uint64_t txEnd = clock_.nowUs() + exchange.tx.size() * byteTimeUs();
  txEvent_ = clock_.schedule(txEnd, [this] { txComplete(); });
  return Status::Ok;
}

void SimUart::txComplete() {
  txEvent_ = 0;
  txDone_ = true;
  fw::hal::UartExchange& ex = *exchange_;
  if (peer_ != nullptr && !ex.tx.empty()) {
    if (noise_.ppm() == 0) {
      peer_->onHostBytes(ex.tx, clock_.nowUs());
    } else {
      // The peer takes what the line delivers; a byte whose frame is lost never reaches it.
      std::vector<uint8_t> line;
      for (uint8_t b : ex.tx) {
        bool lost = false;
        const uint8_t got = noise_.pass(b, lost);
        if (!lost) line.push_back(got);
      }
      peer_->onHostBytes(line, clock_.nowUs());
    }
  }
  if (exchange_ == nullptr) return;  // the peer's reaction aborted the exchange
  if (ex.rx.empty()) {
    complete(Status::Ok);
  } else if (ex.received == ex.rx.size()) {
    complete(Status::Ok);
  } else if (ex.received == 0) {
    armTimeout(clock_.nowUs() + ex.firstByteTimeout.us, Status::NoResponse);
  } else {
    armTimeout(clock_.nowUs() + ex.gapTimeout.us, Status::Truncated);
  }
}

void SimUart::armTimeout(uint64_t atUs, Status status) {
  if (timeout_ != 0) clock_.cancel(timeout_);
  timeout_ = clock_.schedule(atUs, [this, status] {
    timeout_ = 0;
    complete(status);
  });
}

void SimUart::logRx() {
  if (!rxLogged_.empty()) emit(hexLine("RX", rxLogged_));
  rxLogged_.clear();
}

void SimUart::complete(Status status) {
  if (exchange_ == nullptr) return;
  if (timeout_ != 0) {
    clock_.cancel(timeout_);
    timeout_ = 0;
  }
  logRx();
  if (status != Status::Ok) {
    char text[64];
    std::snprintf(text, sizeof text, "RX %s after %zu bytes", fw::statusName(status), exchange_->received);
    emit(text);
  }
  exchange_->status = status;
  exchange_ = nullptr;
  irq_.raise(line_);
}

void SimUart::arrive(uint8_t byte, bool framingError) {
  ++rxBytes_;
  byte = noise_.pass(byte, framingError);
  if (tap_) {
    tap_(byte, framingError);
    return;
  }
  if (exchange_ == nullptr || exchange_->received >= exchange_->rx.size()) {
    ++unsolicited_;
    return;
  }
  if (framingError) {
    complete(Status::CommFault);
    return;
  }
  fw::hal::UartExchange& ex = *exchange_;
  ex.rx[ex.received++] = byte;
  rxLogged_.push_back(byte);
  if (!txDone_) return;  // still transmitting; txComplete() decides
  if (ex.received == ex.rx.size()) {
    complete(Status::Ok);
  } else {
    armTimeout(clock_.nowUs() + ex.gapTimeout.us, Status::Truncated);
  }
}

void SimUart::peerSend(std::span<const uint8_t> bytes, uint64_t startUs) {
  uint64_t t = std::max({startUs, lineFreeUs_, clock_.nowUs()});
  for (uint8_t b : bytes) {
    t += byteTimeUs();
    clock_.schedule(t, [this, b] { arrive(b, false); });
  }
  lineFreeUs_ = t;
}

void SimUart::peerFramingError(uint64_t atUs) {
  const uint64_t t = std::max({atUs, lineFreeUs_, clock_.nowUs()}) + byteTimeUs();
  clock_.schedule(t, [this] { arrive(0, true); });
  lineFreeUs_ = t;
}

Status SimUart::doPing(fw::Duration low, fw::hal::Notify done) {
  if (busy_) return Status::Busy;
  if (low.us == 0) return Status::InvalidArgument;
  busy_ = true;
  done_ = done;
  txEvent_ = clock_.scheduleIn(low, [this, low] {
    txEvent_ = 0;
    std::string name = peer_ != nullptr ? peer_->onPing(low, clock_.nowUs()) : std::string();
    char text[64];
    std::snprintf(text, sizeof text, "PING %s %uus", name.empty() ? "?" : name.c_str(), low.us);
    emit(text);
    irq_.raise(line_);
  });
  return Status::Ok;
}

void SimUart::doAbort() {
  if (txEvent_ != 0) clock_.cancel(txEvent_);
  if (timeout_ != 0) clock_.cancel(timeout_);
  txEvent_ = 0;
  timeout_ = 0;
  if (exchange_ != nullptr) logRx();
  exchange_ = nullptr;
  done_ = {};
  busy_ = false;
}

}  // namespace bsp::host
