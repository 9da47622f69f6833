// Link: the I2C protocol shared by the BQ769x2 (BQ76952...) and BQ7690x (BQ76905/BQ76907) battery monitors,
// as a non-blocking driver layer (drivers/operation.hpp).
//
// The device is an I2C target at a 7-bit address (0x08 by default: 0x10 write / 0x11 read on the wire).
// Everything goes through its 128-byte direct-command space, which auto-increments through consecutive
// commands on reads and writes (TI E2E 1560065: "read 32 bytes from 0x14 and it will read all of the cell
// voltages"), plus the subcommand window inside it:
//   0x3E/0x3F  subcommand code or data-memory address (little-endian); both read 0xFF while it executes and
//              echo the code once the result is ready
//   0x40..0x5F the 32-byte transfer buffer (the result, or data to write)
//   0x60       checksum = ~(0x3E + 0x3F + buffer bytes) & 0xFF
//   0x61       length = buffer bytes + 4
//
// Operations (each: start*() returns Ok when started, Busy while another runs, InvalidArgument for a
// malformed request; then onEvent() until Progress::Done, then result()):
//   startRead(cmd, len, at, delay)  one transaction: S addr+W cmd Sr addr+R [len bytes] P. The bytes land in
//                                   data() (data()[0] = the byte of `cmd`) at scratch offset `at`, so a
//                                   caller can gather several reads in one buffer. `delay` waits first (a
//                                   poll interval) without blocking.
//   startWrite(cmd, bytes)          one transaction: S addr+W cmd bytes... P (1..kMaxWriteData bytes)
//   startSubcommand(code, await)    command-only subcommand: S addr+W 3E lo hi P, then (await) the echo poll
//                                   as below, so the command has run before the next one is written (a new
//                                   0x3E write while one runs would replace it). Without await it ends at the
//                                   write: for RESET, SHUTDOWN and DEEPSLEEP, after which the device does not
//                                   echo. Effects are for the caller to verify (e.g. the CFGUPDATE flag).
//   startSubcommandRead(code, len)  write 3E lo hi; poll 3E/3F every pollInterval (the first poll after
//                                   firstPoll if that is longer) until it echoes `code`
//                                   (at most maxPolls polls: Timeout; any other echo than FF FF or the code:
//                                   EchoMismatch); read 0x40..0x61 (32 + checksum + length); the length must
//                                   be 4..36 and cover `len` data bytes (Length); the checksum is checked
//                                   over the code and the whole buffer the device reports (Checksum).
//                                   data()[0..len) is the result; reported() the data bytes the device
//                                   reported (FW_VERSION reports more than it fills). A data-memory read is
//                                   the same at its address.
//   startSubcommandWrite(code, b)   write 3E lo hi b... then 60 checksum length (length = bytes + 4): the two
//                                   writes TI's SLUAA11B section 3 shows. A data-memory write is the same at
//                                   its address; the device ignores it unless it is in CONFIG_UPDATE.
//
// CRC mode (Comm Type with CRC; BQ7695202 ships with it on): every data byte on the wire is followed by a
// CRC-8 (poly 0x07, init 0): the first one covers every byte since START including the data byte (for a read
// also addr+R), every later one only its own data byte (SLUAA11B / SLUAAM4 section 4). The link adds them to
// writes and checks and strips them on reads (Crc); a device in CRC mode refuses a wrong CRC with a NACK.
//
// Failures and retries. A transaction ends in Ok, Nack (address), DataNack, Timeout (clock stretch beyond the
// bus limit, or no echo within the budget), BusStuck, ArbitrationLost, Crc, Checksum, Length or
// EchoMismatch. Any of them restarts the whole operation from its first byte (the register address is
// resent: a continued read would start wherever the auto-increment pointer stopped, LibreSolar #53) after
// retryDelay, up to `retries` more times; then the operation ends with the last failure. One NACK after
// power-up is therefore absorbed (E2E 1515940). Every wait is bounded: a bus transaction by the I2cBus
// contract (wire time + stretch limit), every other wait by this driver's timer.
//
// What only the monitor's configure operation uses (a delay before a read: the CFGUPDATE polls) is built
// unless FW_BQ769X_CONFIG_PATHS is 0 (drivers/bq769x2/config.hpp). Without it
// startRead() with a delay is InvalidArgument. Subcommand writes with data are always built: FET_CONTROL
// (the monitor's FET commands) needs them.
//
// Memory: one scratch buffer (kScratchBytes) that holds the longest read with its CRC bytes; the data stay
// there until the next operation starts (data() is only meaningful after an Ok result).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/status.hpp"
#include "core/time.hpp"
#include "core/zeroed.hpp"
#include "drivers/bq769x2/config.hpp"
#include "drivers/operation.hpp"
#include "hal/i2c_bus.hpp"
#include "regmap/bq7690x.hpp"
#include "regmap/bq769x2.hpp"
#include "sched/timer.hpp"

