#include "periph/mcan.hpp"

#include <algorithm>
#include <cstdio>

#include "machine.hpp"
#include "sim/can.hpp"

namespace twin {

namespace {

constexpr uint32_t kGprcm = 0x6800, kCpuInt = 0x7820;
// M_CAN core (hw_mcan.h MCAN_* at 0x7000 + offset)
constexpr uint32_t kCrel = 0x7000, kEndn = 0x7004, kDbtp = 0x700C, kTest = 0x7010, kRwd = 0x7014;
constexpr uint32_t kCccr = 0x7018, kNbtp = 0x701C, kTscc = 0x7020, kTscv = 0x7024, kTocc = 0x7028;
constexpr uint32_t kTocv = 0x702C, kEcr = 0x7040, kPsr = 0x7044, kTdcr = 0x7048, kIr = 0x7050, kIe = 0x7054;
constexpr uint32_t kIls = 0x7058, kIle = 0x705C, kGfc = 0x7080, kSidfc = 0x7084, kXidfc = 0x7088;
constexpr uint32_t kXidam = 0x7090, kHpms = 0x7094, kNdat1 = 0x7098, kNdat2 = 0x709C, kRxf0c = 0x70A0;
constexpr uint32_t kRxf0s = 0x70A4, kRxf0a = 0x70A8, kRxbc = 0x70AC, kRxf1c = 0x70B0, kRxf1s = 0x70B4;
constexpr uint32_t kRxf1a = 0x70B8, kRxesc = 0x70BC, kTxbc = 0x70C0, kTxfqs = 0x70C4, kTxesc = 0x70C8;
constexpr uint32_t kTxbrp = 0x70CC, kTxbar = 0x70D0, kTxbcr = 0x70D4, kTxbto = 0x70D8, kTxbcf = 0x70DC;
constexpr uint32_t kTxbtie = 0x70E0, kTxbcie = 0x70E4, kTxefc = 0x70F0, kTxefs = 0x70F4, kTxefa = 0x70F8;
// MCANSS (TI wrapper)
constexpr uint32_t kSsPid = 0x7200, kSsCtrl = 0x7204, kSsStat = 0x7208, kSsEoi = 0x7220;
constexpr uint32_t kClken = 0x7900, kClkdiv = 0x7904;

constexpr uint32_t kInit = 1U << 0, kCce = 1U << 1, kDar = 1U << 6;
constexpr uint32_t kIrRf0n = 1U << 0, kIrRf0f = 1U << 2, kIrRf0l = 1U << 3;
constexpr uint32_t kIrTc = 1U << 9, kIrEp = 1U << 23, kIrBo = 1U << 25;
constexpr uint32_t kBusBitRate = 500000;  // the bus the LaunchPad's transceiver sits on (seed 001)
constexpr uint32_t kMemInitDone = 1U << 1;
constexpr uint32_t kElemXtd = 1U << 30, kElemFdf = 1U << 21;
constexpr uint32_t kElementBytes = 16;  // TXESC = 0: 8-byte data field

}  // namespace

Mcan::Mcan(Machine& machine, Pins& pins, Sysctl& sysctl)
    : Peripheral(machine, "CANFD0", kGprcm, kCpuInt),
      pins_(pins),
      sysctl_(sysctl),
      txDone_(machine.timeline(), [this] { transmitDone(); }),
      integrated_(machine.timeline(),
                  [this] {
                    integrating_ = false;
                    tryTransmit();
                  }),
      recovered_(machine.timeline(),
                 [this] {
                   // ISO 11898-1: after 128 occurrences of 11 recessive bits the node is error active again.
                   busOff_ = false;
                   if (!busOffLog_.empty()) busOffLog_.back().recoveredCycle = machine_.now();
                   errorPassive_ = false;
                   tec_ = 0;
                   setIr(kIrBo);
                   integrating_ = false;
                   tryTransmit();
                 }),
      peerDone_(machine.timeline(), [this] { peerDone(); }),
      busOffStuck_(machine.timeline(),
                   [this] {
                     if (!busOff_) return;
                     machine_.violate(
                         Rule::McanBusOffStuck,
                         std::string(name()) +
                             ": bus-off (PSR.BO) for 1 s with CCCR.INIT still 1 and no write "
                             "clearing it: the M_CAN starts its bus-off recovery only once the CPU "
                             "clears INIT, so the node never rejoins the bus");
                   }),
      ram_(kRamBytes / 4, 0) {}

void Mcan::resetRegisters() {
  cccr_ = kInit;
  initValue_ = true;
  initSyncAt_ = 0;
  nbtp_ = 0x06000A03;  // M_CAN reset value
  dbtp_ = test_ = ir_ = ie_ = ils_ = ile_ = gfc_ = sidfc_ = xidfc_ = rxf0c_ = rxf1c_ = rxbc_ = rxesc_ = 0;
  xidam_ = 0x1FFFFFFF;
  txbc_ = txesc_ = txefc_ = txbrp_ = txbto_ = txbtie_ = txbcie_ = tscc_ = tocc_ = tdcr_ = 0;
  tec_ = 0;
  busOff_ = errorPassive_ = integrating_ = transmitting_ = false;
  get_ = queued_ = 0;
  rxGet_ = rxFill_ = 0;
  rxLost_ = false;
  clken_ = clkdiv_ = 0;
  clockRequestedAt_ = UINT64_MAX;
  lineHeld_ = {};
  std::fill(ram_.begin(), ram_.end(), 0);
  txDone_.cancel();
  integrated_.cancel();
  recovered_.cancel();
  busOffStuck_.cancel();
}

void Mcan::note(const std::string& text) {
  if (notes_.size() < 32) notes_.push_back(text);
}

bool Mcan::initReadBack() const {
  if (initHeld_) return true;
  return machine_.now() >= initSyncAt_ ? initValue_ : !initValue_;
}

bool Mcan::memReady() const {
  return (clken_ & 1U) && sysctl_.canClockRunning() && machine_.now() >= clockRequestedAt_ + kMemInitCycles;
}

uint64_t Mcan::bitCycles() const {
  const uint64_t brp = ((nbtp_ >> 16) & 0x1FF) + 1;
  const uint64_t tq = 1 + (((nbtp_ >> 8) & 0xFF) + 1) + ((nbtp_ & 0x7F) + 1);
  const uint32_t ratio = clkdiv_ & 3U;
  const uint64_t div = ratio == 1 ? 2 : ratio == 2 ? 4 : 1;  // MCAN_CLKDIV_RATIO: /1, /2, /4, /1
  return tq * brp * div * machine_.clockHz() / kCanClockHz;
}

void Mcan::checkWire() {
  if (pins_.routed(rxPincm_, rxPf_) && !pins_.requireInput(rxPincm_, "CANFD0 CAN RX")) return;
  if (busBitRate_ == 0) return;
  const uint64_t brp = ((nbtp_ >> 16) & 0x1FF) + 1, tseg1 = ((nbtp_ >> 8) & 0xFF) + 1;
  const uint64_t tseg2 = (nbtp_ & 0x7F) + 1, sjw = ((nbtp_ >> 25) & 0x7F) + 1;
  const uint64_t nbt = 1 + tseg1 + tseg2;
  const uint32_t ratio = clkdiv_ & 3U;
  const uint64_t div = ratio == 1 ? 2 : ratio == 2 ? 4 : 1;
  const uint64_t rate = kCanClockHz / (div * brp * nbt);
  // The oscillator tolerance the bit timing allows, in ppm.
  const uint64_t dfPs = 1000000 * tseg2 / (2 * (13 * nbt - tseg2));
  const uint64_t dfSjw = 1000000 * sjw / (20 * nbt);
  const uint64_t df = std::min(dfPs, dfSjw);
  const int64_t errorPpm = (static_cast<int64_t>(uint64_t{kCanClockHz} * 1000000 / (div * brp * nbt)) -
                            static_cast<int64_t>(busBitRate_) * 1000000) /
                           static_cast<int64_t>(busBitRate_);
  char buf[240];
  if (static_cast<uint64_t>(errorPpm < 0 ? -errorPpm : errorPpm) > df) {
    std::snprintf(
        buf, sizeof buf,
        "CANFD0: nominal bit rate %llu bit/s (NBTP 0x%08X: BRP %llu, %llu tq, CANCLK %u Hz /%llu) on a "
        "%u bit/s bus: %+.2f %%, beyond the +-%.2f %% its bit timing tolerates",
        static_cast<unsigned long long>(rate), nbtp_, static_cast<unsigned long long>(brp),
        static_cast<unsigned long long>(nbt), kCanClockHz, static_cast<unsigned long long>(div), busBitRate_,
        static_cast<double>(errorPpm) / 1e4, static_cast<double>(df) / 1e4);
    machine_.violate(Rule::CanBitRate, buf);
    return;
  }
  const uint64_t samplePermille = 1000 * (1 + tseg1) / nbt;
  if (samplePermille + 50 < 875 || samplePermille > 875 + 50) {
    std::snprintf(buf, sizeof buf,
                  "CANFD0: sample point %.1f %% (NBTP 0x%08X), more than 5 points from 87.5 %%",
                  static_cast<double>(samplePermille) / 10.0, nbtp_);
    machine_.violate(Rule::CanSamplePoint, buf);
  }
}

void Mcan::setIr(uint32_t bits) {
  ir_ |= bits;
  updateLines();
}

void Mcan::updateLines() {
  for (int n = 0; n < 2; ++n) {
    const uint32_t selected = n == 0 ? ~ils_ : ils_;
    const bool pending = (ile_ & (1U << n)) && (ir_ & ie_ & selected) != 0;
    if (pending && !lineHeld_[static_cast<size_t>(n)]) {
      lineHeld_[static_cast<size_t>(n)] = true;  // held until EOI
      heldSince_[static_cast<size_t>(n)] = machine_.now();
      raise(1U << n);  // wrapper RIS.INTLn
    }
  }
}

uint64_t Mcan::awaitingEoiCycles(int line) const {
  const auto n = static_cast<size_t>(line);
  return lineHeld_[n] ? machine_.now() - heldSince_[n] : 0;
}

// At bus idle: the waiting frame with the lowest identifier takes the wire, the TX FIFO's head or a peer's.
void Mcan::tryTransmit() {
  if (!busIdle()) return;
  if (peerQueue_.empty() && peerSource_) {
    if (auto f = peerSource_()) peerQueue_.push_back(*f);
  }
  const bool ours = queued_ != 0 && powered() && memReady() && !initReadBack() && !busOff_ && !integrating_;
  if (ours) {
    if ((txesc_ & 7U) != 0) {
      stop("TXESC selects data fields longer than 8 bytes (CAN FD), not modelled");
      return;
    }
    const uint32_t ndtb = (txbc_ >> 16) & 0x3F, tfqs = (txbc_ >> 24) & 0x3F;
    const uint32_t element = ndtb + get_ % tfqs;
    const uint32_t at = ((txbc_ & 0xFFFC) + element * kElementBytes) / 4;
    if (at + 4 > ram_.size()) {
      stop("TX FIFO element outside the message RAM");
      return;
    }
    const uint32_t t0 = ram_[at], t1 = ram_[at + 1];
    if (t1 & kElemFdf) {
      stop("a TX element with FDF set (CAN FD), not modelled");
      return;
    }
    current_ = {};
    current_.extended = (t0 & kElemXtd) != 0;
    current_.id = current_.extended ? (t0 & 0x1FFFFFFF) : ((t0 >> 18) & 0x7FF);
    current_.dlc = static_cast<uint8_t>(std::min<uint32_t>((t1 >> 16) & 0xF, 8));
    for (int i = 0; i < 8; ++i)
      current_.data[static_cast<size_t>(i)] =
          static_cast<uint8_t>(ram_[at + 2 + static_cast<uint32_t>(i) / 4] >> (8 * (i % 4)));
  }
  // Arbitration on the base identifier (standard frames: the identifier; extended: its 11 high bits), a
  // standard frame winning against an extended one with the same base (its RTR/IDE bit is dominant).
  auto priority = [](const fw::hal::CanFrame& f) { return f.extended ? (f.id >> 18) * 2 + 1 : f.id * 2; };
  if (!peerQueue_.empty() && (!ours || priority(peerQueue_.front()) < priority(current_))) {
    peerOnWire_ = true;
    peerFrame_ = peerQueue_.front();
    peerQueue_.pop_front();
    peerDone_.after(bsp::host::canFrameBits(peerFrame_) * machine_.clockHz() / kBusBitRate);
    return;
  }
  if (!ours) return;
  transmitting_ = true;
  txDone_.after(bsp::host::canFrameBits(current_) * bitCycles());
}

void Mcan::peerSend(const fw::hal::CanFrame& frame) {
  peerQueue_.push_back(frame);
  tryTransmit();
}

void Mcan::setPeerSource(std::function<std::optional<fw::hal::CanFrame>()> source) {
  peerSource_ = std::move(source);
  tryTransmit();
}

// A peer frame has left the wire: the controller receives it if it takes part in the bus.
void Mcan::peerDone() {
  peerOnWire_ = false;
  ++peerFrames_;
  if (powered() && memReady() && !initReadBack() && !busOff_ && pins_.routed(rxPincm_, rxPf_))
    receive(peerFrame_);
  tryTransmit();
}

// Acceptance filtering, then RX FIFO 0 (see mcan.hpp).
void Mcan::receive(const fw::hal::CanFrame& f) {
  enum class To { Fifo0, Reject };
  std::optional<To> to;
  bool listStores = false;  // an enabled standard element stores its matches in RX FIFO 0
  if (!f.extended) {
    const uint32_t lss = (sidfc_ >> 16) & 0xFF, first = (sidfc_ & 0xFFFC) / 4;
    for (uint32_t k = 0; k < lss && !to; ++k) {
      if (first + k >= ram_.size()) {
        stop("standard filter element outside the message RAM");
        return;
      }
      const uint32_t e = ram_[first + k];
      const uint32_t sft = e >> 30, sfec = (e >> 27) & 7U, id1 = (e >> 16) & 0x7FF, id2 = e & 0x7FF;
      if (sfec == 0 || sft == 3) continue;  // disabled element
      listStores = listStores || sfec == 1;
      const bool match = sft == 0   ? (id1 <= f.id && f.id <= id2)
                         : sft == 1 ? (f.id == id1 || f.id == id2)
                                    : ((f.id & id2) == (id1 & id2));
      if (!match) continue;
      if (sfec != 1 && sfec != 3) {
        stop("a standard filter element storing to RX FIFO 1, a priority or an RX buffer: not modelled");
        return;
      }
      to = sfec == 1 ? To::Fifo0 : To::Reject;
    }
  } else if (((xidfc_ >> 16) & 0x7F) != 0) {
    stop("an extended ID filter list (XIDFC.LSE > 0): not modelled");
    return;
  }
  if (!to) {
    const uint32_t anf = f.extended ? (gfc_ >> 2) & 3U : (gfc_ >> 4) & 3U;
    if (anf == 1) {
      stop("GFC puts non-matching frames in RX FIFO 1: not modelled");
      return;
    }
    to = anf == 0 ? To::Fifo0 : To::Reject;
    // MCAN-FILTER-OPEN (rules.hpp): the list picks the frames to store and ANFS 0 stores every other one too.
    if (anf == 0 && listStores) {
      char buf[220];
      std::snprintf(
          buf, sizeof buf,
          "standard frame 0x%03X, which no element of the %u-element filter list matched, stored in RX "
          "FIFO 0 (GFC 0x%08X, ANFS 0): every frame on the bus gets past the list",
          f.id, (sidfc_ >> 16) & 0xFF, gfc_);
      machine_.violate(Rule::McanFilterOpen, buf);
    }
  }
  if (*to == To::Reject) {
    ++rejected_;
    return;
  }
  const uint32_t size = (rxf0c_ >> 16) & 0x7F;
  if ((rxesc_ & 7U) != 0 || (rxf0c_ >> 31) != 0) {
    stop("RX FIFO 0 with data fields above 8 bytes or in overwrite mode: not modelled");
    return;
  }
  if (size == 0) return;  // no FIFO configured: nowhere to store it
  if (rxFill_ >= size) {  // blocking mode: the new frame is lost
    rxLost_ = true;
    setIr(kIrRf0l);
    return;
  }
  const uint32_t at = ((rxf0c_ & 0xFFFC) + ((rxGet_ + rxFill_) % size) * kElementBytes) / 4;
  if (at + 4 > ram_.size()) {
    stop("RX FIFO 0 element outside the message RAM");
    return;
  }
  ram_[at] = f.extended ? (kElemXtd | f.id) : (f.id << 18);
  ram_[at + 1] = static_cast<uint32_t>(f.dlc) << 16;
  for (uint32_t w = 0; w < 2; ++w) {
    uint32_t v = 0;
    for (uint32_t b = 0; b < 4; ++b)
      v |= static_cast<uint32_t>(f.data[4 * w + b]) << (8 * b);
    ram_[at + 2 + w] = v;
  }
  ++rxFill_;
  ++received_;
  ++rf0nEvents_;
  setIr(kIrRf0n | (rxFill_ == size ? kIrRf0f : 0));
}

void Mcan::transmitDone() {
  transmitting_ = false;
  const uint32_t ndtb = (txbc_ >> 16) & 0x3F, tfqs = (txbc_ >> 24) & 0x3F;
  const uint32_t bit = 1U << (ndtb + get_ % tfqs);
  const bool destroyed = errorFramesLeft_ != 0;  // another node's error frame (injectErrorFrames)
  if (destroyed) --errorFramesLeft_, ++errorFrames_;
  if (destroyed || !pins_.routed(txPincm_, txPf_) || !pins_.routed(rxPincm_, rxPf_)) {
    // Nothing reaches the bus (or the controller cannot see its own bits): a transmit error, and the
    // M_CAN retries unless CCCR.DAR (ISO 11898-1 12.1.4: TEC + 8).
    tec_ += 8;
    if (tec_ >= 128 && !errorPassive_) {
      errorPassive_ = true;
      setIr(kIrEp);
    }
    if (tec_ > 255) {
      enterBusOff();
      return;
    }
    if ((cccr_ & kDar) == 0) tryTransmit();
    return;
  }
  if (tec_ > 0) --tec_;
  if (errorPassive_ && tec_ < 128) {
    errorPassive_ = false;  // error active again (ISO 11898-1 12.1.4.2; the RX side has no errors here)
    setIr(kIrEp);
  }
  txbrp_ &= ~bit;
  txbto_ |= bit;
  get_ = (get_ + 1) % tfqs;
  --queued_;
  if (txbtie_ & bit) setIr(kIrTc);
  if (sink_) sink_({machine_.now(), current_});
  tryTransmit();
}

void Mcan::enterBusOff() {
  busOff_ = true;
  busOffLog_.push_back({machine_.now(), 0});
  tec_ = 256;
  transmitting_ = false;
  txDone_.cancel();
  integrated_.cancel();
  // The M_CAN sets INIT itself on entering bus-off (M_CAN user manual 3.1.1 / ISO 11898-1).
  cccr_ |= kInit;
  initValue_ = true;
  initSyncAt_ = machine_.now();
  busOffStuck_.after(kBusOffStuckMs * machine_.clockHz() / 1000);
  setIr(kIrBo);
}

void Mcan::injectBusOff() {
  if (powered() && !busOff_) enterBusOff();
}

bool Mcan::readRegister(uint32_t offset, uint32_t& value) {
  if (offset < kRamBytes) {
    if ((clken_ & 1U) == 0) stop("message RAM access without the module clock (MCANSS_CLKEN.CLK_REQEN)");
    value = ram_[offset / 4];
    return true;
  }
  if (offset >= kCrel && offset < 0x7100 && (clken_ & 1U) == 0) {
    stop("M_CAN core register read without the module clock (MCANSS_CLKEN.CLK_REQEN)");
    value = 0;
    return true;
  }
  switch (offset) {
    case kCrel:
      value = 0x32380608;
      return true;
    case kEndn:
      value = 0x87654321;
      return true;
    case kDbtp:
      value = dbtp_;
      return true;
    case kTest:
      value = test_;
      return true;
    case kRwd:
      value = 0;
      return true;
    case kCccr:
      value = (cccr_ & ~kInit) | (initReadBack() ? kInit : 0);
      return true;
    case kNbtp:
      value = nbtp_;
      return true;
    case kTscc:
      value = tscc_;
      return true;
    case kTscv:
    case kTocv:
    case kHpms:
    case kNdat1:
    case kNdat2:
    case kRxf0s: {
      const uint32_t size = (rxf0c_ >> 16) & 0x7F;
      value = rxFill_ | (rxGet_ << 8) | ((size ? (rxGet_ + rxFill_) % size : 0) << 16) |
              (size != 0 && rxFill_ >= size ? 1U << 24 : 0) | ((ir_ & kIrRf0l) ? 1U << 25 : 0);
      return true;
    }
    case kRxf1s:
    case kTxefs:
    case kTxbcf:
      value = 0;
      return true;
    case kTocc:
      value = tocc_;
      return true;
    case kEcr:
      value = std::min<uint32_t>(tec_, 255);
      return true;
    case kPsr:
      value = 7U | (busOff_ ? 1U << 7 : 0) | (tec_ >= 96 ? 1U << 6 : 0) | (errorPassive_ ? 1U << 5 : 0) |
              ((transmitting_ ? 3U : 1U) << 3);
      return true;
    case kTdcr:
      value = tdcr_;
      return true;
    case kIr:
      value = ir_;
      return true;
    case kIe:
      value = ie_;
      return true;
    case kIls:
      value = ils_;
      return true;
    case kIle:
      value = ile_;
      return true;
    case kGfc:
      value = gfc_;
      return true;
    case kSidfc:
      value = sidfc_;
      return true;
    case kXidfc:
      value = xidfc_;
      return true;
    case kXidam:
      value = xidam_;
      return true;
    case kRxf0c:
      value = rxf0c_;
      return true;
    case kRxf0a:
    case kRxf1a:
    case kTxbar:
    case kTxbcr:
    case kTxefa:
      value = 0;
      return true;
    case kRxbc:
      value = rxbc_;
      return true;
    case kRxf1c:
      value = rxf1c_;
      return true;
    case kRxesc:
      value = rxesc_;
      return true;
    case kTxbc:
      value = txbc_;
      return true;
    case kTxfqs: {
      const uint32_t ndtb = (txbc_ >> 16) & 0x3F, tfqs = (txbc_ >> 24) & 0x3F;
      if (tfqs == 0) {
        value = 0;
        return true;
      }
      value = (tfqs - queued_) | ((ndtb + get_ % tfqs) << 8) | ((ndtb + (get_ + queued_) % tfqs) << 16) |
              (queued_ >= tfqs ? 1U << 21 : 0);
      return true;
    }
    case kTxesc:
      value = txesc_;
      return true;
    case kTxbrp:
      value = txbrp_;
      return true;
    case kTxbto:
      value = txbto_;
      return true;
    case kTxbtie:
      value = txbtie_;
      return true;
    case kTxbcie:
      value = txbcie_;
      return true;
    case kTxefc:
      value = txefc_;
      return true;
    case kSsPid:
      value = 0x66E31000;
      return true;
    case kSsCtrl:
      value = 0;
      return true;
    case kSsStat:
      value = memReady() ? kMemInitDone : 0;
      return true;
    case kSsEoi:
      value = 0;
      return true;
    case kClken:
      value = clken_;
      return true;
    case kClkdiv:
      value = clkdiv_;
      return true;
    default:
      return false;
  }
}

bool Mcan::writeRegister(uint32_t offset, uint32_t value) {
  if (offset < kRamBytes) {
    if ((clken_ & 1U) == 0) stop("message RAM access without the module clock (MCANSS_CLKEN.CLK_REQEN)");
    ram_[offset / 4] = value;
    return true;
  }
  if (offset >= kCrel && offset < 0x7100 && (clken_ & 1U) == 0) {
    stop("M_CAN core register write without the module clock (MCANSS_CLKEN.CLK_REQEN)");
    return true;
  }
  // Registers a write reaches only during configuration (CCCR.CCE = 1 and INIT = 1).
  auto protectedWrite = [&](uint32_t& reg, const char* name) {
    if (configurable()) {
      reg = value;
    } else {
      char buf[112];
      std::snprintf(buf, sizeof buf, "%s write 0x%08X ignored: CCCR.CCE and INIT are not both set", name,
                    value);
      note(buf);
    }
    return true;
  };
  switch (offset) {
    case kCccr: {
      const bool init = (value & kInit) != 0;
      if (init != initValue_) {
        if (machine_.now() < initSyncAt_) {
          stop("CCCR.INIT changed again before its previous value read back (hw_mcan.h CCCR.INIT)");
          return true;
        }
        initValue_ = init;
        initSyncAt_ = machine_.now() + kInitSyncCycles;
        if (!init) {
          checkWire();
          if ((ie_ & kIrTc) != 0 && txbtie_ == 0) {
            machine_.violate(Rule::McanTcUnarmed,
                             std::string(name()) +
                                 ": joins the bus with IE.TCE set and TXBTIE 0: no TX buffer "
                                 "raises IR.TC, the enabled transmission-complete interrupt "
                                 "never comes");
          }
          busOffStuck_.cancel();  // the CPU cleared INIT: a bus-off recovers
          integrating_ = true;
          // Leaving INIT: bus-off recovery (129 x 11 recessive bits) or bus integration (11 bits).
          if (busOff_) {
            recovered_.at(initSyncAt_ + 129 * 11 * bitCycles());
          } else {
            integrated_.at(initSyncAt_ + 11 * bitCycles());
          }
        } else {
          integrated_.cancel();
          recovered_.cancel();
        }
      }
      // CCE and the other configuration bits change only while INIT reads 1 (MCAN-INIT-SYNC: CCE written
      // before INIT read back is refused, and named).
      if (!initReadBack() && (value & kCce) && init) {
        machine_.violate(Rule::McanInitSync,
                         std::string(name()) +
                             ": CCCR.CCE written before CCCR.INIT read back 1: the "
                             "configuration change is refused and the set-up that follows "
                             "is ignored");
        return true;
      }
      cccr_ = initReadBack() || init ? value : ((cccr_ & ~kInit) | (value & kInit));
      if (!initReadBack() && (value & kCce)) cccr_ &= ~kCce;
      return true;
    }
    case kNbtp:
      return protectedWrite(nbtp_, "NBTP");
    case kDbtp:
      return protectedWrite(dbtp_, "DBTP");
    case kTest:
      return protectedWrite(test_, "TEST");
    case kTscc:
      return protectedWrite(tscc_, "TSCC");
    case kTocc:
      return protectedWrite(tocc_, "TOCC");
    case kTdcr:
      return protectedWrite(tdcr_, "TDCR");
    case kGfc:
      return protectedWrite(gfc_, "GFC");
    case kSidfc:
      return protectedWrite(sidfc_, "SIDFC");
    case kXidfc:
      return protectedWrite(xidfc_, "XIDFC");
    case kXidam:
      return protectedWrite(xidam_, "XIDAM");
    case kRxf0c:
      return protectedWrite(rxf0c_, "RXF0C");
    case kRxf1c:
      return protectedWrite(rxf1c_, "RXF1C");
    case kRxbc:
      return protectedWrite(rxbc_, "RXBC");
    case kRxesc:
      return protectedWrite(rxesc_, "RXESC");
    case kTxbc:
      return protectedWrite(txbc_, "TXBC");
    case kTxesc:
      return protectedWrite(txesc_, "TXESC");
    case kTxefc:
      return protectedWrite(txefc_, "TXEFC");
    case kIr:
      ir_ &= ~value;  // write 1 to clear
      updateLines();
      return true;
    case kIe:
      ie_ = value;
      updateLines();
      return true;
    case kIls:
      ils_ = value;
      updateLines();
      return true;
    case kIle:
      ile_ = value;
      updateLines();
      return true;
    case kTxbtie:
      txbtie_ = value;
      return true;
    case kTxbcie:
      txbcie_ = value;
      return true;
    case kTxbar: {
      const uint32_t ndtb = (txbc_ >> 16) & 0x3F, tfqs = (txbc_ >> 24) & 0x3F;
      for (uint32_t b = 0; b < 32; ++b) {
        if (((value >> b) & 1U) == 0) continue;
        if (tfqs == 0 || queued_ >= tfqs || b != ndtb + (get_ + queued_) % tfqs) {
          stop("TXBAR requests element " + std::to_string(b) +
               ", which is not the TX FIFO's put index (dedicated buffers are not modelled)");
          return true;
        }
        ++queued_;
        txbrp_ |= 1U << b;
        txbto_ &= ~(1U << b);
      }
      tryTransmit();
      return true;
    }
    case kTxbcr:
      if (value != 0) stop("TXBCR (transmission cancellation) is not modelled");
      return true;
    case kRxf0a: {
      // The index of the last element read: the get index moves past it (hw_mcan.h MCAN_RXF0A F0AI).
      const uint32_t size = (rxf0c_ >> 16) & 0x7F, n = value & 0x3F;
      if (size == 0 || rxFill_ == 0 || n >= size) return true;
      const uint32_t count = (n + size - rxGet_) % size + 1;
      if (count > rxFill_) {
        stop("RXF0A acknowledges an element of RX FIFO 0 that holds no frame");
        return true;
      }
      rxGet_ = (n + 1) % size;
      rxFill_ -= count;
      return true;
    }
    case kRxf1a:
    case kTxefa:
    case kRwd:
    case kEcr:
    case kPsr:
    case kTxfqs:
    case kTxbrp:
    case kTxbto:
    case kTxbcf:
    case kSsStat:
    case kSsPid:
      return true;  // read-only or nothing to acknowledge (no reception is modelled)
    case kSsCtrl:
      return true;
    case kSsEoi:
      // 0x01 acknowledges line 0, 0x02 line 1; other writes are ignored (hw_mcan.h MCAN_EOI).
      if (value == 1 || value == 2) {
        lineHeld_[value - 1] = false;
        updateLines();
      }
      return true;
    case kClken:
      if ((value & 1U) && !(clken_ & 1U)) {
        clockRequestedAt_ = machine_.now();
        const std::string off = sysctl_.canClockProblem();
        if (!off.empty()) {
          machine_.violate(Rule::ClockOff, std::string(name()) +
                                               ": MCANSS_CLKEN.CLK_REQEN with no clock: " + off +
                                               ", so the message RAM never initialises (MEM_INIT_DONE)");
          return true;
        }
      }
      clken_ = value;
      return true;
    case kClkdiv:
      // CLK_REQEN "requests the functional and register clocks" of the module (hw_mcan.h MCAN_CLKEN), and
      // TI's MCAN set-up enables the module clock before it sets the divider; TI gives no behaviour for a
      // divider written without the clock, so the twin takes the safe side and refuses it.
      if ((clken_ & 1U) == 0) stop("MCANSS_CLKDIV written before MCANSS_CLKEN.CLK_REQEN requested the clock");
      clkdiv_ = value;
      return true;
    default:
      return false;
  }
}

}  // namespace twin
