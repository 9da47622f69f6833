// The ImageSim overrides every binding whose image sends on a simulated CAN controller (bsp::host::SimCan)
// shares: bus-off injection, frames from a peer, a peer flood, and reading back the frames sent and the
// bus-off spans. A binding derives from CanImageSim instead of ImageSim and names its controller in can().
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "image_sim.hpp"
#include "pack_figures.hpp"
#include "sim/can.hpp"

namespace bmssim {

class CanImageSim : public ImageSim {
 public:
  bool busOff() override {
    can().injectBusOff();
    return true;
  }
  bool canSend(const fw::hal::CanFrame& f) override {
    can().peerSend(f);
    return true;
  }
  bool canFlood(std::function<std::optional<fw::hal::CanFrame>()> source) override {
    can().setPeerSource(std::move(source));
    return true;
  }
  std::vector<BusOffSpan> busOffLog() const override { return busOffSpans(can()); }
  std::vector<SentFrame> frames() const override { return canFrames(can()); }

 protected:
  // The image's CAN controller (the board's, alive as long as the binding).
  virtual bsp::host::SimCan& can() = 0;
  virtual const bsp::host::SimCan& can() const = 0;
};

}  // namespace bmssim
