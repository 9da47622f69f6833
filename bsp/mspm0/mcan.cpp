#include "mcan.hpp"

#include "core/bytes.hpp"
#include "gpio.hpp"
#include "hal/irq.hpp"
#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/gpio.hpp"

namespace bsp::mspm0 {

namespace mcan = reg::mcan;
using fw::Status;
using fw::hal::CanFrame;

namespace {

constexpr uint32_t kRxIrqs = kMcanRx ? mcan::kIrRf0n | mcan::kIrRf0l : 0;
constexpr uint32_t kIrqs = kRxIrqs | mcan::kIrTc | mcan::kIrEp | mcan::kIrBo;
// Bounded waits for hardware handshakes at start-up: about 1 ms each at 32 MHz.
constexpr uint32_t kPollLimit = 1000;
constexpr uint32_t kPollSpins = 8;

bool waitFor(const mmio::Reg& reg, uint32_t mask, uint32_t value) {
  for (uint32_t i = 0; i < kPollLimit; ++i) {
    if ((reg.read() & mask) == value) return true;
    mmio::spin(kPollSpins);
  }
  return false;
}

mmio::Reg* element(uintptr_t base, uint32_t startByte, uint32_t index) {
  return mcan::ram(base, startByte + index * mcan::kElementWords * 4);
}

}  // namespace

Status McanBus::init() {
  const uintptr_t base = config_.base;
  // MCAN keeps its GPRCM at +0x6800 (tsv note "GPRCM keys"); same keys as the others.
  reg::resetAndPowerUp(mcan::gprcm(base));
  muxPeripheral(config_.tx);
  muxPeripheral(config_.rx, reg::iomux::kInputEnable);
  // Request the module clock before setting its divider (TI's example set-up does it in this order):
  // CLK_REQEN gates the MCAN functional and register clocks (hw_mcan.h MCAN_CLKEN).
  mcan::SsClock& ssClock = mcan::ssClock(base);
  ssClock.clken.write(1);   // CLK_REQEN
  ssClock.clkdiv.write(0);  // CANCLK / 1
  if (!waitFor(mcan::ssStat(base), mcan::kSsMemInitDone, mcan::kSsMemInitDone)) return Status::NotReady;
  // Configuration needs INIT, then CCE (M_CAN user manual 3.1.1); INIT crosses clock domains, so wait.
  mcan::Core& core = mcan::core(base);
  core.cccr.write(mcan::kCccrInit);
  if (!waitFor(core.cccr, mcan::kCccrInit, mcan::kCccrInit)) return Status::NotReady;
  core.cccr.write(mcan::kCccrInit | mcan::kCccrCce);
  core.nbtp.write(config_.nbtp);
  mcan::Queues& q = mcan::queues(base);
  // Only the identifiers of the filter list are received (written while CCE and INIT are set, as TI's
  // example adds its filters during software initialisation); every other frame is rejected by the hardware.
  q.gfc.write(mcan::kGfcRejectAll);
  const uint32_t ids = kMcanRx ? static_cast<uint32_t>(config_.accept.size()) : 0;
  const uint32_t elements = (ids + 1) / 2;
  if (elements > kFilterElements) return Status::InvalidArgument;
  for (uint32_t k = 0; k < elements; ++k) {
    const uint32_t first = config_.accept[2 * k];
    mcan::ram(base, kFilterStart + 4 * k)
        ->write(mcan::stdFilterDual(first, 2 * k + 1 < ids ? config_.accept[2 * k + 1] : first));
  }
  q.sidfc.write(mcan::sidfc(kFilterStart, elements));
  q.xidfc.write(0);
  q.rxesc.write(0);  // 8-byte data fields
  q.txesc.write(0);
  if (kMcanRx) q.rxf0c.write(mcan::rxf0c(kRxFifoStart, kFifoElements));
  q.txbc.write(mcan::txbc(kTxFifoStart, kFifoElements));
  q.txbtie.write((1U << kFifoElements) - 1);  // TC for every TX FIFO element
  core.ir.write(0xFFFFFFFF);
  core.ie.write(kIrqs);
  core.ils.write(0);  // all on line 0
  core.ile.write(mcan::kIleLine0);
  reg::EventBlock& events = mcan::cpuInt(base);
  events.iclr.write(mcan::kIntLine0);
  events.imask.write(mcan::kIntLine0);
  // Leave INIT; the controller joins the bus after 11 recessive bits. INIT reads back only once it has
  // crossed into the CAN clock domain, and must be seen before INIT is written again (hw_mcan.h MCAN_CCCR):
  // wait for it, as TI's example set-up polls the operation mode until it reads normal operation.
  core.cccr.write(0);
  if (!waitFor(core.cccr, mcan::kCccrInit, 0)) return Status::NotReady;
  ready_ = true;
  nvic::enable(config_.irq);
  return Status::Ok;
}

Status McanBus::doSend(const CanFrame& frame) {
  if (frame.dlc > 8 || frame.id > (frame.extended ? 0x1FFFFFFFU : 0x7FFU)) return Status::InvalidArgument;
  if (!ready_) return Status::NotReady;
  if (mcan::core(config_.base).psr.read() & mcan::kPsrBusOff) return Status::BusOff;
  mcan::Queues& q = mcan::queues(config_.base);
  fw::hal::CriticalSection cs;  // the put index and inFlight_ are shared with the ISR and other senders
  const uint32_t fqs = q.txfqs.read();
  if (fqs & mcan::kTxfqsFull) {
    txOverflows_ = txOverflows_ + 1;
    return Status::Overflow;
  }
  const uint32_t put = (fqs >> mcan::kTxfqsPutShift) & mcan::kTxfqsPutMask;
  mmio::Reg* e = element(config_.base, kTxFifoStart, put);
  e[0].write(frame.extended ? (mcan::kElemXtd | frame.id) : (frame.id << mcan::kElemStdIdShift));
  e[1].write(static_cast<uint32_t>(frame.dlc) << mcan::kElemDlcShift);
  for (uint32_t word = 0; word < 2; ++word)
    e[2 + word].write(fw::bytes::loadLe32(&frame.data[4 * word]));
  inFlight_ = inFlight_ | (1U << put);
  q.txbar.write(1U << put);
  return Status::Ok;
}

bool McanBus::doReceive(CanFrame& frame) {
  if constexpr (!kMcanRx) return false;  // built without reception: nothing is ever received
  if (!ready_) return false;             // never initialised: nothing to read, possibly unpowered (doState)
  mcan::Queues& q = mcan::queues(config_.base);
  const uint32_t status = q.rxf0s.read();
  if ((status & mcan::kRxf0sFillMask) == 0) return false;
  const uint32_t get = (status >> mcan::kRxf0sGetShift) & mcan::kRxf0sGetMask;
  const mmio::Reg* e = element(config_.base, kRxFifoStart, get);
  const uint32_t r0 = e[0].read();
  const uint32_t r1 = e[1].read();
  frame.extended = (r0 & mcan::kElemXtd) != 0;
  frame.id = frame.extended ? (r0 & 0x1FFFFFFF) : ((r0 >> mcan::kElemStdIdShift) & 0x7FF);
  frame.dlc = static_cast<uint8_t>((r1 >> mcan::kElemDlcShift) & 0xF);
  if (frame.dlc > 8) frame.dlc = 8;  // classic CAN: DLC 9..15 still mean 8 bytes
  for (uint32_t word = 0; word < 2; ++word)
    fw::bytes::storeLe32(&frame.data[4 * word], e[2 + word].read());
  q.rxf0a.write(get);
  ++rxFrames_;
  return true;
}

void McanBus::onInterrupt() {
  const uintptr_t base = config_.base;
  reg::EventBlock& events = mcan::cpuInt(base);
  if ((events.mis.read() & mcan::kIntLine0) == 0) return;
  events.iclr.write(mcan::kIntLine0);
  mcan::Core& core = mcan::core(base);
  const uint32_t ir = core.ir.read() & kIrqs;
  core.ir.write(ir);  // write 1 to clear, only what we handle
  // End of interrupt: the MCAN subsystem holds its line-0 interrupt until EOI is written with 0x01, and
  // asserts it again at once if a source is still pending (hw_mcan.h MCAN_EOI). TI's example ISR writes it
  // right after clearing IR, as here; the wrapper flag was cleared first, so a re-assertion is not lost.
  mcan::ssEoi(base).write(mcan::kSsEoiLine0);
  if (ir & mcan::kIrTc) {
    const uint32_t sent = mcan::queues(base).txbto.read() & inFlight_;
    inFlight_ = inFlight_ & ~sent;
    uint32_t n = txFrames_;
    for (uint32_t bits = sent; bits != 0; bits &= bits - 1)
      ++n;
    txFrames_ = n;
  }
  if ((ir & mcan::kIrBo) && (core.psr.read() & mcan::kPsrBusOff)) busOffEvents_ = busOffEvents_ + 1;
  if (ir & mcan::kIrRf0l) rxLost_ = rxLost_ + 1;
  if (ir & mcan::kIrRf0n) rxNotify_();
  if (ir & ~kRxIrqs) notify_();
}

fw::hal::CanState McanBus::doState() const {
  // Not initialised (no crystal, a handshake that timed out): the controller takes no part on the bus, and
  // its registers may not even be powered (reading them is not allowed then: SLAU846B "Peripheral power
  // enable control"), so answer from what init() left.
  if (!ready_) return fw::hal::CanState::BusOff;
  const uint32_t psr = mcan::core(config_.base).psr.read();
  if (psr & mcan::kPsrBusOff) return fw::hal::CanState::BusOff;
  if (psr & mcan::kPsrErrorPassive) return fw::hal::CanState::ErrorPassive;
  return fw::hal::CanState::ErrorActive;
}

Status McanBus::doRecover() {
  if (!ready_) return Status::NotReady;
  mcan::Core& core = mcan::core(config_.base);
  if (core.psr.read() & mcan::kPsrBusOff) mmio::clearBits(core.cccr, mcan::kCccrInit);
  return Status::Ok;
}

fw::hal::CanCounters McanBus::doCounters() const {
  return fw::hal::CanCounters{txFrames_, rxFrames_, txOverflows_, busOffEvents_, rxLost_};
}

}  // namespace bsp::mspm0
