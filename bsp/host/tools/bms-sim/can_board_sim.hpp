// The part of an image binding that only depends on its host board sending on a simulated CAN controller:
// CanBoardSim<Board> owns the board (built from the arguments given to its constructor) and answers for it
// the ImageSim calls every such binding answers the same way: the harness, bus-off injection and its log,
// frames from a peer and a peer flood, the frames sent, and the protection log.
// Board has `h` (bsp::host::Harness), `can` (bsp::host::SimCan) and `app` (the image's app, with
// protection()). A binding derives from CanBoardSim<ItsBoard> and reaches the board as board_.
#pragma once

#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "image_sim.hpp"
#include "pack_figures.hpp"
#include "sim/can.hpp"

namespace bmssim {

template <class Board>
class CanBoardSim : public ImageSim {
 public:
  bsp::host::Harness& harness() override { return board_.h; }

  bool busOff() override {
    board_.can.injectBusOff();
    return true;
  }
  bool canSend(const fw::hal::CanFrame& f) override {
    board_.can.peerSend(f);
    return true;
  }
  bool canFlood(std::function<std::optional<fw::hal::CanFrame>()> source) override {
    board_.can.setPeerSource(std::move(source));
    return true;
  }
  std::vector<BusOffSpan> busOffLog() const override { return busOffSpans(board_.can); }
  std::vector<SentFrame> frames() const override { return canFrames(board_.can); }

  std::vector<fw::app::ProtectionRecord> protectionLog() const override {
    return protectionLogOf(board_.app);
  }

 protected:
  template <class... Args>
  explicit CanBoardSim(Args&&... args) : board_(std::forward<Args>(args)...) {}

  Board board_;
};

}  // namespace bmssim
