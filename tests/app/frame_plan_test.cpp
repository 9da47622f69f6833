// FramePlan: which frames a publish cycle carries, and that no stale or invalid value goes out as current.
#include <gtest/gtest.h>

#include <vector>

#include "app/frame_plan.hpp"
#include "can/bms.hpp"

namespace {

using fw::ms;
using fw::app::BoardSample;
using fw::app::FramePlan;
using fw::app::PackView;
using fw::app::PublishStatus;
namespace bms = fw::can::bms;

fw::Instant at(uint32_t tMs) {
  return fw::Instant{tMs * 1000};
}

struct Pack {
  BoardSample boards[2]{};
  int16_t raw[2][16]{};
  PackView view;
  PublishStatus status;
  FramePlan plan{view, status, ms(300)};

  Pack() {
    view.boards = boards;
    view.cellsPerBoard = 16;
    view.tempsPerBoard = 2;
    view.rawCells = &raw[0][0];
    for (int b = 0; b < 2; ++b) {
      boards[b].valid = true;
      boards[b].last = fw::Status::Ok;
      for (int c = 0; c < 16; ++c) {
        boards[b].cellMv[c] = static_cast<int16_t>(3000 + 100 * b + c);
        raw[b][c] = static_cast<int16_t>(0x1000 + 0x100 * b + c);
      }
      boards[b].tempDeciK[0] = static_cast<int16_t>(2982 + b);
      boards[b].tempDeciK[1] = static_cast<int16_t>(2990 + b);
    }
    scanned(0);
  }
  void scanned(uint32_t tMs) {
    for (auto& b : boards) {
      if (b.last == fw::Status::Ok) b.takenAt = at(tMs);
    }
    fw::app::summarize(view, at(tMs));
  }
  // All frames of the current cycle, as built at `tMs`.
  std::vector<fw::hal::CanFrame> drain(uint32_t tMs) {
    std::vector<fw::hal::CanFrame> out;
    fw::hal::CanFrame f;
    while (plan.build(at(tMs), f)) {
      out.push_back(f);
      plan.advance();
    }
    return out;
  }
};

std::vector<uint32_t> ids(const std::vector<fw::hal::CanFrame>& frames) {
  std::vector<uint32_t> v;
  for (const auto& f : frames)
    v.push_back(f.id);
  return v;
}

TEST(FramePlan, FastCycleIsSummaryAndExtremesPlusAnEventWhenAFaultChanged) {
  Pack p;
  p.plan.beginFast();
  EXPECT_EQ(ids(p.drain(10)), (std::vector<uint32_t>{0x100, 0x101}));
  p.status.pendingTripped = 0x0001;
  p.plan.beginFast();
  const auto frames = p.drain(10);
  ASSERT_EQ(ids(frames), (std::vector<uint32_t>{0x100, 0x101, 0x103}));
  EXPECT_EQ(bms::ProtectionEvent::unpack(frames[2]).newlyTripped, 0x0001);
  EXPECT_EQ(p.status.pendingTripped, 0) << "sending the event consumes it";
  p.plan.beginFast();
  EXPECT_EQ(p.drain(10).size(), 2u);
}

TEST(FramePlan, SlowCycleCarriesEveryBoardsCellsAndTemperatures) {
  Pack p;
  p.plan.beginSlow();
  const auto frames = p.drain(10);
  // summary, extremes, 2 boards x 6 cell frames, 2 boards x 1 temperature frame, temperature extremes.
  ASSERT_EQ(frames.size(), 2u + 12u + 2u + 1u);
  for (int b = 0; b < 2; ++b) {
    for (int k = 0; k < 6; ++k) {
      const auto m = bms::CellVoltages::unpack(frames[2 + b * 6 + k]);
      EXPECT_EQ(m.board, b);
      EXPECT_EQ(m.frameIndex, k);
      EXPECT_EQ(m.status, 0) << "valid";
      for (int j = 0; j < 3; ++j) {
        const int cell = k * 3 + j;
        EXPECT_EQ(m.cell[j], cell < 16 ? 3000 + 100 * b + cell : 0) << "board " << b << " cell " << cell;
      }
    }
  }
  const auto t1 = bms::Temperatures::unpack(frames[15]);
  EXPECT_EQ(t1.board, 1);
  EXPECT_EQ(t1.temp[0], 2983);
  EXPECT_EQ(t1.temp[1], 2991);
  EXPECT_EQ(t1.temp[2], 0);
  const auto e = bms::TemperatureExtremes::unpack(frames[16]);
  EXPECT_EQ(e.maxTemperature, 2991);
  EXPECT_EQ(e.minTemperature, 2982);
  const auto s = bms::PackSummary::unpack(frames[0]);
  EXPECT_EQ(s.dataValid, 1);
  EXPECT_EQ(s.packVoltage, (16 * 3000 + 120 + 16 * 3100 + 120 + 5) / 10);
  const auto x = bms::CellExtremes::unpack(frames[1]);
  EXPECT_EQ(x.maxCellVoltage, 3115);
  EXPECT_EQ(x.maxCellIndex, 16 + 15);
  EXPECT_EQ(x.minCellVoltage, 3000);
  EXPECT_EQ(x.minCellIndex, 0);
}

TEST(FramePlan, AFailedBoardGoesOutWithItsStatusAndNoValues) {
  Pack p;
  p.boards[1].last = fw::Status::NoResponse;  // board 1 stopped answering; it has old values
  p.scanned(100);
  p.plan.beginSlow();
  const auto frames = p.drain(110);
  for (int k = 0; k < 6; ++k) {
    const auto m = bms::CellVoltages::unpack(frames[2 + 6 + k]);
    EXPECT_EQ(m.board, 1);
    EXPECT_EQ(m.status, 2) << "comm_fault";
    EXPECT_EQ(m.cell[0] | m.cell[1] | m.cell[2], 0) << "no old value goes out";
  }
  EXPECT_EQ(bms::CellVoltages::unpack(frames[2]).status, 0) << "board 0 is still valid";
  EXPECT_EQ(bms::CellExtremes::unpack(frames[1]).maxCellVoltage, 3015) << "extremes only over valid boards";
}

TEST(FramePlan, ProtectionEventCountsEveryFailedBoardMeasurementAndSaturates) {
  Pack p;
  EXPECT_EQ(p.view.commErrors, 0);
  p.boards[1].last = fw::Status::NoResponse;
  p.scanned(100);  // board 1 failed: 1
  p.boards[0].last = fw::Status::Crc;
  p.scanned(200);  // both failed: 3
  p.boards[0].last = p.boards[1].last = fw::Status::Ok;
  p.scanned(300);  // none failed: still 3
  p.status.pendingTripped = 0x0001;
  p.plan.beginFast();
  auto frames = p.drain(300);
  ASSERT_EQ(ids(frames), (std::vector<uint32_t>{0x100, 0x101, 0x103}));
  EXPECT_EQ(bms::ProtectionEvent::unpack(frames[2]).commErrors, 3);

  p.view.commErrors = 65534;
  p.boards[0].last = p.boards[1].last = fw::Status::Timeout;
  p.scanned(400);
  p.scanned(500);
  p.status.pendingTripped = 0x0001;
  p.plan.beginFast();
  frames = p.drain(500);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(bms::ProtectionEvent::unpack(frames[2]).commErrors, 65535) << "saturates, never wraps to 0";
}

TEST(FramePlan, StaleDataIsNeverSentAsCurrent) {
  Pack p;  // scanned at 0 ms; stale after 300 ms
  p.plan.beginSlow();
  const auto frames = p.drain(301);
  const auto s = bms::PackSummary::unpack(frames[0]);
  EXPECT_EQ(s.dataValid, 0);
  EXPECT_EQ(s.packVoltage, 0);
  EXPECT_EQ(s.stateOfCharge, 255);
  EXPECT_EQ(bms::CellExtremes::unpack(frames[1]).maxCellVoltage, 0);
  for (int k = 0; k < 12; ++k) {
    const auto m = bms::CellVoltages::unpack(frames[2 + k]);
    EXPECT_EQ(m.status, 1) << "stale";
    EXPECT_EQ(m.cell[0] | m.cell[1] | m.cell[2], 0);
  }
}

TEST(FramePlan, AFrameHeldBackIsRebuiltFromTheDataWhenItFinallyGoes) {
  Pack p;
  p.plan.beginSlow();
  fw::hal::CanFrame f;
  ASSERT_TRUE(p.plan.build(at(10), f));
  EXPECT_EQ(bms::PackSummary::unpack(f).dataValid, 1);
  // The queue refused it; by the time the bus takes it the data went stale.
  ASSERT_TRUE(p.plan.build(at(400), f));
  EXPECT_EQ(bms::PackSummary::unpack(f).dataValid, 0);
}

TEST(FramePlan, TiCycleIsSeed001sLayoutTopOfStackFirst) {
  Pack p;
  p.plan.beginTi();
  const auto frames = p.drain(10);
  ASSERT_EQ(frames.size(), 8u);
  for (const auto& f : frames)
    EXPECT_EQ(f.id, 0x004u);
  // Slot 0 is board 1 (the top), cells 16..13 big-endian; slot 1 is board 0.
  EXPECT_EQ(frames[0].data, (std::array<uint8_t, 8>{0x11, 0x0F, 0x11, 0x0E, 0x11, 0x0D, 0x11, 0x0C}));
  EXPECT_EQ(frames[3].data, (std::array<uint8_t, 8>{0x11, 0x03, 0x11, 0x02, 0x11, 0x01, 0x11, 0x00}));
  EXPECT_EQ(frames[4].data, (std::array<uint8_t, 8>{0x10, 0x0F, 0x10, 0x0E, 0x10, 0x0D, 0x10, 0x0C}));
}

TEST(FramePlan, TiCycleLeavesOutABoardThatIsNotValid) {
  Pack p;
  p.boards[1].last = fw::Status::Crc;
  p.scanned(100);
  p.plan.beginTi();
  const auto frames = p.drain(110);
  ASSERT_EQ(frames.size(), 4u) << "only board 0: the TI layout cannot mark a board invalid";
  EXPECT_EQ(frames[0].data[0], 0x10);
}

TEST(FramePlan, AbandonEndsTheCycleAndCounterCountsSummaries) {
  Pack p;
  p.plan.beginSlow();
  fw::hal::CanFrame f;
  ASSERT_TRUE(p.plan.build(at(10), f));
  EXPECT_EQ(bms::PackSummary::unpack(f).counter, 0);
  p.plan.advance();
  p.plan.abandon();
  EXPECT_FALSE(p.plan.active());
  EXPECT_FALSE(p.plan.build(at(10), f));
  p.plan.beginFast();
  ASSERT_TRUE(p.plan.build(at(10), f));
  EXPECT_EQ(bms::PackSummary::unpack(f).counter, 1);
}

}  // namespace
