// DmaChannel: one MSPM0 DMA channel moving bytes between memory and a peripheral FIFO register.
//
// Contract
// - start() programs source, destination, count and trigger and enables the channel; each trigger pulse
//   from the peripheral moves one byte (single-transfer mode). When the count reaches zero the channel
//   disables itself and the DMA signals "done" to the triggering peripheral, which raises its own
//   DMA_DONE_TX / DMA_DONE_RX interrupt (so the peripheral's ISR sees completion; no DMA IRQ is needed).
// - remaining() is the number of transfers not yet done (DMASZ counts down). stop() disables the channel;
//   afterwards the channel touches memory no more (the owner may reuse the buffer).
// - ISR-safe: each call is a handful of register writes, owned by one driver.
#pragma once

#include <cstdint>

#include "mmio.hpp"
#include "regs/dma.hpp"

namespace bsp::mspm0 {

class DmaChannel {
 public:
  enum class Direction : uint8_t { ToPeripheral, FromPeripheral };

  // `trigger` is the DMATSEL value of the peripheral event (tsv dmatrig rows). The register addresses are
  // worked out here, at compile time for the constinit board objects.
  constexpr DmaChannel(uintptr_t dmaBase, uint8_t channel, uint8_t trigger)
      : channel_(reg::dma::channelAddress(dmaBase, channel)),
        triggerSelect_(reg::dma::triggerSelectAddress(dmaBase, channel)),
        trigger_(trigger) {}
  constexpr DmaChannel() = default;

  void start(Direction direction, uint32_t source, uint32_t destination, uint32_t count) const {
    reg::dma::Channel& ch = mmio::block<reg::dma::Channel>(channel_);
    ch.ctl.write(0);
    ch.sa.write(source);
    ch.da.write(destination);
    ch.sz.write(count);
    mmio::block<mmio::Reg>(triggerSelect_).write(trigger_);
    ch.ctl.write(reg::dma::kCtlEnable | (direction == Direction::ToPeripheral ? reg::dma::kCtlSrcIncrement
                                                                              : reg::dma::kCtlDstIncrement));
  }
  uint32_t remaining() const { return mmio::block<reg::dma::Channel>(channel_).sz.read() & 0xFFFF; }
  void stop() const { mmio::block<reg::dma::Channel>(channel_).ctl.write(0); }

 private:
  uintptr_t channel_ = 0;        // DMA_BASE + 0x1200 + 0x10 * n (tsv note "DMA")
  uintptr_t triggerSelect_ = 0;  // DMA_BASE + 0x1110 + 4 * n
  uint8_t trigger_ = 0;
};

}  // namespace bsp::mspm0