namespace fw::drivers::bq769x2 {

inline constexpr uint8_t kDefaultAddress = 0x08;  // 7-bit; 0x10/0x11 on the wire
inline constexpr uint8_t kCmdSubcommand = 0x3E;
inline constexpr uint8_t kCmdBuffer = 0x40;
inline constexpr uint8_t kCmdChecksum = 0x60;
inline constexpr uint8_t kBufferBytes = 32;                // 0x40..0x5F
inline constexpr uint8_t kWindowBytes = kBufferBytes + 2;  // 0x40..0x61: buffer, checksum, length
// The longest direct read: the largest scan block of either family (regmaps/*/commands.yaml `blocks`).
inline constexpr uint8_t kMaxReadBytes =
    std::max(regmap::bq769x2::blocks::kLargestSize, regmap::bq7690x::blocks::kLargestSize);
// The scan gathers its blocks and then the accumulated-charge read (the subcommand echo and 12 bytes) in the
// scratch, each with a CRC after every byte in CRC mode (monitor.hpp scanFits).
inline constexpr uint8_t kChargeReadBytes = 2 + 12;
inline constexpr uint8_t kScratchBytes = static_cast<uint8_t>(std::max<unsigned>(
    2u * kMaxReadBytes,
    std::max<unsigned>(regmap::bq769x2::blocks::kRecordSize, regmap::bq7690x::blocks::kRecordSize) +
        2u * kChargeReadBytes));
inline constexpr uint8_t kMaxWriteData = 4;  // data bytes of one write (U4/F4 data memory)

static_assert(kMaxReadBytes >= kWindowBytes,
              "a subcommand result (0x40..0x61) is fetched into the scratch too");

inline constexpr bool kConfigPaths = FW_BQ769X_CONFIG_PATHS != 0;
inline constexpr bool kCrc = FW_BQ769X_CRC != 0;
inline constexpr bool kBalance =
    FW_BQ769X_BALANCE != 0;  // host-controlled balancing is built (drivers/bq769x2/config.hpp)
inline constexpr bool kCharge = FW_BQ769X_CHARGE != 0;
inline constexpr bool kSleepControl = FW_BQ769X_SLEEP != 0;

struct LinkConfig {
  uint8_t address = kDefaultAddress;
  bool crc = false;       // per-byte CRC-8 on the wire (must match the device's Comm Type)
  uint8_t retries = 2;    // extra attempts of a failed operation
  uint8_t maxPolls = 40;  // echo polls of a subcommand read: 40 x 250 us >= 10 ms (IROM_SIG takes ~8.5 ms)
  // The first echo poll comes no earlier than this after the command (pollInterval when shorter). The
  // BQ7690x variant raises it to 2 ms: no TI document found says the BQ7690x reads FF FF while a subcommand
  // runs (regmaps/README.md), so its result is fetched no earlier than TI's examples fetch one.
  Duration firstPoll{};
  Duration retryDelay = us(500);
  Duration pollInterval = us(250);
};

// Every Status a link attempt can fail with is below this one (Busy, Nack ... EchoMismatch).
inline constexpr uint8_t kLinkStatusCount = static_cast<uint8_t>(Status::EchoMismatch) + 1;

// Link statistics since construction (never reset by the driver). In a build without statistics
// (core/stats.hpp) only `retries` counts: the monitor's scan acts on it.
struct LinkStats {
  uint32_t transactions = 0;               // I2C transactions started
  uint32_t retries = 0;                    // whole-operation restarts
  uint32_t polls = 0;                      // echo polls that found the device still busy
  uint16_t errors[kLinkStatusCount] = {};  // failed attempts per Status (Nack, Crc, Checksum, ...)
};

class Link {
 public:
  // Inline: an image constructs it once, and the constructor is then stores only. `firstPollAtLeast`: the
  // device's own lower bound of LinkConfig::firstPoll (the monitor's variant).
  Link(hal::I2cBus& bus, const DriverContext& context, const LinkConfig& config,
       Duration firstPollAtLeast = {})
      : cfg_(config), bus_(bus), ctx_(context) {
    if (cfg_.firstPoll < firstPollAtLeast) cfg_.firstPoll = firstPollAtLeast;
  }
  Link(const Link&) = delete;
  Link& operator=(const Link&) = delete;

