#include "drivers/bq769x2/link.hpp"

#include "core/assert.hpp"
#include "core/crc.hpp"
#include "core/stats.hpp"

namespace fw::drivers::bq769x2 {

FW_MODULE(Module::DriverBq769x2);

Status Link::startRead(uint8_t cmd, uint8_t len, uint8_t at, Duration delay) {
  if (busy()) return Status::Busy;
  if (len == 0 || at + len * (crc() ? 2 : 1) > kScratchBytes || (!kConfigPaths && delay.us != 0))
    return Status::InvalidArgument;
  state_->at = at;
  if (kConfigPaths) state_->delay = delay;
  return request(Op::Read, cmd, {}, len);
}

Status Link::startWrite(uint8_t cmd, std::span<const uint8_t> bytes) {
  if (bytes.empty()) return Status::InvalidArgument;
  return request(Op::Write, cmd, bytes, 0);
}

Status Link::startSubcommand(uint16_t code, bool awaitEcho) {
  return request(awaitEcho ? Op::Sub : Op::SubWrite, code, {}, 0);
}

Status Link::startSubcommandRead(uint16_t code, uint8_t len) {
  return request(Op::SubRead, code, {}, len);
}

Status Link::startSubcommandWrite(uint16_t code, std::span<const uint8_t> bytes) {
  return request(Op::SubWrite, code, bytes, 0);
}

Status Link::request(Op op, uint16_t code, std::span<const uint8_t> bytes, uint8_t len) {
  if (busy()) return Status::Busy;
  // A build without the CRC mode refuses a link configured for it (config.hpp FW_BQ769X_CRC).
  if (bytes.size() > kMaxWriteData || len > kMaxReadBytes || (op != Op::Read && len > kBufferBytes) ||
      crc() != cfg_.crc)
    return Status::InvalidArgument;
  if (op != Op::Read) {
    state_->at = 0;
    if (kConfigPaths) state_->delay = {};
  }
  state_->op = op;
  state_->code = code;
  state_->len = len;
  state_->attempt = 0;
  state_->reported = 0;
  buffers_->data[0] = static_cast<uint8_t>(code);
  buffers_->data[1] = static_cast<uint8_t>(code >> 8);
  state_->dataLen = static_cast<uint8_t>(bytes.size());
  for (uint8_t i = 0; i < state_->dataLen; ++i)
    buffers_->data[2 + i] = bytes[i];
  state_->phase = Phase::Main;
  state_->polls = 0;
  if (kConfigPaths && state_->delay.us != 0) {
    wait(state_->delay);
  } else {
    phase(Phase::Main);
  }
  return Status::Ok;
}

void Link::phase(Phase p) {
  state_->phase = p;
  // Each phase is one transaction: its command byte, the data that follow it and the bytes to read.
  uint8_t cmd = kCmdSubcommand;
  const uint8_t* data = nullptr;
  uint8_t count = 0;
  uint8_t readLen = 0;
  uint8_t tail[2];
  switch (p) {
    case Phase::Main:
      // A direct access sends its command byte and data; a subcommand sends 0x3E, the code and data.
      if (state_->op <= Op::Write) {
        cmd = buffers_->data[0];
        data = buffers_->data + 2;
        count = state_->dataLen;
        readLen = state_->op == Op::Read ? state_->len : 0;
      } else {
        data = buffers_->data;
        count = static_cast<uint8_t>(state_->dataLen + 2);
      }
      break;
    case Phase::Poll:
      readLen = 2;
      break;
    case Phase::Fetch:
      cmd = kCmdBuffer;
      readLen = kWindowBytes;
      break;
    case Phase::Commit:
      // SLUAA11B section 3.3: the checksum covers 0x3E, 0x3F and the data; the length counts them plus
      // 0x60 and 0x61 (data + 4).
      tail[0] = transferChecksum(state_->code, buffers_->data + 2, state_->dataLen);
      tail[1] = static_cast<uint8_t>(state_->dataLen + 4);
      cmd = kCmdChecksum;
      data = tail;
      count = 2;
      break;
  }
  transfer(cmd, data, count, readLen);
}

// Builds and starts one transaction. With CRC on, a CRC follows every data byte: the first covers
// addr+W, the command and that byte, each later one its byte alone (SLUAA11B section 4). Without CRC no CRC
// is computed at all (the common case: every scan read).
inline void Link::transfer(uint8_t cmd, const uint8_t* data, uint8_t count, uint8_t readLen) {
  const bool withCrc = crc();
  uint8_t sum = 0;
  if (withCrc) sum = crc::crc8Update(crc::crc8Update(0, static_cast<uint8_t>(cfg_.address << 1)), cmd);
  uint8_t k = 0;
  buffers_->tx[k++] = cmd;
  for (uint8_t i = 0; i < count; ++i) {
    buffers_->tx[k++] = data[i];
    if (withCrc) {
      buffers_->tx[k++] = crc::crc8Update(sum, data[i]);
      sum = 0;
    }
  }
  buffers_->txn.address = cfg_.address;
  buffers_->txn.write = {buffers_->tx, k};
  buffers_->txn.read = {buffers_->scratch + state_->at, static_cast<size_t>(withCrc ? 2 * readLen : readLen)};
  if (kStats) ++buffers_->stats.transactions;
  state_->wait = Wait::Bus;
  const Status s = bus_.start({&buffers_->txn, 1}, ctx_.busNotify());
  if (s != Status::Ok) {
    // Nothing started (another driver owns the bus): report it through the normal completion path so the
    // operation still ends (or retries) from onEvent().
    buffers_->txn.status = s;
    ctx_.scheduler.post(ctx_.task, ctx_.busEvent);
  }
}

Progress Link::onEvent(sched::EventMask events) {
  const bool running = busy();
  if (state_->wait == Wait::Bus && (events & ctx_.busEvent) != 0) {
    state_->wait = Wait::None;
    onBus();
  } else if (state_->wait == Wait::Timer && (events & ctx_.timerEvent) != 0) {
    state_->wait = Wait::None;
    phase(state_->phase);
  }
  return running && !busy() ? Progress::Done : Progress::Running;
}

void Link::onBus() {
  if (buffers_->txn.status != Status::Ok) return fail(buffers_->txn.status);
  const size_t readLen = buffers_->txn.read.size();
  if (crc() && readLen != 0) {
    // The first CRC of a read covers addr+W, the command, addr+R and the first data byte; then each byte
    // alone. The data are compacted in place over their CRCs.
    const uint8_t addressW = static_cast<uint8_t>(cfg_.address << 1);
    uint8_t sum =
        crc::crc8Update(crc::crc8Update(crc::crc8Update(0, addressW), buffers_->tx[0]), addressW | 1);
    uint8_t* w = buffers_->txn.read.data();
    for (size_t i = 0; i < readLen / 2; ++i) {
      const uint8_t d = w[2 * i];
      if (crc::crc8Update(sum, d) != w[2 * i + 1]) return fail(Status::Crc);
      sum = 0;
      w[i] = d;
    }
  }
  switch (state_->phase) {
    case Phase::Main:
      if (state_->op >= Op::SubRead) {
        state_->phase = Phase::Poll;
        return wait(cfg_.pollInterval < cfg_.firstPoll ? cfg_.firstPoll : cfg_.pollInterval);
      }
      if (state_->op == Op::SubWrite && state_->dataLen != 0) return phase(Phase::Commit);
      return finish(Status::Ok);
    case Phase::Poll: {
      // 0x3E/0x3F read FF FF while the subcommand runs and echo the code when its result is in the buffer;
      // anything else means the device lost the command (reset, bus error): start over. A poll whose two
      // bytes straddle the end of the command reads 0x3E still busy (FF) and 0x3F already the code's high
      // byte (the read goes 0x3E first): the command has run, so that is one more poll, not a restart that
      // would send the command again (ALL_FETS_OFF then took 2.5 ms instead of 1.6 ms on the twin).
      const uint16_t echo = static_cast<uint16_t>(buffers_->scratch[0] | (buffers_->scratch[1] << 8));
      if (echo == state_->code) return state_->op == Op::Sub ? finish(Status::Ok) : phase(Phase::Fetch);
      if (echo != 0xFFFF && echo != (0x00FF | (state_->code & 0xFF00))) return fail(Status::EchoMismatch);
      if (++state_->polls >= cfg_.maxPolls) return fail(Status::Timeout);
      if (kStats) ++buffers_->stats.polls;
      return wait(cfg_.pollInterval);
    }
    case Phase::Fetch: {
      // 0x61 counts the buffer bytes plus 4; the checksum at 0x60 covers the code and every buffer byte the
      // device reports, whatever the TRM says the command returns (FW_VERSION reports 11, E2E 1010048).
      const uint8_t length = buffers_->scratch[kBufferBytes + 1];
      if (length < 4 || length > kBufferBytes + 4 || length - 4 < state_->len) return fail(Status::Length);
      if (transferChecksum(state_->code, buffers_->scratch, length - 4) != buffers_->scratch[kBufferBytes])
        return fail(Status::Checksum);
      state_->reported = static_cast<uint8_t>(length - 4);
      return finish(Status::Ok);
    }
    case Phase::Commit:
      return finish(Status::Ok);
  }
}

void Link::fail(Status s) {
  if (kStats && static_cast<uint8_t>(s) < kLinkStatusCount) ++buffers_->stats.errors[static_cast<uint8_t>(s)];
  if (state_->attempt >= cfg_.retries) return finish(s);
  ++state_->attempt;
  ++buffers_->stats.retries;
  state_->phase = Phase::Main;
  state_->polls = 0;
  wait(kConfigPaths ? cfg_.retryDelay + state_->delay : cfg_.retryDelay);
}

void Link::finish(Status s) {
  state_->result = s;
  state_->op = Op::Idle;
}

void Link::wait(Duration d) {
  state_->wait = Wait::Timer;
  ctx_.scheduler.startTimer(buffers_->timer, ctx_.task, ctx_.timerEvent, d);
}

}  // namespace fw::drivers::bq769x2
