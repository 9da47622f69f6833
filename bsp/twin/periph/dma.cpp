#include "periph/dma.hpp"

#include <cstdio>

namespace twin {

namespace {
constexpr uint32_t kCpuInt = 0x1020, kPrio = 0x1100, kTrig = 0x1110, kChan = 0x1200;
constexpr uint32_t kReq = 1U << 0, kEnable = 1U << 1;
constexpr uint32_t kTmMask = 0x30000000, kTmSingle = 0, kTmBlock = 0x10000000;
constexpr uint32_t kEmMask = 0x03000000;
constexpr uint32_t kTriggerInternal = 1U << 7;
}  // namespace

Dma::Dma(Machine& machine, int channels)
    : machine_(machine), channels_(channels), serviceEvent_(machine.timeline(), [this] { service(); }) {
  machine.onReset([this](ResetKind) { reset(); });
}

void Dma::reset() {
  ch_ = {};
  cpuInt_ = {};
  prio_ = 0;
  serviceEvent_.cancel();
  updateInterrupt();
}

void Dma::updateInterrupt() {
  const bool level = cpuInt_.mis() != 0;
  if (level == lineLevel_) return;
  lineLevel_ = level;
  if (line_) line_(level);
}

void Dma::checkTrigger(int n, const Channel& ch) {
  const int selected = static_cast<int>(ch.tctl & 0x3F);
  for (const TriggerInfo& t : triggers_) {
    const uint32_t end = t.toPeripheral ? ch.da : ch.sa;
    if (end != t.dataRegister) continue;
    char buf[220];
    if (selected != t.trigger) {
      std::string selectedName =
          selected == 0 ? "trigger 0 (software: DMAREQ only)" : "trigger " + std::to_string(selected);
      for (const TriggerInfo& other : triggers_) {
        if (other.trigger == selected) selectedName += " (" + other.name + ")";
      }
      std::snprintf(buf, sizeof buf,
                    "DMA channel %d enabled to move %s %s (0x%08X) on %s, not %s's trigger %d: the "
                    "peripheral never paces it",
                    n, t.toPeripheral ? "to" : "from", t.name.c_str(), t.dataRegister, selectedName.c_str(),
                    t.name.c_str(), t.trigger);
      machine_.violate(Rule::DmaTrigger, buf);
      return;
    }
    const uint32_t dstInc = (ch.ctl >> 20) & 0xFU;
    if (!t.toPeripheral && ch.sz > 1 && dstInc == 0 && machine_.inSram(ch.da)) {
      std::snprintf(buf, sizeof buf,
                    "DMA channel %d moves %u items from %s (0x%08X) to SRAM 0x%08X without incrementing the "
                    "destination (DMADSTINCR 0): each overwrites the last",
                    n, ch.sz, t.name.c_str(), t.dataRegister, ch.da);
      machine_.violate(Rule::DmaNoIncrement, buf);
    }
    DmaRequester* requester = requesters_[static_cast<size_t>(t.trigger)];
    Rule rule = Rule::UartDmaLevel;
    const std::string problem = requester != nullptr ? requester->dmaTriggerProblem(t.trigger, rule) : "";
    if (!problem.empty()) {
      std::snprintf(buf, sizeof buf, "DMA channel %d on %s's trigger %d: %s", n, t.name.c_str(), t.trigger,
                    problem.c_str());
      machine_.violate(rule, buf);
    }
    return;
  }
}

void Dma::requestRaised(int) {
  if (!serviceEvent_.armed()) serviceEvent_.after(kTransferCycles);
}

bool Dma::transfer(Channel& ch) {
  const uint32_t srcWidth = (ch.ctl >> 8) & 7U, dstWidth = (ch.ctl >> 12) & 7U;
  const uint32_t srcInc = (ch.ctl >> 16) & 0xFU, dstInc = (ch.ctl >> 20) & 0xFU;
  if (srcWidth > 2 || dstWidth > 2 || (srcInc != 0 && srcInc != 2 && srcInc != 3) ||
      (dstInc != 0 && dstInc != 2 && dstInc != 3) || (ch.ctl & kEmMask) != 0) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "DMA: DMACTL 0x%08X uses widths, strides or modes the twin does not model",
                  ch.ctl);
    machine_.stop(buf);
    return false;
  }
  uint32_t value = 0;
  const unsigned srcBytes = 1U << srcWidth, dstBytes = 1U << dstWidth;
  if (!machine_.busRead(ch.sa, srcBytes, value) || !machine_.busWrite(ch.da, dstBytes, value)) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "DMA: transfer from 0x%08X to 0x%08X reaches an address no model covers",
                  ch.sa, ch.da);
    machine_.stop(buf);
    return false;
  }
  if (srcInc == 3) ch.sa += srcBytes;
  if (srcInc == 2) ch.sa -= srcBytes;
  if (dstInc == 3) ch.da += dstBytes;
  if (dstInc == 2) ch.da -= dstBytes;
  ch.sz = (ch.sz - 1) & 0xFFFF;
  return true;
}

