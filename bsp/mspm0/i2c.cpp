#include "i2c.hpp"

#include "gpio.hpp"
#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/gpio.hpp"

namespace bsp::mspm0 {

namespace i2c = reg::i2c;
using fw::Status;
using fw::hal::I2cTransaction;

namespace {

constexpr uint32_t kCommonIrqs = i2c::kIntNack | i2c::kIntStop | i2c::kIntArbLost | i2c::kIntTimeoutA;
// RX at 7 of the 8 entries: one interrupt per 7 bytes read (a 26-byte read takes 3 and the STOP's, 6 and the
// STOP's at level 4). The eighth byte still arrives meanwhile, so the handler has a byte time (22.5 us at
// 400 kHz, 90 us at 100 kHz) before a full FIFO makes the controller hold SCL (SLAU847D 21.2 controller RX
// FIFO: no byte is lost either way, the bus only waits).
constexpr uint32_t kFifoTriggers = i2c::kFifoTxTrigLevel4 | i2c::kFifoRxTrigLevel7;
// MFIFOSR with both FIFOs empty: all 8 TX entries free, no RX byte.
constexpr uint32_t kFifosEmpty = i2c::kFifoDepth << i2c::kFifoTxFreeShift;
// A flush completes within a few functional clocks; 64 polls (several microseconds even at /8) bound it.
constexpr uint32_t kFlushPolls = 64;
// Bus recovery runs at 100 kHz or slower whatever the bus speed: 5 us half periods = 40 spin iterations of
// 4 cycles at 32 MHz.
constexpr uint32_t kRecoveryHalfPeriodSpins = 40;
// PINCM for I2C pins: input enabled, open drain (a driven 1 is Hi-Z), as TI's example sets them (tsv row
// "PA0 I2C0_SDA ... input function + HiZ").
constexpr uint32_t kOpenDrainInput = reg::iomux::kInputEnable | reg::iomux::kHiZ1;

}  // namespace

void I2cController::init() {
  reg::resetAndPowerUp(reg::gprcm(config_.base));
  muxPeripheral(config_.sda, kOpenDrainInput);
  muxPeripheral(config_.scl, kOpenDrainInput);
  configure();
  nvic::enable(config_.irq);
}

void I2cController::configure() {
  i2c::Clock& clock = i2c::clock(config_.base);
  clock.clksel.write(i2c::kClkselBusclk);
  clock.clkdiv.write(config_.timing.clkdivRatio);
  i2c::Controller& r = i2c::controller(config_.base);
  // GFCTL keeps its reset value 0: no glitch filter, as TI's I2C controller and bq769x2 examples (their
  // set-up clears GFCTL.AGFEN) and TI's Zephyr driver leave it. The analog filter (AGFEN) alone
  // would not even be in the path: without GFCTL.CHAIN only the digital filter's output reaches the
  // controller (hw_i2c.h GFCTL.CHAIN), and TI documents no example that chains them (README, choices).
  r.mtpr.write(config_.timing.tpr);
  r.mfifoctl.write(kFifoTriggers);
  r.timeoutCtl.write(i2c::kTimeoutAEnable | config_.timing.timeoutCount);
  reg::EventBlock& events = reg::cpuInt(config_.base);
  events.imask.write(0);
  events.iclr.write(0xFFFFFFFF);
  r.mcr.write(i2c::kMcrActive | i2c::kMcrClkStretch);
}

Status I2cController::doStart(std::span<I2cTransaction> list, const fw::hal::Notify& done) {
  if (list.empty() || list.size() > (kI2cLists ? 255U : 1U)) return Status::InvalidArgument;
  if (busy_) return Status::Busy;
  for (I2cTransaction& t : list) {
    if ((t.write.empty() && t.read.empty()) || t.address > 0x7F || t.read.size() > 255 ||
        t.write.size() > i2c::kMctrLenMax - 1 || (!kI2cPec && (t.pec || t.blockRead))) {
      return Status::InvalidArgument;
    }
    t.status = Status::Aborted;  // what every transaction after a failure keeps
    t.readCount = 0;
  }
  busy_ = true;
  list_ = list;
  done_ = done;
  if (kI2cLists) index_ = 0;
  startTransaction();
  return Status::Ok;
}

void I2cController::startTransaction() {
  i2c::Controller& r = i2c::controller(config_.base);
  const I2cTransaction& t = current();
  // A target that was reset mid-byte can hold SDA low on an idle bus; the controller would then wait for
  // the bus forever. Free it first (I2C UM10204 3.1.16).
  if ((r.mbmon.read() & i2c::kMbmonSda) == 0 && !recoverBus()) {
    // Report from the ISR, as the contract promises: pend the IRQ and let onInterrupt() complete.
    stuck_ = true;
    phase_ = Phase::Write;
    nvic::setPending(config_.irq);
    return;
  }
  result_ = Status::Ok;
  flushFifos();  // first: if it has to reset the controller, the settings below come after the reset
  const bool pec = kI2cPec && t.pec;
  // PECCNT counts the data bytes of the whole transaction (both bursts) including the PEC byte; writing
  // the register also restarts the hardware byte count. A block read's length is known only from its count
  // byte: PECCNT stays 0 (no byte is taken for the PEC) until then, while the CRC runs over every byte from
  // the START on (hw_i2c.h CONTROLLER_I2CPECCTL PECEN / PECCNT).
  if (kI2cPec) {
    const uint32_t count = t.blockRead ? 0 : static_cast<uint32_t>(t.write.size() + t.read.size() + 1);
    r.pecctl.write(pec ? i2c::kPecEnable | count : 0);
  }
  reg::cpuInt(config_.base).iclr.write(0xFFFFFFFF);
  if (t.write.empty()) {
    beginRead();
    return;
  }
  tx_ = t.write.data();
  txLeft_ = static_cast<uint16_t>(t.write.size());
  txPecDummy_ = pec && t.read.empty();
  const uint32_t length = t.write.size() + (txPecDummy_ ? 1 : 0);  // before fillTx() consumes the dummy
  fillTx();
  const bool more = txLeft_ != 0 || (kI2cPec && txPecDummy_);
  phase_ = Phase::Write;
  // TXDONE only where a read follows (beginRead()); a write alone ends at its STOP, one interrupt.
  reg::cpuInt(config_.base)
      .imask.write(kCommonIrqs | (t.read.empty() ? 0 : i2c::kIntTxDone) | (more ? i2c::kIntTxFifoTrig : 0));
  r.msa.write(static_cast<uint32_t>(t.address) << 1);
  // No STOP when a read follows: the controller keeps the bus and the next START is a repeated START.
  r.mctr.write((length << i2c::kMctrLenShift) | i2c::kMctrBurstRun | i2c::kMctrStart |
               (t.read.empty() ? i2c::kMctrStop : 0));
}

void I2cController::beginRead() {
  i2c::Controller& r = i2c::controller(config_.base);
  const I2cTransaction& t = current();
  rx_ = t.read.data();
  rxLeft_ = static_cast<uint16_t>(t.read.size());
  const bool block = kI2cPec && t.blockRead;
  reg::cpuInt(config_.base)
      .imask.write(kCommonIrqs | i2c::kIntRxFifoTrig | (kI2cPec ? i2c::kIntPecRxErr : 0) |
                   (block ? i2c::kIntRxDone : 0));
  r.msa.write((static_cast<uint32_t>(t.address) << 1) | i2c::kMsaRead);
  if (block) {
    // The count byte alone, ACKed, no STOP: the controller keeps the bus and raises RXDONE (blockCount()
    // continues the read).
    phase_ = Phase::BlockCount;
    r.mctr.write((1U << i2c::kMctrLenShift) | i2c::kMctrAck | i2c::kMctrBurstRun | i2c::kMctrStart);
    return;
  }
  phase_ = Phase::Read;
  const uint32_t length = t.read.size() + (kI2cPec && t.pec ? 1 : 0);
  // ACK = 0: the last byte is NACKed, as a controller receiver must before STOP.
  r.mctr.write((length << i2c::kMctrLenShift) | i2c::kMctrBurstRun | i2c::kMctrStart | i2c::kMctrStop);
}

// RXDONE after a block read's count byte. The sequence is TI's SMBus library's (mspm0-sdk source/ti/smbus
// smbus_nwk.c SMBus_NWK_startRxTransfer / SMBus_NWK_startRxBlockPayloadTransfer, smbus_phy.c
// SMBus_PHY_controllerStartRx): the count byte was read alone with MBLEN 1, ACK = 1 and no STOP, so the
// controller acknowledged it and keeps the bus; a burst without START now continues the receive (SLAU846A
// I2C controller transfer table: a burst without START continues the receive), N data bytes plus the PEC
// with PECCNT rewritten to N + 1 in between (a PECCTL write clears the byte count, not the CRC: hw_i2c.h
// CONTROLLER_I2CPECCTL.PECCNT), the last byte NACKed (ACK = 0) and STOP. A count of 0 or one that does not
// fit the buffer was already acknowledged, so the target sends on: one more byte is read and NACKed before
// the STOP, which ends the read the way I2C requires (UM10204 3.1.6) where TI's library sends a bare STOP:
// Length, readCount 1. The controller ACK override (MCTR.MACKOEN) is not used: no TI example or library
// does (README, open questions).
void I2cController::blockCount() {
  i2c::Controller& r = i2c::controller(config_.base);
  I2cTransaction& t = current();
  // I2C_ERR_08 (SLAZ741/SLAZ742): at RXDONE the RX FIFO may not hold the byte yet ("wait 2 I2C CLK cycles");
  // its count is polled, bounded, instead of being read at once.
  for (uint32_t poll = 0; poll < kFlushPolls && (r.mfifosr.read() & i2c::kFifoRxCountMask) == 0; ++poll) {
  }
  drainRx();
  const uint32_t count = t.read[0];
  uint32_t length = 1;  // a count that does not fit: the byte after it, NACKed
  if (t.readCount == 1 && count != 0 && count <= rxLeft_) {
    rxLeft_ = static_cast<uint16_t>(count);
    const uint32_t pec = t.pec ? 1 : 0;
    if (pec) r.pecctl.write(i2c::kPecEnable | (count + 1));
    length = count + pec;
  } else {
    result_ = Status::Length;
    rxLeft_ = 0;  // the extra byte is not stored
  }
  phase_ = Phase::BlockData;
  r.mctr.write((length << i2c::kMctrLenShift) | i2c::kMctrBurstRun | i2c::kMctrStop);
}

// Empties both FIFOs (bytes a NACKed or aborted transfer left behind) the way the TRM asks: set the flush
// bits, wait until MFIFOSR shows TXFIFOCNT = 8 and RXFIFOCNT = 0, then clear them (hw_i2c.h MFIFOCTL.TXFLUSH
// and RXFLUSH: check the counts before clearing the bit). The wait is bounded; a flush that has not
// finished by then is finished by a controller reset, which empties the FIFOs too.
void I2cController::flushFifos() {
  i2c::Controller& r = i2c::controller(config_.base);
  r.mfifoctl.write(kFifoTriggers | i2c::kFifoTxFlush | i2c::kFifoRxFlush);
  for (uint32_t poll = 0; poll < kFlushPolls; ++poll) {
    if ((r.mfifosr.read() & (i2c::kFifoTxFreeMask | i2c::kFifoRxCountMask)) == kFifosEmpty) {
      r.mfifoctl.write(kFifoTriggers);
      return;
    }
  }
  reg::resetAndPowerUp(reg::gprcm(config_.base));
  configure();
}

// Queues as many write bytes as the TX FIFO has free entries (MFIFOSR.TXFIFOCNT), and the PEC dummy after
// the last one. A write to a full FIFO would be lost (MFIFOSR.TXFIFOCNT counts the free entries, hw_i2c.h).
// One status read is enough: the FIFO only drains while we fill it.
void I2cController::fillTx() {
  i2c::Controller& r = i2c::controller(config_.base);
  uint32_t room = (r.mfifosr.read() & i2c::kFifoTxFreeMask) >> i2c::kFifoTxFreeShift;
  while (room != 0 && txLeft_ != 0) {
    r.mtxdata.write(*tx_++);
    --txLeft_;
    --room;
  }
  if (kI2cPec && room != 0 && txPecDummy_) {
    r.mtxdata.write(0);  // replaced on the wire by the PEC
    txPecDummy_ = false;
  }
}

void I2cController::drainRx() {
  i2c::Controller& r = i2c::controller(config_.base);
  // RXFIFOCNT is at most 8, so both loops are bounded. The bytes are stored through a local pointer by a loop
  // with no other test (a store through rx_ may alias any member, which would be reloaded for every byte).
  uint32_t count = r.mfifosr.read() & i2c::kFifoRxCountMask;
  const uint32_t stored = count < rxLeft_ ? count : rxLeft_;
  uint8_t* rx = rx_;
  uint8_t* const end = rx + stored;
  if (rx != end) {
    do {
      *rx++ = static_cast<uint8_t>(r.mrxdata.read());
    } while (rx != end);
  }
  for (count -= stored; count != 0; --count)
    (void)r.mrxdata.read();  // the PEC byte, already checked by the hardware
  rx_ = rx;
  rxLeft_ = static_cast<uint16_t>(rxLeft_ - stored);
  I2cTransaction& t = current();
  t.readCount = static_cast<uint8_t>(t.readCount + stored);
}

void I2cController::onInterrupt() {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  const uint32_t pending = events.mis.read();
  events.iclr.write(pending);
  if (phase_ == Phase::Idle) return;
  // The most frequent interrupt, 7 bytes in the middle of a read, alone: no other bit to look at.
  if (pending == i2c::kIntRxFifoTrig) {
    drainRx();
    return;
  }

  if (stuck_) {
    stuck_ = false;
    complete(Status::BusStuck);
    return;
  }
  if (pending & i2c::kIntTimeoutA) {
    complete(recoverBus() ? Status::Timeout : Status::BusStuck);
    return;
  }
  if (pending & i2c::kIntArbLost) {
    complete(Status::ArbitrationLost);
    return;
  }
  if ((pending & i2c::kIntNack) && result_ == Status::Ok) {
    result_ = (i2c::controller(config_.base).msr.read() & i2c::kMsrAdrAck) ? Status::Nack : Status::DataNack;
  }
  if (kI2cPec && (pending & i2c::kIntPecRxErr) && result_ == Status::Ok) result_ = Status::Pec;
  if (pending & i2c::kIntRxFifoTrig) drainRx();
  if (pending & i2c::kIntTxFifoTrig) {
    fillTx();
    if (txLeft_ == 0 && !(kI2cPec && txPecDummy_)) mmio::clearBits(events.imask, i2c::kIntTxFifoTrig);
  }
  if (pending & i2c::kIntStop) {
    drainRx();
    complete(result_);
    return;
  }
  if (kI2cPec && (pending & i2c::kIntRxDone) && phase_ == Phase::BlockCount) {
    blockCount();
    return;
  }
  if ((pending & i2c::kIntTxDone) && phase_ == Phase::Write && result_ == Status::Ok &&
      !current().read.empty()) {
    beginRead();
  }
}

void I2cController::complete(Status status) {
  current().status = status;
  if (kI2cLists && status == Status::Ok && index_ + 1U < list_.size()) {
    ++index_;
    startTransaction();
    return;
  }
  finish();
}

inline void I2cController::finish() {
  reg::cpuInt(config_.base).imask.write(0);
  phase_ = Phase::Idle;
  busy_ = false;
  done_();
}

Status I2cController::doRecover() {
  if (busy_) return Status::Busy;
  return recoverBus() ? Status::Ok : Status::BusStuck;
}

namespace {

// One line of the bus as an open-drain GPIO during recovery: DOUT 1 releases it (the pull-up raises it),
// DOUT 0 pulls it low. Each change is followed by half a recovery clock period.
struct RecoveryLine {
  const Pin& pin;

