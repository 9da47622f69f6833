// State of charge on the BQ769x2-family applications (lp-mspm0g3507-bq76952 and the BQ76907 composition,
// each with its EVM pack's parameters: 2 500 mAh), against the emulator's accumulated charge: the application
// reads the device's counter every scan and the emulator integrates the current into it as the devices do
// (bsp/host/emul/bq769x2/charge.cpp). The truth is the charge the emulator let flow (trueChargeMaUs).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "bq769x2/board.hpp"

namespace {

namespace b769 = fw::drivers::bq769x2;
using Emulator = bsp::host::Bq769xEmulator;
using fw::app::SocBasis;

constexpr int64_t kCapacityMah = 2500;
constexpr int64_t kCapacityMaUs = kCapacityMah * 3600 * 1000000;

struct G3507 : bsp::host::G3507Bq76952Board {
  G3507() : bsp::host::G3507Bq76952Board(Emulator::Model::Bq76952, fw::app::kBq76952Settings, 16, true) {}
  void cells(int16_t mv) {
    for (uint8_t c = 1; c <= 16; ++c)
      emu.setCellMv(c, mv);
  }
};
struct L1306Bq76907 : bsp::host::L1306Bq7690xBoard {
  L1306Bq76907()
      : bsp::host::L1306Bq7690xBoard(Emulator::Model::Bq76907, fw::app::kBq76907Settings, 7, false,
                                     b769::kBq76907) {}
  void cells(int16_t mv) {
    for (uint8_t c = 1; c <= 7; ++c)
      emu.setCellMv(c, mv);
  }
};

// The emulator's true state of charge in 0.1 % from a start value and the charge that flowed since `from`.
int64_t truePermille(int64_t startPermille, int64_t chargeSinceMaUs) {
  return startPermille + chargeSinceMaUs * 1000 / kCapacityMaUs;
}

// Full at rest (every cell 4 190 mV, above the table's 100 % point): the first scan at rest sets 100 %. Then
// 1C (2.5 A) for 59 simulated minutes with the cells at 3 700 mV under load (no full or empty reset, no
// rest): only the count moves the value, which ends within 2 % of the charge the emulator let flow.
template <class Board>
void oneCDischarge(const char* image) {
  Board b;
  b.cells(4190);
  b.emu.setCurrentMa(0);
  b.h.runFor(fw::s(1));
  auto& soc = b.app.stateOfCharge();
  ASSERT_TRUE(soc.known());
  EXPECT_EQ(soc.basis(), SocBasis::Ocv);
  EXPECT_EQ(soc.permille(), 1000);
  EXPECT_EQ(b.app.pack().soc.permille, 1000);
  EXPECT_EQ(b.app.pack().soc.fullChargeMah, kCapacityMah) << "the pack file's capacity";
  const int64_t start = b.emu.trueChargeMaUs();
  b.cells(3700);
  b.emu.setCurrentMa(-2500);
  b.h.runFor(fw::s(59 * 60));
  const int64_t truth = truePermille(1000, b.emu.trueChargeMaUs() - start);
  const int64_t got = soc.permille();
  std::printf("REPORT soc.%s.one_c_discharge_59min true_permille=%lld soc_permille=%lld remaining_mah=%u\n",
              image, static_cast<long long>(truth), static_cast<long long>(got), soc.remainingMah());
  EXPECT_NEAR(truth, 1000 - 59 * 1000 / 60, 2);  // the emulator counted 1C for 59 minutes
  EXPECT_LE(std::llabs(got - truth), 20) << "within 2 %";
  // Published in the view (CAN PackSummary.StateOfCharge and the StateOfCharge message).
  EXPECT_EQ(b.app.pack().soc.permille, got);
  EXPECT_EQ(b.app.pack().soc.remainingMah, soc.remainingMah());
  EXPECT_EQ(b.app.pack().soc.basis, SocBasis::Ocv);
  const int64_t trueRemainingMah = truth * kCapacityMah / 1000;
  EXPECT_LE(std::llabs(static_cast<int64_t>(soc.remainingMah()) - trueRemainingMah), kCapacityMah * 2 / 100)
      << "remaining charge within 2 % of the capacity";
}

TEST(SocApp, OneCDischargeEndsWithinTwoPercentOnTheBq76952) {
  oneCDischarge<G3507>("bq76952");
}
TEST(SocApp, OneCDischargeEndsWithinTwoPercentOnTheBq76907) {
  oneCDischarge<L1306Bq76907>("bq76907");
}

// Before the first value the view says not available (PackSummary.StateOfCharge 255).
TEST(SocApp, NotAvailableUntilKnown) {
  G3507 b;
  b.emu.setCurrentMa(-2500);  // under load: the open-circuit table is not used
  b.h.runFor(fw::s(2));
  EXPECT_FALSE(b.app.stateOfCharge().known());
  EXPECT_FALSE(b.app.pack().soc.known());
}

// A start value 20 % off (the pack is at 60 %, the value says 80 %), 6 minutes at 1C (true 50 %, the count
// says 70 %), then a rest with the cells at the table's 50 % voltage: after the pack's rest time (600 s) the
// open-circuit voltage corrects the value to within 5 %.
template <class Board>
void restCorrects(const char* image) {
  Board b;
  b.app.stateOfCharge().restore(800);
  b.cells(3700);
  b.emu.setCurrentMa(-2500);
  b.h.runFor(fw::s(6 * 60));
  auto& soc = b.app.stateOfCharge();
  EXPECT_EQ(soc.basis(), SocBasis::Restored);
  EXPECT_NEAR(soc.permille(), 700, 5) << "the count moved the wrong start value";
  b.emu.setCurrentMa(0);
  b.cells(3740);  // the EVM packs' table: 50 %
  b.h.runFor(fw::s(610));
  std::printf("REPORT soc.%s.rest_correction start_error_permille=200 after_rest_permille=%u true=500\n",
              image, soc.permille());
  EXPECT_EQ(soc.basis(), SocBasis::Ocv);
  EXPECT_LE(std::abs(static_cast<int>(soc.permille()) - 500), 50) << "within 5 %";
}

TEST(SocApp, RestCorrectsATwentyPercentErrorOnTheBq76952) {
  restCorrects<G3507>("bq76952");
}
TEST(SocApp, RestCorrectsATwentyPercentErrorOnTheBq76907) {
  restCorrects<L1306Bq76907>("bq76907");
}

}  // namespace
