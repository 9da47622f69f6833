// The G3507-BQ76952 board of bq769x2/board.hpp with a command sender on its CAN bus: the commands' tests
// (command_app_test.cpp, storage_app_test.cpp) build frames as bmsctl send does and read the answers back.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "bq769x2/board.hpp"
#include "can/bms.hpp"
#include "commands/command_frames.hpp"

namespace command_rig {

namespace bms = fw::can::bms;

struct Rig {
  std::unique_ptr<bsp::host::G3507Bq76952Board> board = bsp::host::makeG3507Bq76952Board();
  bsp::host::G3507Bq76952Board& b = *board;
  bmstool::CommandBuilder commands;
  size_t seen = 0;

  Rig() { b.h.runFor(fw::ms(1000)); }  // set up and measuring

  void send(const std::string& message, const std::vector<std::string>& words = {}) {
    std::string error;
    const auto f = commands.build(message, words, error);
    ASSERT_TRUE(f) << error;
    b.output.peerSend(*f);
  }
  void sendRaw(const fw::hal::CanFrame& f) { b.output.peerSend(f); }
  // The answers (0x580..0x584) sent since the last call.
  std::vector<fw::hal::CanFrame> answers() {
    std::vector<fw::hal::CanFrame> out;
    const auto& sent = b.output.sent();
    for (; seen < sent.size(); ++seen) {
      if (sent[seen].frame.id >= 0x580 && sent[seen].frame.id <= 0x584) out.push_back(sent[seen].frame);
    }
    return out;
  }
  // Sends, runs 20 ms, and returns the one acknowledgement that came back.
  bms::CommandAck ack(const std::string& message, const std::vector<std::string>& words = {}) {
    answers();
    send(message, words);
    b.h.runFor(fw::ms(20));
    const auto a = answers();
    EXPECT_FALSE(a.empty()) << message << ": no answer";
    if (a.empty()) return {};
    EXPECT_EQ(a[0].id, bms::CommandAck::kId);
    return bms::CommandAck::unpack(a[0]);
  }
  bool active(fw::app::FaultId f) const { return (b.app.status().active & fw::app::bit(f)) != 0; }
};

}  // namespace command_rig
