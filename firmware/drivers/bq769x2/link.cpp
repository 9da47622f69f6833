#include "drivers/bq769x2/link.hpp"

#include "core/assert.hpp"
#include "core/crc.hpp"

namespace fw::drivers::bq769x2 {

FW_MODULE(Module::DriverBq769x2);

namespace {

// One CRC-8 step, kept out of line so the three users share one copy of the bit loop.
[[gnu::noinline]] uint8_t crcStep(uint8_t crc, uint8_t byte) {
  return crc::crc8Update(crc, byte);
}

}  // namespace

Link::Link(hal::I2cBus& bus, const DriverContext& context, const LinkConfig& config)
    : crc_(config.crc),
      address_(config.address),
      retries_(config.retries),
      maxPolls_(config.maxPolls),
      bus_(bus),
      ctx_(context),
      retryDelay_(config.retryDelay),
      pollInterval_(config.pollInterval) {}

Status Link::startRead(uint8_t cmd, uint8_t len, uint8_t at, Duration delay) {
  if (busy()) return Status::Busy;
  if (len == 0 || at + len * (crc_ ? 2 : 1) > kScratchBytes) return Status::InvalidArgument;
  at_ = at;
  delay_ = delay;
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
  if (bytes.size() > kMaxWriteData || len > kMaxReadBytes || (op != Op::Read && len > kBufferBytes))
    return Status::InvalidArgument;
  if (op != Op::Read) {
    at_ = 0;
    delay_ = {};
  }
  op_ = op;
  code_ = code;
  len_ = len;
  attempt_ = 0;
  reported_ = 0;
  data_[0] = static_cast<uint8_t>(code);
  data_[1] = static_cast<uint8_t>(code >> 8);
  dataLen_ = static_cast<uint8_t>(bytes.size());
  for (uint8_t i = 0; i < dataLen_; ++i)
    data_[2 + i] = bytes[i];
  phase_ = Phase::Main;
  polls_ = 0;
  if (delay_.us != 0) {
    wait(delay_);
  } else {
    phase(Phase::Main);
  }
  return Status::Ok;
}

void Link::phase(Phase p) {
  phase_ = p;
  switch (p) {
    case Phase::Main:
      // A direct access sends its command byte and data; a subcommand sends 0x3E, the code and data.
      if (op_ <= Op::Write) {
        transfer(data_[0], data_ + 2, dataLen_, op_ == Op::Read ? len_ : 0);
      } else {
        transfer(kCmdSubcommand, data_, static_cast<uint8_t>(dataLen_ + 2), 0);
      }
      break;
    case Phase::Poll:
      transfer(kCmdSubcommand, nullptr, 0, 2);
      break;
    case Phase::Fetch:
      transfer(kCmdBuffer, nullptr, 0, kWindowBytes);
      break;
    case Phase::Commit: {
      // SLUAA11B section 3.3: the checksum covers 0x3E, 0x3F and the data; the length counts them plus
      // 0x60 and 0x61 (data + 4).
      const uint8_t tail[2] = {transferChecksum(code_, data_ + 2, dataLen_),
                               static_cast<uint8_t>(dataLen_ + 4)};
      transfer(kCmdChecksum, tail, 2, 0);
      break;
    }
  }
}

// Builds and starts one transaction. With CRC on, a CRC follows every data byte: the first covers
// addr+W, the command and that byte, each later one its byte alone (SLUAA11B section 4).
void Link::transfer(uint8_t cmd, const uint8_t* data, uint8_t count, uint8_t readLen) {
  const uint8_t addressW = static_cast<uint8_t>(address_ << 1);
  uint8_t crc = crcStep(crcStep(0, addressW), cmd);
  uint8_t k = 0;
  tx_[k++] = cmd;
  for (uint8_t i = 0; i < count; ++i) {
    tx_[k++] = data[i];
    if (crc_) {
      tx_[k++] = crcStep(crc, data[i]);
      crc = 0;
    }
  }
  txn_.address = address_;
  txn_.write = {tx_, k};
  txn_.read = {scratch_ + at_, static_cast<size_t>(crc_ ? 2 * readLen : readLen)};
  ++stats_.transactions;
  wait_ = Wait::Bus;
  const Status s = bus_.start({&txn_, 1}, ctx_.busNotify());
  if (s != Status::Ok) {
    // Nothing started (another driver owns the bus): report it through the normal completion path so the
    // operation still ends (or retries) from onEvent().
    txn_.status = s;
    ctx_.scheduler.post(ctx_.task, ctx_.busEvent);
  }
}

Progress Link::onEvent(sched::EventMask events) {
  const bool running = busy();
  if (wait_ == Wait::Bus && (events & ctx_.busEvent) != 0) {
    wait_ = Wait::None;
    onBus();
  } else if (wait_ == Wait::Timer && (events & ctx_.timerEvent) != 0) {
    wait_ = Wait::None;
    phase(phase_);
  }
  return running && !busy() ? Progress::Done : Progress::Running;
}

void Link::onBus() {
  if (txn_.status != Status::Ok) return fail(txn_.status);
  const size_t readLen = txn_.read.size();
  if (crc_ && readLen != 0) {
    // The first CRC of a read covers addr+W, the command, addr+R and the first data byte; then each byte
    // alone. The data are compacted in place over their CRCs.
    const uint8_t addressW = static_cast<uint8_t>(address_ << 1);
    uint8_t crc = crcStep(crcStep(crcStep(0, addressW), tx_[0]), addressW | 1);
    uint8_t* w = txn_.read.data();
    for (size_t i = 0; i < readLen / 2; ++i) {
      const uint8_t d = w[2 * i];
      if (crcStep(crc, d) != w[2 * i + 1]) return fail(Status::Crc);
      crc = 0;
      w[i] = d;
    }
  }
  switch (phase_) {
    case Phase::Main:
      if (op_ >= Op::SubRead) {
        phase_ = Phase::Poll;
        return wait(pollInterval_);
      }
      if (op_ == Op::SubWrite && dataLen_ != 0) return phase(Phase::Commit);
      return finish(Status::Ok);
    case Phase::Poll: {
      // 0x3E/0x3F read FF FF while the subcommand runs and echo the code when its result is in the buffer;
      // anything else means the device lost the command (reset, bus error): start over.
      const uint16_t echo = static_cast<uint16_t>(scratch_[0] | (scratch_[1] << 8));
      if (echo == code_) return op_ == Op::Sub ? finish(Status::Ok) : phase(Phase::Fetch);
      if (echo != 0xFFFF) return fail(Status::EchoMismatch);
      if (++polls_ >= maxPolls_) return fail(Status::Timeout);
      ++stats_.polls;
      return wait(pollInterval_);
    }
    case Phase::Fetch: {
      // 0x61 counts the buffer bytes plus 4; the checksum at 0x60 covers the code and every buffer byte the
      // device reports, whatever the TRM says the command returns (FW_VERSION reports 11, E2E 1010048).
      const uint8_t length = scratch_[kBufferBytes + 1];
      if (length < 4 || length > kBufferBytes + 4 || length - 4 < len_) return fail(Status::Length);
      if (transferChecksum(code_, scratch_, length - 4) != scratch_[kBufferBytes])
        return fail(Status::Checksum);
      reported_ = static_cast<uint8_t>(length - 4);
      return finish(Status::Ok);
    }
    case Phase::Commit:
      return finish(Status::Ok);
  }
}

void Link::fail(Status s) {
  if (static_cast<uint8_t>(s) < kLinkStatusCount) ++stats_.errors[static_cast<uint8_t>(s)];
  if (attempt_ >= retries_) return finish(s);
  ++attempt_;
  ++stats_.retries;
  phase_ = Phase::Main;
  polls_ = 0;
  wait(retryDelay_ + delay_);
}

void Link::finish(Status s) {
  result_ = s;
  op_ = Op::Idle;
}

void Link::wait(Duration d) {
  wait_ = Wait::Timer;
  ctx_.scheduler.startTimer(timer_, ctx_.task, ctx_.timerEvent, d);
}

}  // namespace fw::drivers::bq769x2
