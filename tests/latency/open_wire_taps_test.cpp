// An open sense wire at every tap (issue 24 item 3): the bottom tap (the wire below cell 1, VC0), one in the
// middle and the top tap (above the last cell), on each image as bms-sim runs it. The cell beside an open
// end tap reads nothing (SLUSF21: VC0's current source pulls it up, every other VC pin's sink pulls it down;
// SLUUBY2B: the BQ769x2's open-wire current drains the node); a middle tap gives one cell reading nothing and
// its neighbour both. Every position must trip open_wire within one scan period, open both paths, and take
// the cells beside it out of what is published: their CellVoltages slots not available with status
// open_wire (the BQ4050 gauge refuses a cell word above 5 V: then no valid board at all), and PackVoltage
// not available (the pack's sum would hold a 0 mV "cell"). Before, the bottom and top taps went out as a
// valid 0 mV cell, inside PackVoltage, with charging on.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/protection/protection.hpp"
#include "can/bms.hpp"
#include "image_sim.hpp"

namespace {

namespace bms = fw::can::bms;
using fw::app::FaultId;

std::unique_ptr<bmssim::ImageSim> make() {
  bmssim::SimOptions options;
  options.image = BMS_SIM_IMAGE;
  options.devices = 2;
  std::string error;
  for (const auto& e : bmssim::images()) {
    if (options.image == e.image) return e.make(options, error);
  }
  return nullptr;
}

fw::hal::CanFrame canFrame(const bmssim::SentFrame& s) {
  fw::hal::CanFrame f{};
  f.id = s.id;
  f.extended = s.extended;
  f.dlc = static_cast<uint8_t>(s.data.size());
  for (size_t i = 0; i < s.data.size() && i < 8; ++i)
    f.data[i] = s.data[i];
  return f;
}

void run(bmssim::ImageSim& sim, uint32_t ms) {
  for (uint32_t t = 0; t < ms; ++t) {
    sim.runFor(fw::ms(1));
    sim.afterStep();
  }
}

enum class Tap { Bottom, Middle, Top };

class OpenWireTap : public ::testing::TestWithParam<Tap> {};

TEST_P(OpenWireTap, IsAnOpenWireWithItsCellsNotAvailable) {
  auto sim = make();
  ASSERT_TRUE(sim);
  const int cells = sim->cellsPerBoard();
  // The wire below cell `tap` (cells + 1: above the top cell), and the cells that no longer read a voltage.
  const int tap = GetParam() == Tap::Bottom ? 1 : GetParam() == Tap::Top ? cells + 1 : cells / 2 + 1;
  std::vector<int> beside;
  if (tap > 1) beside.push_back(tap - 1);
  if (tap <= cells) beside.push_back(tap);
  run(*sim, 1000);
  ASSERT_EQ(sim->figures().activeFaults, 0);
  const uint64_t onsetUs = sim->harness().nowUs();
  sim->openWire(0, tap);
  run(*sim, 150);
  auto f = sim->figures();
  EXPECT_NE(f.activeFaults & fw::app::bit(FaultId::OpenWire), 0) << "tap " << tap;
  EXPECT_FALSE(f.chargeOn) << "tap " << tap;
  EXPECT_FALSE(f.dischargeOn) << "tap " << tap;
  const auto log = sim->protectionLog();
  uint64_t detectedUs = 0;
  for (const auto& r : log)
    if (r.fault == FaultId::OpenWire) detectedUs = r.detected.us;
  ASSERT_NE(detectedUs, 0u);
  run(*sim, 1100);  // a whole cycle of the 1 s cell frames
  f = sim->figures();
  EXPECT_NE(f.activeFaults & fw::app::bit(FaultId::OpenWire), 0) << "tap " << tap << ": still open";
  // What went out from the first PackSummary that reports the fault on (a frame built before the detection,
  // still on its way out then, carries the scan before it), which comes within one cycle of the detection.
  constexpr uint16_t kOpenWire = fw::app::bit(FaultId::OpenWire);
  uint64_t reportedUs = 0;
  std::vector<bool> seen(static_cast<size_t>(cells) + 1, false);
  for (const auto& s : sim->frames()) {
    if (s.timeUs <= detectedUs || s.extended) continue;
    if (s.id == bms::PackSummary::kId) {
      const auto m = bms::PackSummary::unpack(canFrame(s));
      if (reportedUs == 0 && (m.activeFaults & kOpenWire) != 0) reportedUs = s.timeUs;
      if (reportedUs == 0) continue;
      EXPECT_EQ(m.packVoltage, bms::PackSummary::kPackVoltageNotAvailable)
          << "tap " << tap << ": PackVoltage at " << s.timeUs << " us";
    } else if (reportedUs != 0 && s.id == bms::CellVoltages::kId) {
      const auto m = bms::CellVoltages::unpack(canFrame(s));
      if (m.board != 0) continue;
      for (int k = 0; k < 3; ++k) {
        const int cell = m.frameIndex * 3 + k + 1;
        for (int b : beside) {
          if (cell != b) continue;
          seen[static_cast<size_t>(cell)] = true;
          EXPECT_EQ(m.cell[k], bms::CellVoltages::kCellNotAvailable) << "tap " << tap << ", cell " << cell;
          // A board published as valid says why the slot is empty (status 4, open_wire); a monitor that
          // refused the whole reading (the BQ4050 gauge, a cell word above 5 V) publishes no valid board.
          EXPECT_NE(m.status, 0) << "tap " << tap << ", cell " << cell << ": status valid";
          if (m.status == 0 || m.status == 4) continue;
          for (int j = 0; j < 3; ++j)
            EXPECT_EQ(m.cell[j], bms::CellVoltages::kCellNotAvailable)
                << "tap " << tap << ", status " << int{m.status};
        }
      }
    }
  }
  ASSERT_NE(reportedUs, 0u) << "tap " << tap << ": no PackSummary reports open_wire";
  EXPECT_LE(reportedUs - detectedUs, 110000u) << "tap " << tap << ": open_wire published late";
  for (int b : beside)
    EXPECT_TRUE(seen[static_cast<size_t>(b)]) << "no CellVoltages frame with cell " << b;
  std::printf("REPORT open_wire.%s.tap%d=%.3f ms onset to detection (%s)\n", BMS_SIM_IMAGE, tap,
              static_cast<double>(detectedUs - onsetUs) / 1000.0,
              GetParam() == Tap::Bottom ? "bottom"
              : GetParam() == Tap::Top  ? "top"
                                        : "middle");
}

INSTANTIATE_TEST_SUITE_P(Taps, OpenWireTap, ::testing::Values(Tap::Bottom, Tap::Middle, Tap::Top),
                         [](const ::testing::TestParamInfo<Tap>& info) {
                           return info.param == Tap::Bottom ? "Bottom"
                                  : info.param == Tap::Top  ? "Top"
                                                            : "Middle";
                         });

}  // namespace