void Dma::service() {
  // The lowest-numbered channel with a pending request goes first (fixed priority, DMAPRIO 0).
  for (int n = 0; n < channels_; ++n) {
    Channel& ch = ch_[static_cast<size_t>(n)];
    if ((ch.ctl & kEnable) == 0 || ch.sz == 0) continue;
    const int trigger = static_cast<int>(ch.tctl & 0x3F);
    const bool software = (ch.ctl & kReq) != 0;
    DmaRequester* requester = requesters_[static_cast<size_t>(trigger)];
    if (!software && (requester == nullptr || !requester->dmaRequested(trigger))) continue;
    if ((ch.ctl & kTmMask) != kTmSingle && (ch.ctl & kTmMask) != kTmBlock) {
      machine_.stop("DMA: repeat transfer modes are not modelled");
      return;
    }
    ch.ctl &= ~kReq;
    // The request is acknowledged as the transfer starts: the peripheral raises it again if its condition
    // still holds after the transfer (a TX FIFO with room left, an RX FIFO with data left).
    if (!software) requester->dmaAcknowledge(trigger);
    do {
      if (!transfer(ch)) return;
    } while ((ch.ctl & kTmMask) == kTmBlock && ch.sz != 0);
    if (ch.sz == 0) {
      ch.ctl &= ~kEnable;
      cpuInt_.ris |= 1U << n;
      updateInterrupt();
      if (!software) requester->dmaDone(trigger);
    }
    break;  // one transfer per service slot
  }
  // Anything still requested gets the next slot.
  for (int n = 0; n < channels_; ++n) {
    const Channel& ch = ch_[static_cast<size_t>(n)];
    const auto trigger = static_cast<size_t>(ch.tctl & 0x3F);
    if ((ch.ctl & kEnable) && ch.sz != 0 &&
        ((ch.ctl & kReq) || (requesters_[trigger] != nullptr &&
                             requesters_[trigger]->dmaRequested(static_cast<int>(trigger))))) {
      serviceEvent_.after(kTransferCycles);
      return;
    }
  }
}

bool Dma::read(uint32_t offset, unsigned bytes, uint32_t& value) {
  if (bytes != 4) return false;
  if (offset - kCpuInt < 0x30) {
    const bool ok = cpuInt_.read(offset - kCpuInt, value);
    updateInterrupt();
    return ok;
  }
  if (offset == kPrio) {
    value = prio_;
    return true;
  }
  if (offset >= kTrig && offset < kTrig + 4U * static_cast<uint32_t>(channels_)) {
    value = ch_[(offset - kTrig) / 4].tctl;
    return true;
  }
  if (offset >= kChan && offset < kChan + 0x10U * static_cast<uint32_t>(channels_)) {
    const Channel& ch = ch_[(offset - kChan) / 0x10];
    const uint32_t regs[4] = {ch.ctl, ch.sa, ch.da, ch.sz};
    value = regs[(offset & 0xF) / 4];
    return true;
  }
  return false;
}

bool Dma::write(uint32_t offset, unsigned bytes, uint32_t value) {
  if (bytes != 4) return false;
  if (offset - kCpuInt < 0x30) {
    const bool ok = cpuInt_.write(offset - kCpuInt, value);
    updateInterrupt();
    return ok;
  }
  if (offset == kPrio) {
    prio_ = value;
    return true;
  }
  if (offset >= kTrig && offset < kTrig + 4U * static_cast<uint32_t>(channels_)) {
    if (value & kTriggerInternal)
      machine_.stop("DMA: internal (channel-to-channel) triggers are not modelled");
    ch_[(offset - kTrig) / 4].tctl = value;
    return true;
  }
  if (offset >= kChan && offset < kChan + 0x10U * static_cast<uint32_t>(channels_)) {
    Channel& ch = ch_[(offset - kChan) / 0x10];
    switch ((offset & 0xF) / 4) {
      case 0:
        ch.ctl = value;
        if ((value & kEnable) && ch.sz != 0) {
          checkTrigger(static_cast<int>((offset - kChan) / 0x10), ch);
          serviceEvent_.after(kTransferCycles);
        }
        break;
      case 1:
        ch.sa = value;
        break;
      case 2:
        ch.da = value;
        break;
      default:
        ch.sz = value & 0xFFFF;
        break;
    }
    return true;
  }
  return false;
}

}  // namespace twin
