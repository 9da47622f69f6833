// FramePlan: which frames a publish cycle carries, that no stale or invalid value goes out as current, and
// that a value with no reading behind it goes out as its signal's not-available value (bms.yaml).
#include <gtest/gtest.h>

#include <iterator>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "app/publish/frame_plan.hpp"
#include "app/version.hpp"
#include "can/bms.hpp"

namespace {

using fw::ms;
using fw::app::BoardSample;
using fw::app::FramePlan;
using fw::app::PackView;
using fw::app::PublishStatus;
namespace bms = fw::can::bms;

constexpr uint16_t kNa = 0xFFFF;  // every unsigned signal's not-available value in bms.yaml

fw::Instant at(uint32_t tMs) {
  return fw::Instant{tMs * 1000};
}

struct Pack {
  std::vector<BoardSample> boards;
  std::vector<int16_t> raw;
  PackView view;
  PublishStatus status;
  FramePlan plan{view, status, ms(300)};

  explicit Pack(int n = 2, uint8_t cells = 16, uint8_t temps = 2) : boards(n), raw(n * 16) {
    view.boards = boards;
    view.cellsPerBoard = cells;
    view.tempsPerBoard = temps;
    view.rawCells = raw.data();
    for (int b = 0; b < n; ++b) {
      boards[b].valid = true;
      boards[b].last = fw::Status::Ok;
      for (int c = 0; c < 16; ++c) {
        boards[b].cellMv[c] = static_cast<int16_t>(3000 + 100 * b + c);
        raw[b * 16 + c] = static_cast<int16_t>(0x1000 + 0x100 * b + c);
      }
      for (int t = 0; t < 4; ++t)
        boards[b].tempDeciK[t] = static_cast<int16_t>(2982 + 8 * t + b);
    }
    scanned(0);
  }
  void scanned(uint32_t tMs) {
    for (auto& b : boards) {
      if (b.last == fw::Status::Ok) b.takenAt = at(tMs);
    }
    fw::app::summarize(view, at(tMs));
  }
  // All frames of the current cycle, as built at `tMs`; at most `limit` of them.
  std::vector<fw::hal::CanFrame> drain(uint32_t tMs, size_t limit = SIZE_MAX) {
    std::vector<fw::hal::CanFrame> out;
    fw::hal::CanFrame f;
    while (out.size() < limit && plan.build(at(tMs), f)) {
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
  // summary, extremes, 2 boards x 6 cell frames, 2 boards x 1 temperature frame, temperature extremes,
  // state of charge.
  ASSERT_EQ(frames.size(), 2u + 12u + 2u + 1u + 1u);
  EXPECT_EQ(frames[17].id, bms::StateOfCharge::kId);
  for (int b = 0; b < 2; ++b) {
    for (int k = 0; k < 6; ++k) {
      const auto m = bms::CellVoltages::unpack(frames[2 + b * 6 + k]);
      EXPECT_EQ(m.board, b);
      EXPECT_EQ(m.frameIndex, k);
      EXPECT_EQ(m.status, 0) << "valid";
      for (int j = 0; j < 3; ++j) {
        const int cell = k * 3 + j;
        EXPECT_EQ(m.cell[j], cell < 16 ? 3000 + 100 * b + cell : kNa) << "board " << b << " cell " << cell;
      }
    }
  }
  const auto t1 = bms::Temperatures::unpack(frames[15]);
  EXPECT_EQ(t1.board, 1);
  EXPECT_EQ(t1.temp[0], 2983);
  EXPECT_EQ(t1.temp[1], 2991);
  EXPECT_EQ(t1.temp[2], kNa) << "the board has two sensors: the third slot has no reading";
  const auto e = bms::TemperatureExtremes::unpack(frames[16]);
  EXPECT_EQ(e.maxTemperature, 2991);
  EXPECT_EQ(e.minTemperature, 2982);
  const auto s = bms::PackSummary::unpack(frames[0]);
  EXPECT_EQ(s.dataValid, 1);
  EXPECT_EQ(s.packVoltage, (16 * 3000 + 120 + 16 * 3100 + 120 + 50) / 100) << "0.1 V steps";
  const auto x = bms::CellExtremes::unpack(frames[1]);
  EXPECT_EQ(x.maxCellVoltage, 3115);
  EXPECT_EQ(x.maxCellIndex, 16 + 15);
  EXPECT_EQ(x.minCellVoltage, 3000);
  EXPECT_EQ(x.minCellIndex, 0);
}

TEST(FramePlan, CellsAndSensorsABoardDoesNotHaveAreNotAvailable) {
  // A BQ76907 board: 7 cells, 1 sensor; a pack monitor without a current sensor.
  Pack p(1, 7, 1);
  p.plan.beginSlow();
  const auto frames = p.drain(10);
  ASSERT_EQ(ids(frames), (std::vector<uint32_t>{0x100, 0x101, 0x200, 0x200, 0x200, 0x201, 0x102, 0x104}));
  const auto c2 = bms::CellVoltages::unpack(frames[4]);  // cells 7..9
  EXPECT_EQ(c2.cell[0], 3006);
  EXPECT_EQ(c2.cell[1], kNa) << "cell 8 was sent as 0 mV";
  EXPECT_EQ(c2.cell[2], kNa);
  const auto t = bms::Temperatures::unpack(frames[5]);
  EXPECT_EQ(t.temp[0], 2982);
  EXPECT_EQ(t.temp[1], kNa) << "sensor 2 was sent as 0 K (-273.15 degC)";
  EXPECT_EQ(t.temp[2], kNa);
  const auto s = bms::PackSummary::unpack(frames[0]);
  EXPECT_EQ(s.packCurrent, bms::PackSummary::kPackCurrentNotAvailable) << "no sensor: not 0 A";
  EXPECT_EQ(s.stateOfCharge, 255);
}

// StateOfCharge (once a second) and PackSummary.StateOfCharge carry the view's value once known, while the
// scan behind it is fresh; not available before and after.
TEST(FramePlan, StateOfChargeGoesOutOnceKnownAndWhileFresh) {
  Pack p;
  auto slow = [&](uint32_t tMs) {
    p.plan.beginSlow();
    const auto frames = p.drain(tMs);
    return std::pair{bms::PackSummary::unpack(frames.front()), bms::StateOfCharge::unpack(frames.back())};
  };
  auto [s, q] = slow(10);
  EXPECT_EQ(s.stateOfCharge, 255) << "nothing known yet";
  EXPECT_EQ(q.soc, bms::StateOfCharge::kSocNotAvailable);
  EXPECT_EQ(q.remainingCapacity, bms::StateOfCharge::kRemainingCapacityNotAvailable);
  EXPECT_EQ(q.fullChargeCapacity, bms::StateOfCharge::kFullChargeCapacityNotAvailable);
  EXPECT_EQ(q.basis, bms::StateOfCharge::kBasisNotAvailable);

  p.view.soc.set(437, 1092, 2500, fw::app::SocBasis::Ocv);
  std::tie(s, q) = slow(20);
  EXPECT_EQ(s.stateOfCharge, 44) << "43.7 % rounded";
  EXPECT_EQ(q.soc, 437);
  EXPECT_EQ(q.remainingCapacity, 1092u);
  EXPECT_EQ(q.fullChargeCapacity, 2500u);
  EXPECT_EQ(q.basis, static_cast<uint8_t>(fw::app::SocBasis::Ocv));

  p.view.soc.set(1000, 4000, 4000, fw::app::SocBasis::Gauge);
  std::tie(s, q) = slow(30);
  EXPECT_EQ(s.stateOfCharge, 100);
  EXPECT_EQ(q.soc, 1000);
  EXPECT_EQ(q.basis, 5);

  std::tie(s, q) = slow(301);  // scanned at 0 ms, stale after 300 ms
  EXPECT_EQ(s.stateOfCharge, 255);
  EXPECT_EQ(q.soc, bms::StateOfCharge::kSocNotAvailable) << "an old value is not sent as current";
  EXPECT_EQ(q.remainingCapacity, bms::StateOfCharge::kRemainingCapacityNotAvailable);
}

TEST(FramePlan, ATemperatureWithNoReadingIsNotAvailableAndLeftOutOfTheExtremes) {
  Pack p;
  p.boards[1].tempDeciK[0] = fw::app::kNoReading;  // that part of board 1's scan failed
  p.scanned(100);
  p.plan.beginSlow();
  const auto frames = p.drain(110);
  const auto t1 = bms::Temperatures::unpack(frames[15]);
  EXPECT_EQ(t1.status, 0);
  EXPECT_EQ(t1.temp[0], kNa);
  EXPECT_EQ(t1.temp[1], 2991);
  const auto e = bms::TemperatureExtremes::unpack(frames[16]);
  EXPECT_EQ(e.minTemperature, 2982);
  EXPECT_EQ(e.minTemperatureIndex, 0);
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
    for (int j = 0; j < 3; ++j)
      EXPECT_EQ(m.cell[j], kNa) << "no old value, and no 0 mV, goes out";
  }
  EXPECT_EQ(bms::Temperatures::unpack(frames[15]).temp[0], kNa);
  EXPECT_EQ(bms::CellVoltages::unpack(frames[2]).status, 0) << "board 0 is still valid";
  EXPECT_EQ(bms::CellExtremes::unpack(frames[1]).maxCellVoltage, 3015) << "extremes only over valid boards";
  const auto s = bms::PackSummary::unpack(frames[0]);
  EXPECT_EQ(s.dataValid, 1);
  EXPECT_EQ(s.packVoltage, kNa) << "board 0 alone is not the pack";
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

TEST(FramePlan, StaleDataIsNeverSentAsCurrentNorAsAReading) {
  Pack p;  // scanned at 0 ms; stale after 300 ms
  p.plan.beginSlow();
  const auto frames = p.drain(301);
  const auto s = bms::PackSummary::unpack(frames[0]);
  EXPECT_EQ(s.dataValid, 0);
  EXPECT_EQ(s.packVoltage, kNa);
  EXPECT_EQ(s.packCurrent, bms::PackSummary::kPackCurrentNotAvailable);
  EXPECT_EQ(s.stateOfCharge, 255);
  const auto x = bms::CellExtremes::unpack(frames[1]);
  EXPECT_EQ(x.maxCellVoltage, kNa) << "was 0 mV";
  EXPECT_EQ(x.maxCellIndex, kNa);
  EXPECT_EQ(x.minCellVoltage, kNa);
  EXPECT_EQ(x.minCellIndex, kNa);
  for (int k = 0; k < 12; ++k) {
    const auto m = bms::CellVoltages::unpack(frames[2 + k]);
    EXPECT_EQ(m.status, 1) << "stale";
    EXPECT_EQ(m.cell[0] & m.cell[1] & m.cell[2], kNa);
  }
  const auto e = bms::TemperatureExtremes::unpack(frames[16]);
  EXPECT_EQ(e.maxTemperature, kNa) << "was 0 K, -273.15 degC";
  EXPECT_EQ(e.minTemperature, kNa);
  EXPECT_EQ(e.maxTemperatureIndex, kNa);
  EXPECT_EQ(e.minTemperatureIndex, kNa);
}

TEST(FramePlan, PackVoltageOfTheLargestPackFits) {
  // 64 boards x 16 cells x 5 V = 5 120 V: 0.1 V steps give 51 200 (the 10 mV steps sent 655.35 V).
  Pack p(64);
  for (auto& b : p.boards) {
    for (auto& c : b.cellMv)
      c = 5000;
  }
  p.scanned(100);
  p.plan.beginFast();
  EXPECT_EQ(bms::PackSummary::unpack(p.drain(110)[0]).packVoltage, 51200);
}

TEST(FramePlan, AnOpenSenseWireMarksTheTwoCellsBesideIt) {
  // The tap between cells 3 and 4 of board 1 (numbered from 1) is open: cell 3 reads both, cell 4 nothing.
  Pack p;
  p.boards[1].cellMv[2] = 7400;
  p.boards[1].cellMv[3] = 0;
  p.scanned(100);
  EXPECT_TRUE(p.view.totals.openWire);
  p.plan.beginSlow();
  const auto frames = p.drain(110);
  const auto f0 = bms::CellVoltages::unpack(frames[2 + 6 + 0]);  // board 1, cells 1..3
  const auto f1 = bms::CellVoltages::unpack(frames[2 + 6 + 1]);  // cells 4..6
  EXPECT_EQ(f0.status, 4) << "open_wire";
  EXPECT_EQ(f0.cell[0], 3100);
  EXPECT_EQ(f0.cell[2], kNa);
  EXPECT_EQ(f1.status, 4);
  EXPECT_EQ(f1.cell[0], kNa);
  EXPECT_EQ(f1.cell[1], 3104);
  EXPECT_EQ(bms::CellVoltages::unpack(frames[2 + 6 + 2]).status, 0) << "cells 7..9 are fine";
  EXPECT_EQ(bms::CellVoltages::unpack(frames[2]).status, 0) << "board 0 is fine";
  const auto x = bms::CellExtremes::unpack(frames[1]);
  // 7 400 and 0 mV are not cell voltages: board 1 stays out of the extremes (and the cell limits; open_wire
  // stands in for them) until the wire is back.
  EXPECT_EQ(x.maxCellVoltage, 3015);
  EXPECT_EQ(x.maxCellIndex, 15);
  EXPECT_EQ(x.minCellVoltage, 3000);
  EXPECT_EQ(bms::PackSummary::unpack(frames[0]).packVoltage, kNa);
}

// An open wire shows as two neighbours too far apart, or one reading below the plausibility floor (500 mV):
// the bottom and top taps have no neighbour beyond them, and a 0 mV reading is never a cell voltage.
TEST(FramePlan, OpenWireIsAPairTooFarApartOrAReadingBelowTheFloor) {
  const int16_t normal[4] = {3700, 4300, 3700, 3700};
  EXPECT_EQ(fw::app::openWireCells(normal, 4), 0);
  const int16_t flat[4] = {3700, 501, 3700, 3700};  // a deeply discharged cell is a cell_uv matter
  EXPECT_EQ(fw::app::openWireCells(flat, 4), 0);
  const int16_t empty[4] = {3700, 0, 3700, 3700};  // below the floor: not a cell voltage
  EXPECT_EQ(fw::app::openWireCells(empty, 4), 0b0010);
  const int16_t bottom[4] = {0, 3700, 3700, 3700};  // VC0 open (SLUSF21: its current source pulls it up)
  EXPECT_EQ(fw::app::openWireCells(bottom, 4), 0b0001);
  const int16_t top[4] = {3700, 3700, 3700, 499};  // the top tap open: its node drained
  EXPECT_EQ(fw::app::openWireCells(top, 4), 0b1000);
  const int16_t negative[4] = {3700, 3700, -40, 3700};
  EXPECT_EQ(fw::app::openWireCells(negative, 4), 0b0100);
  const int16_t below[4] = {3700, 7400, 0, 3700};  // bms-sim's model: the cell below the open tap reads both
  EXPECT_EQ(fw::app::openWireCells(below, 4), 0b0110);
  const int16_t above[4] = {0, 6250, 3700, 3700};  // or the other way round; BQ79616 full scale 6 250 mV
  EXPECT_EQ(fw::app::openWireCells(above, 4), 0b0011);
  const int16_t last[4] = {3700, 3700, 3700, 7400};  // beyond the board's cells: not looked at
  EXPECT_EQ(fw::app::openWireCells(last, 3), 0);
  const int16_t beyond[4] = {3700, 3700, 3700, 0};
  EXPECT_EQ(fw::app::openWireCells(beyond, 3), 0);
  const int16_t one[1] = {0};
  EXPECT_EQ(fw::app::openWireCells(one, 1), 0b1);
}

// The window a CellVoltages frame uses gives the whole board's verdict for its cells, at every position
// (the ends of the board included) and for every kind of open wire, on boards of every size.
TEST(FramePlan, OpenWireOfAWindowIsTheBoardsVerdictForItsCells) {
  const int16_t readings[] = {3700, 0, 7400, 499, 500, 6250, -40, 3700, 8300};
  uint32_t seed = 1;
  int open = 0;
  for (int round = 0; round < 2000; ++round) {
    int16_t cells[fw::app::kMaxCellsPerBoard];
    for (int16_t& c : cells) {
      seed = seed * 1103515245U + 12345U;
      c = (seed >> 16) % 4 != 0 ? int16_t{3700} : readings[(seed >> 18) % std::size(readings)];
    }
    for (uint8_t n = 1; n <= fw::app::kMaxCellsPerBoard; ++n) {
      const uint16_t board = fw::app::openWireCells(cells, n);
      open += board != 0;
      for (uint8_t first = 0; first < n; ++first)
        for (uint8_t count = 1; count <= 3; ++count)
          ASSERT_EQ(fw::app::openWireCells(cells, n, first, count), (board >> first) & ((1U << count) - 1U))
              << "round " << round << " cells " << int(n) << " from " << int(first) << " count "
              << int(count);
    }
  }
  EXPECT_GT(open, 1000);  // the boards do show open wires
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

TEST(FramePlan, ASlowPartLongerThanAFastPeriodContinuesAfterTheNextFastFrames) {
  // 64 boards: 384 cell frames, 64 temperature frames, the temperature extremes and the state of charge; at
  // 500 kbit/s more
  // than one 100 ms period. Each fast cycle's frames go first, then the slow part picks up where it was.
  Pack p(64);
  EXPECT_FALSE(p.plan.beginSlow());
  auto frames = p.drain(10, 200);
  std::map<std::pair<uint32_t, int>, int> seen;  // (message, board * 16 + frame index) -> times sent
  auto count = [&](const std::vector<fw::hal::CanFrame>& fs) {
    for (const auto& f : fs) {
      if (f.id == 0x200 || f.id == 0x201) ++seen[{f.id, f.data[0] * 16 + (f.data[1] & 0xF)}];
      if (f.id == 0x102 || f.id == 0x104) ++seen[{f.id, 0}];
    }
  };
  count(frames);
  for (int tick = 1; tick < 10; ++tick) {
    EXPECT_FALSE(p.plan.beginFast()) << "tick " << tick << ": nothing is dropped";
    frames = p.drain(10 + 100 * tick, 200);
    ASSERT_GE(frames.size(), 2u);
    EXPECT_EQ(frames[0].id, 0x100u) << "the summary goes first";
    EXPECT_EQ(frames[1].id, 0x101u);
    count(frames);
  }
  EXPECT_FALSE(p.plan.active());
  EXPECT_EQ(seen.size(), 64u * 6 + 64 + 2);
  for (const auto& [key, n] : seen)
    EXPECT_EQ(n, 1) << "message " << key.first << " slot " << key.second;
}

TEST(FramePlan, ANewSlowCycleDropsWhatIsLeftOfTheLastOne) {
  Pack p(64);
  p.plan.beginSlow();
  p.drain(10, 100);
  EXPECT_TRUE(p.plan.beginSlow()) << "the last second's cell frames had not all gone out";
  const auto frames = p.drain(1010, 3);
  EXPECT_EQ(ids(frames), (std::vector<uint32_t>{0x100, 0x101, 0x200}));
  EXPECT_EQ(bms::CellVoltages::unpack(frames[2]).board, 0) << "the new second starts at board 0";
  EXPECT_EQ(bms::CellVoltages::unpack(frames[2]).frameIndex, 0);
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

TEST(FramePlan, TiSetGoesOutOnlyWhenEveryBoardIsValid) {
  // The layout has no board index: leaving board 1 out would make a receiver read board 0's cells as
  // board 1's, and sending board 1 alone would be a set cut short.
  Pack p;
  p.boards[1].last = fw::Status::Crc;
  p.scanned(100);
  p.plan.beginTi();
  EXPECT_TRUE(p.drain(110).empty());
  p.boards[1].last = fw::Status::Ok;
  p.boards[0].last = fw::Status::Crc;
  p.scanned(200);
  p.plan.beginTi();
  EXPECT_TRUE(p.drain(210).empty()) << "not even the top board's frames";
  p.boards[0].last = fw::Status::Ok;
  p.boards[0].cellMv[2] = 7400;  // an open sense wire: two codes that are not cell voltages
  p.boards[0].cellMv[3] = 0;
  p.scanned(300);
  p.plan.beginTi();
  EXPECT_TRUE(p.drain(310).empty()) << "an open wire's codes would go out as cells";
}

TEST(FramePlan, TiSetThatIsGoingOutIsNotCutByTheNextScan) {
  // 64 boards: 256 frames, about 60 ms at 500 kbit/s. A scan that ends meanwhile (start-up, an nFAULT
  // scan) used to restart the set from the top, so boards 0..5 never went out.
  Pack p(64);
  p.plan.beginTi();
  auto frames = p.drain(10, 200);
  p.scanned(50);
  p.plan.beginTi();
  const auto rest = p.drain(50);
  frames.insert(frames.end(), rest.begin(), rest.end());
  ASSERT_EQ(frames.size(), 256u);
  EXPECT_EQ(frames.back().data, (std::array<uint8_t, 8>{0x10, 0x03, 0x10, 0x02, 0x10, 0x01, 0x10, 0x00}))
      << "the set ends with board 0's cells 4..1";
}

TEST(FramePlan, TiSetEndsWhereABoardStopsBeingValid) {
  Pack p(4);
  p.plan.beginTi();
  auto frames = p.drain(10, 6);  // boards 3 and half of 2
  p.boards[1].last = fw::Status::NoResponse;
  p.scanned(60);
  const auto rest = p.drain(60);
  EXPECT_EQ(rest.size(), 2u) << "board 2's last frames, then nothing for board 1 or below";
  EXPECT_FALSE(p.plan.active());
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
  EXPECT_FALSE(p.plan.beginFast()) << "an abandoned cycle is not dropped twice";
  ASSERT_TRUE(p.plan.build(at(10), f));
  EXPECT_EQ(bms::PackSummary::unpack(f).counter, 1);
  p.plan.advance();
  ASSERT_TRUE(p.plan.build(at(10), f));
  EXPECT_EQ(f.id, 0x101u) << "no slow part waits after abandon()";
  p.plan.advance();
  EXPECT_FALSE(p.plan.active());
}

// A summary that never went out leaves a Counter gap (bms.yaml: "a gap means a lost frame"): the cycle was
// abandoned because the controller was bus-off and refused it (the twin's MCAN model, as the M_CAN, keeps
// nothing it was not given), or the next cycle began before it was sent. A summary held back and then sent
// keeps its value. (The counter once counted summaries accepted, so a refused one left no gap.)
TEST(FramePlan, ASummaryThatNeverWentOutLeavesACounterGap) {
  Pack p;
  fw::hal::CanFrame f;
  auto summary = [&](uint32_t tMs) {
    EXPECT_TRUE(p.plan.build(at(tMs), f));
    EXPECT_EQ(f.id, bms::PackSummary::kId);
    return bms::PackSummary::unpack(f).counter;
  };
  p.plan.beginFast();
  EXPECT_EQ(summary(10), 0);
  p.plan.advance();
  p.drain(10);
  p.plan.beginFast();
  EXPECT_EQ(summary(110), 1);
  p.plan.abandon();  // the controller refused it: bus-off
  p.plan.beginFast();
  EXPECT_EQ(summary(210), 2) << "the 110 ms summary (1) was never sent: the receiver sees 0, then 2";
  p.plan.advance();
  p.drain(210);
  p.plan.beginFast();
  EXPECT_EQ(summary(310), 3);  // refused (queue full): rebuilt later with the same value
  EXPECT_EQ(summary(311), 3);
  EXPECT_TRUE(p.plan.beginFast()) << "its cycle is dropped: the 310 ms summary never went out";
  EXPECT_EQ(summary(410), 4) << "the receiver sees 2, then 4";
}

// The Startup message (bms.yaml Startup): once after announceStartup(), at the end of the next cycle's fast
// part, so PackSummary keeps its time.
TEST(FramePlan, StartupGoesOutOnceAfterTheNextFastPart) {
  Pack p;
  p.plan.announceStartup({0x0E, false, 0, 0});  // a WWDT0 reset: no fault record survived it
  p.plan.beginFast();
  const auto frames = p.drain(10);
  EXPECT_EQ(ids(frames), (std::vector<uint32_t>{0x100, 0x101, 0x1F0}));
  const auto u = bms::Startup::unpack(frames[2]);
  EXPECT_EQ(u.resetCause, 0x0E);
  EXPECT_EQ(u.firmwareMajor, fw::app::kFirmwareVersionMajor);
  EXPECT_EQ(u.firmwareMinor, fw::app::kFirmwareVersionMinor);
  EXPECT_EQ(u.firmwarePatch, fw::app::kFirmwareVersionPatch);
  EXPECT_EQ(u.faultModule, bms::Startup::kFaultModuleNotAvailable);
  EXPECT_EQ(u.faultLine, bms::Startup::kFaultLineNotAvailable);
  EXPECT_EQ(bms::PackSummary::unpack(frames[0]).counter, 0);
  p.plan.beginSlow();
  const auto next = p.drain(20);
  ASSERT_FALSE(next.empty());
  for (const auto& f : next)
    EXPECT_NE(f.id, 0x1F0u) << "once only";
}

TEST(FramePlan, StartupCarriesTheFaultRecordThatSurvived) {
  Pack p;
  p.plan.announceStartup({0x1B, true, 30, 0x1234});  // fw::onFault's software SYSRST kept its record
  p.plan.beginSlow();
  const auto frames = p.drain(10);
  ASSERT_GE(frames.size(), 4u);
  EXPECT_EQ(ids(frames)[2], 0x1F0u) << "after the fast part, before the slow part";
  EXPECT_EQ(frames[3].id, 0x200u);
  const fw::hal::CanFrame& f = frames[2];
  EXPECT_EQ(f.data,
            (std::array<uint8_t, 8>{0x1B, fw::app::kFirmwareVersionMajor, fw::app::kFirmwareVersionMinor,
                                    fw::app::kFirmwareVersionPatch, 30, 0x34, 0x12, 0x3F}))
      << "no record store restored: ProtectionLogEntries and FaultSource not available";
}

// What the record store restored (app/store/persistence.hpp): the protection-log entries and where the fault
// record comes from, in the byte that was spare.
TEST(FramePlan, StartupCarriesWhatTheRecordStoreRestored) {
  Pack p;
  fw::app::StartupInfo info{0x01, true, 30, 0xFFFC};  // a power cycle; the watchdog record kept in flash
  info.kept.logEntries = 3;
  info.kept.faultSource = fw::app::FaultSource::Stored;
  p.plan.announceStartup(info);
  p.plan.beginFast();
  const auto frames = p.drain(10);
  ASSERT_EQ(ids(frames), (std::vector<uint32_t>{0x100, 0x101, 0x1F0}));
  const auto u = bms::Startup::unpack(frames[2]);
  EXPECT_EQ(u.resetCause, 0x01);
  EXPECT_EQ(u.faultModule, 30);
  EXPECT_EQ(u.faultLine, 0xFFFC);
  EXPECT_EQ(u.protectionLogEntries, 3);
  EXPECT_EQ(u.faultSource, 2);
  EXPECT_EQ(frames[2].data[7], 0x23);
}

TEST(FramePlan, StartupHeldBackByAFullQueueGoesOutWithTheNextCycle) {
  Pack p;
  p.plan.announceStartup({0x01, false, 0, 0});
  p.plan.beginFast();
  EXPECT_EQ(p.drain(10, 2).size(), 2u);
  p.plan.abandon();  // bus-off before the Startup frame was accepted
  p.plan.beginFast();
  EXPECT_EQ(ids(p.drain(10)), (std::vector<uint32_t>{0x100, 0x101, 0x1F0}));
}

TEST(FramePlan, StartupPrecedesTheFirstTiSet) {
  Pack p;
  p.plan.announceStartup({0x01, false, 0, 0});
  p.plan.beginTi();
  const auto frames = p.drain(10);
  ASSERT_EQ(frames.size(), 9u);
  EXPECT_EQ(frames[0].id, 0x1F0u);
  for (size_t i = 1; i < frames.size(); ++i)
    EXPECT_EQ(frames[i].id, 0x004u);
}

}  // namespace
