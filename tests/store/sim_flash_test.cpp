// SimFlash: the hal/flash.hpp contract and the power-cut and failure injection the store tests rely on.
#include "sim/sim_flash.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>

using bsp::host::SimFlash;
using fw::Status;

namespace {
constexpr std::array<uint8_t, 8> kWord = {0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77};
bool erasedAt(const SimFlash& f, uint32_t offset) {
  const auto img = f.read();
  return std::all_of(img.begin() + offset, img.begin() + offset + 8, [](uint8_t b) { return b == 0xFF; });
}
}  // namespace

TEST(SimFlash, StartsErasedAndEnforcesTheContract) {
  SimFlash flash(2);
  EXPECT_EQ(flash.sectorCount(), 2U);
  EXPECT_EQ(flash.size(), 2048U);
  EXPECT_TRUE(std::all_of(flash.read().begin(), flash.read().end(), [](uint8_t b) { return b == 0xFF; }));
  EXPECT_EQ(flash.program(8, kWord), Status::Ok);
  EXPECT_TRUE(std::equal(kWord.begin(), kWord.end(), flash.read().begin() + 8));
  EXPECT_EQ(flash.program(8, kWord), Status::InvalidArgument);     // not erased
  EXPECT_EQ(flash.program(12, kWord), Status::InvalidArgument);    // not word-aligned
  EXPECT_EQ(flash.program(2048, kWord), Status::InvalidArgument);  // outside
  EXPECT_EQ(flash.erase(2), Status::InvalidArgument);
  EXPECT_EQ(flash.erase(0), Status::Ok);
  EXPECT_TRUE(erasedAt(flash, 8));
  EXPECT_EQ(flash.eraseCount(0), 1U);
  EXPECT_EQ(flash.eraseCount(1), 0U);
}

TEST(SimFlash, InjectedFailuresChangeNothing) {
  SimFlash flash(2);
  flash.failNext(Status::Timeout);
  EXPECT_EQ(flash.program(0, kWord), Status::Timeout);
  EXPECT_TRUE(erasedAt(flash, 0));
  EXPECT_EQ(flash.program(0, kWord), Status::Ok);
  flash.failNext(Status::VerifyFailed);
  EXPECT_EQ(flash.erase(0), Status::VerifyFailed);
  EXPECT_FALSE(erasedAt(flash, 0));
}

TEST(SimFlash, ACutProgramTearsTheWordAndStopsEverything) {
  for (auto tear :
       {SimFlash::Tear::Erased, SimFlash::Tear::Partial, SimFlash::Tear::Random, SimFlash::Tear::Complete}) {
    SimFlash flash(2, 7);
    flash.cutAtProgram(1, tear);
    EXPECT_EQ(flash.program(0, kWord), Status::Ok);
    EXPECT_EQ(flash.program(8, kWord), Status::Aborted);
    EXPECT_TRUE(flash.powerLost());
    EXPECT_EQ(flash.program(16, kWord), Status::Aborted);
    EXPECT_EQ(flash.erase(1), Status::Aborted);
    EXPECT_TRUE(erasedAt(flash, 16));
    const auto img = flash.read();
    if (tear == SimFlash::Tear::Erased) {
      EXPECT_TRUE(erasedAt(flash, 8));
    }
    if (tear == SimFlash::Tear::Complete) {
      EXPECT_TRUE(std::equal(kWord.begin(), kWord.end(), img.begin() + 8));
    }
    if (tear == SimFlash::Tear::Partial) {
      for (uint32_t i = 0; i < 8; ++i)  // only bits the word programs to 0 can be 0
        EXPECT_EQ(img[8 + i] & kWord[i], kWord[i]);
    }
    flash.powerOn();
    EXPECT_EQ(flash.program(16, kWord), Status::Ok);
  }
}

TEST(SimFlash, ACutEraseLeavesThePartlyErasedSector) {
  SimFlash flash(2, 3);
  for (uint32_t off = 0; off < 1024; off += 8)
    ASSERT_EQ(flash.program(off, kWord), Status::Ok);
  flash.cutAtErase(0);
  EXPECT_EQ(flash.erase(0), Status::Aborted);
  EXPECT_TRUE(flash.powerLost());
  uint32_t erased = 0, kept = 0;
  for (uint32_t off = 0; off < 1024; off += 8) {
    if (erasedAt(flash, off)) ++erased;
    for (uint32_t i = 0; i < 8; ++i)  // an erase only sets bits
      EXPECT_EQ(flash.read()[off + i] & kWord[i], kWord[i]);
    if (!erasedAt(flash, off)) ++kept;
  }
  EXPECT_GT(erased, 0U);
  EXPECT_GT(kept, 0U);
}

TEST(SimFlash, ImageSavesAndLoads) {
  const std::string path = ::testing::TempDir() + "sim_flash_image.bin";
  SimFlash flash(2);
  ASSERT_EQ(flash.program(1016, kWord), Status::Ok);
  ASSERT_TRUE(flash.save(path));
  SimFlash other(2);
  ASSERT_TRUE(other.load(path));
  EXPECT_TRUE(std::equal(flash.read().begin(), flash.read().end(), other.read().begin()));
  SimFlash wrongSize(3);
  EXPECT_FALSE(wrongSize.load(path));
  EXPECT_FALSE(wrongSize.load(path + ".missing"));
  std::remove(path.c_str());
}