  reg::gpio::Data& port() const { return reg::gpio::data(pin.portBase()); }
  void drive(bool high) const {
    (high ? port().doutset : port().doutclr).write(pin.mask());
    mmio::spin(kRecoveryHalfPeriodSpins);
  }
  bool high() const { return (reg::gpio::input(pin.portBase()).din.read() & pin.mask()) != 0; }
  // Released high first, then the output driver on and the pin muxed to GPIO, so it never glitches low.
  void takeAsGpio() const {
    port().doutset.write(pin.mask());
    port().doeset.write(pin.mask());
    reg::iomux::pincm(pin.pincm).write(reg::iomux::kPc | reg::iomux::kPfGpio | kOpenDrainInput);
  }
  void giveBack(const PinFunction& function) const {
    port().doeclr.write(pin.mask());
    muxPeripheral(function, kOpenDrainInput);
  }
};

}  // namespace

bool I2cController::recoverBus() {
  const RecoveryLine sda{config_.sda.pin};
  const RecoveryLine scl{config_.scl.pin};
  // Stop the controller from driving the lines, then take both pins as open-drain GPIOs released high.
  reg::resetAndPowerUp(reg::gprcm(config_.base));
  sda.takeAsGpio();
  scl.takeAsGpio();
  // Up to 9 clocks: a target stuck mid-byte releases SDA at the latest after its last bit and ACK slot.
  for (int clock = 0; clock < 9 && !sda.high(); ++clock) {
    scl.drive(false);
    scl.drive(true);
  }
  // STOP: SDA rises while SCL is high.
  scl.drive(false);
  sda.drive(false);
  scl.drive(true);
  sda.drive(true);
  const bool free = sda.high() && scl.high();
  sda.giveBack(config_.sda);
  scl.giveBack(config_.scl);
  configure();
  return free;
}

}  // namespace bsp::mspm0