  Status startRead(uint8_t cmd, uint8_t len, uint8_t at = 0, Duration delay = {});
  Status startWrite(uint8_t cmd, std::span<const uint8_t> bytes);
  Status startSubcommand(uint16_t code, bool awaitEcho = true);
  Status startSubcommandRead(uint16_t code, uint8_t len);
  Status startSubcommandWrite(uint16_t code, std::span<const uint8_t> bytes);

  sched::EventMask events() const { return ctx_.events(); }
  Progress onEvent(sched::EventMask events);

  bool busy() const { return state_->op != Op::Idle; }
  Status result() const { return state_->result; }
  const uint8_t* data() const { return buffers_->scratch + state_->at; }
  uint8_t* scratch() { return buffers_->scratch; }
  uint8_t reported() const { return state_->reported; }
  bool crc() const { return kCrc && cfg_.crc; }
  void setCrc(bool on) { cfg_.crc = on; }  // when idle (the CRC-mode probe)
  Duration pollInterval() const { return cfg_.pollInterval; }
  const LinkStats& stats() const { return buffers_->stats; }

 private:
  enum class Op : uint8_t { Idle, Read, Write, SubWrite, SubRead, Sub };
  enum class Phase : uint8_t { Main, Poll, Fetch, Commit };
  enum class Wait : uint8_t { None, Bus, Timer };

  Status request(Op op, uint16_t code, std::span<const uint8_t> bytes, uint8_t len);
  void phase(Phase p);
  inline void transfer(uint8_t cmd, const uint8_t* data, uint8_t count, uint8_t readLen);
  void onBus();
  void fail(Status s);
  void finish(Status s);
  void wait(Duration d);

  // The operation in progress: small fields, zero at construction (one block, no per-member start-up code).
  struct State {
    Op op;
    Phase phase;
    Wait wait;
    Status result;
    uint8_t len;
    uint8_t at;
    uint8_t attempt;
    uint8_t polls;
    uint8_t reported;
    uint8_t dataLen;
    uint16_t code;  // subcommand code or data-memory address; the command byte of a direct access
    Duration delay;
  };
  // The buffers, zero at construction as well.
  struct Buffers {
    hal::I2cTransaction txn;
    sched::Timer timer;
    uint8_t data[2 + kMaxWriteData];          // code lo, hi, then the data of a write
    uint8_t tx[1 + 2 * (kMaxWriteData + 2)];  // command byte + data with CRCs
    LinkStats stats;
    uint8_t scratch[kScratchBytes];
  };

  // Byte fields first: Cortex-M0+ byte loads reach only 31 bytes past the object's base register. The
  // configuration is kept whole (its bytes first), so the constructor copies it as one block.
  LinkConfig cfg_;
  Zeroed<State> state_;
  hal::I2cBus& bus_;
  DriverContext ctx_;
  Zeroed<Buffers> buffers_;
};

// The transfer checksum: ~(sum of the code bytes and the data) & 0xFF (SLUUBY2B section 13.1).
constexpr uint8_t transferChecksum(uint16_t code, const uint8_t* data, size_t n) {
  uint8_t sum = static_cast<uint8_t>(code + (code >> 8));
  for (size_t i = 0; i < n; ++i)
    sum = static_cast<uint8_t>(sum + data[i]);
  return static_cast<uint8_t>(~sum);
}

}  // namespace fw::drivers::bq769x2
