// The FLASHCTL model (bsp/twin/periph/flashctl.hpp) against TI's description: commands, protection, the
// stall, timing, the misuse rules and the power cut. Registers are driven through the address map as the
// CPU's stores would; the CPU meanwhile runs a counting loop in flash (or in SRAM), so the stall shows.
#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "app/store/record_store.hpp"
#include "chip_rig.hpp"
#include "core/status.hpp"
#include "elf_file.hpp"
#include "flash_file.hpp"
#include "gtest/gtest.h"
#include "mspm0.hpp"

namespace {

using twin::Mspm0;
using twin::Part;

// hw_flashctl.h: FLASHCTL_BASE 0x400CD000 (tsv base rows) and the GEN register offsets.
constexpr uint32_t kFc = 0x400CD000;
constexpr uint32_t kCmdexec = kFc + 0x1100, kCmdtype = kFc + 0x1104, kCmdctl = kFc + 0x1108;
constexpr uint32_t kCmdaddr = kFc + 0x1120, kCmdbyten = kFc + 0x1124, kData0 = kFc + 0x1130;
constexpr uint32_t kData1 = kFc + 0x1134, kWeprotA = kFc + 0x11D0, kWeprotNm = kFc + 0x1210;
constexpr uint32_t kStatcmd = kFc + 0x13D0;
// STATCMD: CMDDONE 0, CMDPASS 1, CMDINPROGRESS 2, FAILWEPROT 4 (hw_flashctl.h).
constexpr uint32_t kDone = 1, kPass = 2, kInProgress = 4, kFailWeProt = 0x10;
constexpr uint32_t kData = 0x7000;  // the data region (bsp/mspm0/linker), sector 28

class Flash : public twin_test::ChipRig {
 protected:
  // The CPU runs ADDS r0, #1; B .-2 (r0 counts the iterations), from flash or from the bottom of SRAM.
  explicit Flash(Part part = Part::G3507, bool fromSram = false,
                 std::array<uint8_t, 4> loop = {0x01, 0x30, 0xFD, 0xE7})
      : ChipRig(part, loop, fromSram) {}
  uint8_t flashAt(uint32_t address) { return chip_.machine().flash()[address]; }
  uint32_t rdFlash32(uint32_t address) {
    return static_cast<uint32_t>(flashAt(address) | flashAt(address + 1) << 8 | flashAt(address + 2) << 16) |
           static_cast<uint32_t>(flashAt(address + 3)) << 24;
  }
  // A one-word program in the order TI's driverlib issues it (hardware ECC on the G3507): the sector
  // unprotected first.
  void program(uint32_t address, uint32_t lo, uint32_t hi, bool unprotect = true) {
    wr(kCmdctl, 0);
    wr(kCmdtype, 0x01);  // PROGRAM, ONEWORD
    wr(kCmdaddr, address);
    wr(kCmdbyten, chip_.part() == Part::G3507 ? 0x1FF : 0xFF);
    wr(kData0, lo);
    wr(kData1, hi);
    if (unprotect) wr(kWeprotA, ~(1U << (address / 1024)));
    wr(kCmdexec, 1);
  }
  void erase(uint32_t address) {
    wr(kCmdctl, 0);
    wr(kCmdtype, 0x42);  // ERASE, SECTOR
    wr(kCmdaddr, address);
    wr(kWeprotA, ~(1U << (address / 1024)));
    wr(kCmdexec, 1);
  }
};

TEST_F(Flash, AWordIsProgrammedAfterTheTypicalTimeAndTheSectorIsProtectedAgain) {
  program(kData + 8, 0x44332211, 0x88776655);
  EXPECT_EQ(rd(kStatcmd), kInProgress);
  runUs(45);
  EXPECT_EQ(flashAt(kData + 8), 0xFF) << "word program takes 50 us typical (data sheet 7.7)";
  runUs(10);
  EXPECT_EQ(rd(kStatcmd), kDone | kPass);
  for (uint32_t i = 0; i < 8; ++i)
    EXPECT_EQ(flashAt(kData + 8 + i), 0x11 * (i + 1));
  EXPECT_EQ(rd(kWeprotA), 0xFFFFFFFFU) << "re-protected after every command (TRM FLASHCTL)";
  EXPECT_FALSE(chip_.machine().stopped()) << why();
}

TEST_F(Flash, ASectorEraseTakesTheTypicalTime) {
  chip_.machine().flash()[kData + 1023] = 0;
  erase(kData);
  runUs(3900);
  EXPECT_EQ(flashAt(kData + 1023), 0);
  runUs(200);
  EXPECT_EQ(flashAt(kData + 1023), 0xFF);
  EXPECT_EQ(rd(kStatcmd), kDone | kPass);
}

TEST_F(Flash, ACommandOnAProtectedSectorFailsWithFailWeProtAndStops) {
  program(kData, 0, 0, false);
  EXPECT_EQ(rd(kStatcmd), kDone | kFailWeProt);
  EXPECT_EQ(flashAt(kData), 0xFF);
  EXPECT_TRUE(chip_.machine().stopped());
  EXPECT_NE(why().find("[FLASH-PROTECTED]"), std::string::npos) << why();
}

TEST_F(Flash, TheUnprotectHoldsForOneCommandOnly) {
  program(kData, 0, 0);
  runUs(60);
  program(kData + 8, 0, 0, false);  // the same sector, no new unprotect
  EXPECT_NE(why().find("[FLASH-PROTECTED]"), std::string::npos) << why();
}

TEST_F(Flash, ProgrammingAWordTwiceWithoutEraseStops) {
  program(kData, 0xFFFFFF00, 0xFFFFFFFF);
  runUs(60);
  program(kData, 0xFFFF0000, 0xFFFFFFFF);  // only 1 -> 0 bits, still refused: the ECC byte would not match
  EXPECT_NE(why().find("[FLASH-UNERASED]"), std::string::npos) << why();
}

TEST_F(Flash, ACommandToNonmainStops) {
  wr(kCmdtype, 0x42);
  wr(kCmdaddr, 0x41C00000);
  wr(kCmdexec, 1);
  EXPECT_NE(why().find("[FLASH-REGION]"), std::string::npos) << why();
}

TEST_F(Flash, UnprotectingNonmainStops) {
  wr(kWeprotNm, 0);
  EXPECT_NE(why().find("[FLASH-REGION]"), std::string::npos) << why();
}

TEST_F(Flash, ACommandToTheImageStops) {
  chip_.flashctl().setImageEnd(0x4000);
  erase(0x3C00);
  EXPECT_NE(why().find("[FLASH-REGION]"), std::string::npos) << why();
}

TEST_F(Flash, FlashCodeStallsWhileTheBankIsBusy) {
  runUs(10);
  const uint32_t before = chip_.machine().core().reg(0);
  program(kData, 1, 2);
  runUs(40);
  EXPECT_EQ(chip_.machine().core().reg(0), before) << "no instruction fetched from flash during the program";
  runUs(20);
  EXPECT_GT(chip_.machine().core().reg(0), before);
}

class FlashSram : public Flash {
 protected:
  FlashSram() : Flash(Part::G3507, true) {}
};

// An interrupt during a program waits for it: the vector and the handler are in flash. The latency figure
// (Machine::interrupts) includes the wait, so a protection latency measured on the twin does too.
TEST_F(FlashSram, AnInterruptDuringAProgramWaitsForItsEnd) {
  // IRQ 5's vector (0x40 + 4 x 5) -> 0x104: B . (the handler spins; only its entry matters here).
  auto& f = chip_.machine().flash();
  f[0x54] = 0x05, f[0x55] = 0x01, f[0x56] = 0, f[0x57] = 0;
  f[0x104] = 0xFE, f[0x105] = 0xE7;
  wr(0xE000E100, 1U << 5);  // NVIC ISER
  runUs(10);
  program(kData, 1, 2);
  runUs(5);
  chip_.machine().setIrq(5, true);
  runUs(100);
  const uint64_t latency = chip_.machine().interrupts()[16 + 5].worstLatencyCycles;
  EXPECT_GE(latency, 44U * 32) << "the program's remaining 45 us";
  EXPECT_LE(latency, 46U * 32);
}

TEST_F(FlashSram, SramCodeRunsWhileTheBankIsBusy) {
  runUs(10);
  const uint32_t before = chip_.machine().core().reg(0);
  program(kData, 1, 2);
  runUs(40);
  EXPECT_GT(chip_.machine().core().reg(0), before + 100);
  EXPECT_EQ(rd(kStatcmd), kInProgress);
}

// SRAM code that reads the flash (here LDR r0, [r1] with r1 = 0 from reset: the vector table) waits too: the
// one bank stalls data reads as well as fetches (SLAU846A NVM chapter, flash banks; SLAAE56A). So a wait loop
// in SRAM that read a literal or a constant from flash would be caught here, not only on the part.
class FlashSramLoads : public Flash {
 protected:
  FlashSramLoads() : Flash(Part::G3507, true, {0x08, 0x68, 0xFD, 0xE7}) {}  // LDR r0, [r1]; B .-2 (r1 = 0)
};

TEST_F(FlashSramLoads, SramCodeThatLoadsFromFlashWaitsForTheProgramToEnd) {
  twin::Machine& m = chip_.machine();
  runUs(10);
  const uint64_t before = m.core().instructions();
  ASSERT_GT(before, 0U);
  program(kData, 1, 2);
  runUs(40);
  EXPECT_LE(m.core().instructions(), before + 1) << "a load from flash completed during the program";
  runUs(20);
  EXPECT_GT(m.core().instructions(), before + 100) << "the loop runs on once the program is done";
  EXPECT_EQ(m.core().reg(0), rdFlash32(0)) << "the load, run again, read the vector table's first word";
  EXPECT_FALSE(m.stopped()) << why();
}

TEST_F(Flash, APowerCutHalfWayLeavesATornWordAndTheFlashSurvivesTheReset) {
  program(kData + 16, 0x00000000, 0x00000000);
  runUs(25);
  chip_.cutPower();
  EXPECT_EQ(flashAt(kData + 16), 0x00);
  EXPECT_EQ(flashAt(kData + 20), 0xF0) << "half programmed: the byte being programmed is torn";
  EXPECT_EQ(flashAt(kData + 23), 0xFF);
  EXPECT_EQ(rd(kStatcmd), 0U);
  EXPECT_EQ(rd(kWeprotA), 0xFFFFFFFFU);
  runUs(100);  // nothing completes the abandoned command later
  EXPECT_EQ(flashAt(kData + 23), 0xFF);
  EXPECT_GT(chip_.machine().core().reg(0), 0U) << "the CPU runs again after the power-on reset";
}

TEST_F(Flash, APowerCutDuringAnEraseLeavesTheSectorPartlyErased) {
  for (uint32_t i = 0; i < 1024; ++i)
    chip_.machine().flash()[kData + i] = 0;
  erase(kData);
  runUs(1000);  // a quarter of 4 ms
  chip_.cutPower();
  EXPECT_EQ(flashAt(kData), 0xFF);
  EXPECT_EQ(flashAt(kData + 1023), 0x00);
  EXPECT_EQ(chip_.flashctl().busy(), twin::Flashctl::Op::None);
}

// bms-sim / twin-bsl --flash (flash_file.hpp): the region in a file across runs.
TEST(FlashFile, AMissingFileIsCreatedErasedAndTheRegionComesBackFromIt) {
  const std::string path = ::testing::TempDir() + "twin_flash_file_test.bin";
  std::remove(path.c_str());
  const twin::FlashRegion region = twin::kLinkerDataRegion;
  std::string error;
  {
    Mspm0 chip(Part::L1306);
    chip.machine().flash()[region.begin] = 0x00;
    ASSERT_TRUE(twin::loadFlashFile(chip.machine(), region, path, error)) << error;
    EXPECT_EQ(chip.machine().flash()[region.begin], 0xFF) << "created erased";
    chip.machine().flash()[region.begin + 5] = 0x5A;
    chip.machine().flash()[region.end - 1] = 0x00;
    ASSERT_TRUE(twin::saveFlashFile(chip.machine(), region, path, error)) << error;
  }
  Mspm0 next(Part::L1306);
  ASSERT_TRUE(twin::loadFlashFile(next.machine(), region, path, error)) << error;
  EXPECT_EQ(next.machine().flash()[region.begin + 5], 0x5A);
  EXPECT_EQ(next.machine().flash()[region.end - 1], 0x00);
  EXPECT_EQ(next.machine().flash()[region.end], 0xFF) << "nothing outside the region";
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "short";
  EXPECT_FALSE(twin::loadFlashFile(next.machine(), region, path, error));
  EXPECT_NE(error.find("5 B, the data region is 4096 B"), std::string::npos) << error;
  std::remove(path.c_str());
}

#ifdef TWIN_PROGRAMS
// The driver itself (bsp/mspm0/flashctl.cpp, programs/flash_driver.cpp) with the product's start-up and
// linker script, on the model: the sequence TI documents works, the SRAM loop is copied and runs, the
// refusals never reach the controller.
class Driver : public ::testing::TestWithParam<Part> {
 protected:
  Driver() : chip_(GetParam()) {
    const std::string chip = GetParam() == Part::G3507 ? "mspm0g3507" : "mspm0l1306";
    EXPECT_TRUE(elf_.load(std::string(TWIN_PROGRAMS) + "/flash_driver_" + chip + ".elf")) << elf_.error();
    EXPECT_TRUE(chip_.load(elf_)) << chip_.error();
  }
  uint32_t word(const char* symbol, uint32_t index = 0) {
    const auto s = elf_.symbol(symbol);
    EXPECT_TRUE(s.has_value()) << symbol;
    return s ? chip_.machine().readSram32(s->value + 4 * index) : 0;
  }
  // Runs until the program sets kDone (at most 100 ms); the time it took, in us.
  uint64_t runToDone() {
    const uint64_t start = chip_.machine().now();
    chip_.machine().run(start +
                        32 * 10);  // past the start-up's zeroing of .bss (SRAM holds a pattern before)
    while (word("kDone") != 1 && !chip_.machine().stopped() && chip_.machine().now() - start < 3200000)
      chip_.machine().run(chip_.machine().now() + 32 * 10);
    return (chip_.machine().now() - start) / 32;
  }
  void expectResults() {
    const uint32_t ok = static_cast<uint32_t>(fw::Status::Ok);
    const uint32_t invalid = static_cast<uint32_t>(fw::Status::InvalidArgument);
    EXPECT_EQ(word("kResults", 0), ok) << "erase";
    EXPECT_EQ(word("kResults", 1), ok) << "program 0";
    EXPECT_EQ(word("kResults", 2), ok) << "program 8";
    EXPECT_EQ(word("kResults", 3), invalid) << "program into a programmed word";
    EXPECT_EQ(word("kResults", 4), invalid) << "unaligned";
    EXPECT_EQ(word("kResults", 5), invalid) << "sector outside the region";
    EXPECT_EQ(word("kResults", 6), invalid) << "offset outside the region";
    EXPECT_EQ(word("kResults", 7), 4U) << "sectors in the region";
    const auto& flash = chip_.machine().flash();
    EXPECT_EQ(flash[0x7000], 0x11);
    EXPECT_EQ(flash[0x7007], 0x88);
    EXPECT_EQ(flash[0x700F], 0x07);
    EXPECT_EQ(flash[0x7010], 0xFF);
  }

  twin::ElfFile elf_;
  Mspm0 chip_;
};

TEST_P(Driver, ErasesProgramsAndRefusesWhatTheContractRefuses) {
  const uint64_t us = runToDone();
  ASSERT_FALSE(chip_.machine().stopped()) << chip_.machine().stopReason();
  expectResults();
  // One erase and two programs at the typical times (4 ms + 2 x 50 us) pass while the core waits.
  EXPECT_GE(us, 4100U);
  EXPECT_EQ(chip_.flashctl().commandsStarted(), 3U) << "the refused requests never reached the controller";
}

TEST_P(Driver, APowerCutInTheFirstProgramLeavesATornWordAndTheRestartRecovers) {
  while (chip_.flashctl().commandsStarted() < 2 && !chip_.machine().stopped())
    chip_.machine().run(chip_.machine().now() + 32);
  ASSERT_EQ(chip_.flashctl().busy(), twin::Flashctl::Op::Program);
  chip_.machine().run(chip_.machine().now() + 25 * 32);
  chip_.cutPower();
  EXPECT_EQ(chip_.machine().flash()[0x7000], 0x11);
  EXPECT_NE(chip_.machine().flash()[0x7007], 0x88) << "the word is torn";
  runToDone();  // the restarted program erases the sector again
  ASSERT_FALSE(chip_.machine().stopped()) << chip_.machine().stopReason();
  expectResults();
}

INSTANTIATE_TEST_SUITE_P(Parts, Driver, ::testing::Values(Part::L1306, Part::G3507));

// The record store (firmware/app/store) on the driver, programs/record_store_cuts.cpp: power is cut after
// every instruction of one record write, and after each cut the restarted store must give, for every type,
// the last record whose write returned Ok or the one being written, never a torn one (the program counts a
// record whose bytes are not the ones written in kBad) and never an older one; then both of the next boot's
// writes must succeed. Two writes are swept: one into a sector with free slots (four records before it), and
// one that finds the sector full (twelve before it) and so compacts the newest of every type into the next
// sector first. The state before the write is made by running the program itself, boot after boot.
class RecordCuts : public ::testing::TestWithParam<Part> {
 protected:
  static constexpr uint32_t kRegion = 0x7000, kRegionEnd = 0x8000;  // the data region (bsp/mspm0/linker)
  static constexpr int kTypes = 3;
  static constexpr uint32_t kMark = 0xC0DE0000;  // kPhase and kSweeping are kMark + n (the program says why)

  RecordCuts() {
    const std::string chip = GetParam() == Part::G3507 ? "mspm0g3507" : "mspm0l1306";
    EXPECT_TRUE(elf_.load(std::string(TWIN_PROGRAMS) + "/record_store_cuts_" + chip + ".elf"))
        << elf_.error();
  }
  // A chip with the program loaded and `region` in the data region, before its first instruction.
  std::unique_ptr<Mspm0> boot(const std::vector<uint8_t>& region) {
    auto chip = std::make_unique<Mspm0>(GetParam());
    EXPECT_TRUE(chip->load(elf_)) << chip->error();
    std::copy(region.begin(), region.end(), chip->machine().flash().begin() + kRegion);
    return chip;
  }
  uint32_t word(Mspm0& chip, const char* symbol, uint32_t index = 0) {
    const auto s = elf_.symbol(symbol);
    EXPECT_TRUE(s.has_value()) << symbol;
    return s ? chip.machine().readSram32(s->value + 4 * index) : 0;
  }
  // Runs until kPhase reaches `phase` (at most 200 ms of the chip's time); false if it did not.
  bool runToPhase(Mspm0& chip, uint32_t phase) {
    twin::Machine& m = chip.machine();
    const uint64_t end = m.now() + 200000ULL * 32;
    auto reached = [&] { return word(chip, "kPhase") - kMark - phase <= 2 - phase; };
    while (!reached() && !m.stopped() && m.now() < end)
      m.run(m.now() + 32 * 20);
    return reached();
  }
  std::vector<uint8_t> regionOf(Mspm0& chip) {
    const auto& flash = chip.machine().flash();
    return {flash.begin() + kRegion, flash.begin() + kRegionEnd};
  }
  // The data region after `boots` boots of the program from an erased region (two records each).
  std::vector<uint8_t> after(int boots) {
    std::vector<uint8_t> region(kRegionEnd - kRegion, 0xFF);
    for (int i = 0; i < boots; ++i) {
      auto chip = boot(region);
      EXPECT_TRUE(runToPhase(*chip, 2)) << chip->machine().stopReason();
      region = regionOf(*chip);
    }
    return region;
  }
  // What a cut after one instruction leaves for the next boot: the data region as the cut leaves it, and
  // which records the program had written (kCommitted) and was writing (kInFlight) at that moment.
  struct CutState {
    std::vector<uint8_t> region;
    std::array<uint32_t, 2 * kTypes> written;
    bool operator<(const CutState& o) const {
      return std::tie(region, written) < std::tie(o.region, o.written);
    }
  };
  // `scratch`: a flash-sized buffer, of which only the data region is used (a cut's effect lies there).
  CutState cutStateOf(Mspm0& chip, std::vector<uint8_t>& scratch) {
    const auto& flash = chip.machine().flash();
    std::copy(flash.begin() + kRegion, flash.begin() + kRegionEnd, scratch.begin() + kRegion);
    chip.flashctl().leaveCut(scratch);
    CutState state{{scratch.begin() + kRegion, scratch.begin() + kRegionEnd}, {}};
    for (int t = 0; t < kTypes; ++t) {
      state.written[t] = chip.machine().readSram32(committed_ + 4 * t);
      state.written[kTypes + t] = chip.machine().readSram32(inFlight_ + 4 * t);
    }
    return state;
  }
  // Boots on what the cut left and checks the restore and the two writes after it; false with a message.
  bool restartsWell(const CutState& cut, std::string& why) {
    auto chip = boot(cut.region);
    twin::Machine& m = chip->machine();
    bool good = runToPhase(*chip, 1) && word(*chip, "kRestore") == static_cast<uint32_t>(fw::Status::Ok) &&
                word(*chip, "kBad") == 0;
    for (int t = 0; t < kTypes && good; ++t) {
      const uint32_t found = word(*chip, "kFound", t);
      good = found == cut.written[t] || (cut.written[kTypes + t] != 0 && found == cut.written[kTypes + t]);
    }
    good = good && runToPhase(*chip, 2) &&
           word(*chip, "kWrites", 0) == static_cast<uint32_t>(fw::Status::Ok) &&
           word(*chip, "kWrites", 1) == static_cast<uint32_t>(fw::Status::Ok);
    if (!good) {
      why = "restore " + std::to_string(word(*chip, "kRestore")) + ", bad " +
            std::to_string(word(*chip, "kBad")) + ", found";
      for (int t = 0; t < kTypes; ++t)
        why += " " + std::to_string(word(*chip, "kFound", t));
      why += ", written";
      for (const uint32_t w : cut.written)
        why += " " + std::to_string(w);
      why += ", writes " + std::to_string(word(*chip, "kWrites", 0)) + " " +
             std::to_string(word(*chip, "kWrites", 1)) + (m.stopped() ? ", stopped: " + m.stopReason() : "");
    }
    return good;
  }
  struct Sweep {
    uint64_t cuts = 0;      // instructions of the write, each one a cut
    uint64_t distinct = 0;  // distinct states those cuts leave, each booted and checked
    uint64_t programs = 0;  // word programs of the write
  };
  // Cuts power after every instruction of the first write of a boot on `before`.
  //
  // After a cut the chip is powered on again (POR: SRAM, the core and every peripheral start afresh) and
  // only the flash is kept, as Flashctl::leaveCut() leaves it; the twin is deterministic, so cuts that leave
  // the same flash (most instructions of a write are the SRAM loop waiting for the controller) restart the
  // same way. The reference run therefore takes the state each instruction's cut would leave, and each
  // distinct state is booted and checked once. That this is what a real cut leaves is checked too: every
  // 499th instruction is also cut for real, from power-on, and must leave the same flash.
  Sweep sweep(const std::vector<uint8_t>& before) {
    Sweep result;
    std::set<CutState> states;
    std::vector<std::pair<uint64_t, std::vector<uint8_t>>> samples;  // cycle, the region a cut leaves
    {
      auto chip = boot(before);
      twin::Machine& m = chip->machine();
      committed_ = elf_.symbol("kCommitted")->value;
      inFlight_ = elf_.symbol("kInFlight")->value;
      const uint32_t sweeping = elf_.symbol("kSweeping")->value;
      std::vector<uint8_t> scratch(m.flash().size());
      while (m.readSram32(sweeping) != kMark + 1 && !m.stopped())
        m.run(m.now() + 1);
      const uint64_t started = chip->flashctl().commandsStarted();
      CutState last;
      while (m.readSram32(sweeping) == kMark + 1 && !m.stopped()) {
        m.run(m.now() + 1);
        CutState state = cutStateOf(*chip, scratch);
        if (result.cuts++ % 499 == 0) samples.emplace_back(m.now(), state.region);
        // Most instructions leave what the one before left: only a change can be a new state.
        if (state.written != last.written || state.region != last.region) {
          last = state;
          states.insert(std::move(state));
        }
      }
      EXPECT_FALSE(m.stopped()) << m.stopReason();
      EXPECT_EQ(word(*chip, "kWrites", 0), static_cast<uint32_t>(fw::Status::Ok));
      result.programs = chip->flashctl().commandsStarted() - started;
    }
    result.distinct = states.size();
    for (const auto& [cycle, region] : samples) {
      auto chip = boot(before);
      chip->machine().run(cycle);
      EXPECT_EQ(chip->machine().now(), cycle) << "the run is not deterministic";
      chip->cutPower();
      EXPECT_TRUE(regionOf(*chip) == region) << "a real cut at cycle " << cycle << " left other flash";
    }
    int failures = 0;
    for (const CutState& state : states) {
      std::string why;
      if (!restartsWell(state, why) && failures++ < 5) ADD_FAILURE() << why;
    }
    EXPECT_EQ(failures, 0) << "of " << states.size() << " states";
    return result;
  }

  twin::ElfFile elf_;
  uint32_t committed_ = 0, inFlight_ = 0;  // the program's kCommitted and kInFlight
};

TEST_P(RecordCuts, EveryInstructionOfARecordWriteLeavesTheLastCompleteRecord) {
  const Sweep s = sweep(after(2));
  EXPECT_LE(s.programs, fw::app::store::RecordStore::kSlotWords) << "a plain write: one slot";
  EXPECT_GT(s.distinct, s.programs * 8) << "every word's torn states";
  std::printf(
      "REPORT twin.record_store_cuts.%s.write: %llu cuts (every instruction), %llu distinct states "
      "booted, %llu word programs\n",
      GetParam() == Part::G3507 ? "g3507" : "l1306", static_cast<unsigned long long>(s.cuts),
      static_cast<unsigned long long>(s.distinct), static_cast<unsigned long long>(s.programs));
}

TEST_P(RecordCuts, EveryInstructionOfACompactingWriteLeavesTheLastCompleteRecord) {
  const Sweep s = sweep(after(6));
  // The newest record of each type copied (the words that are not all 0xFF), then the new one.
  EXPECT_GT(s.programs, fw::app::store::RecordStore::kSlotWords * 2) << "the copies, then the record";
  std::printf(
      "REPORT twin.record_store_cuts.%s.compacting_write: %llu cuts (every instruction), %llu distinct "
      "states booted, %llu word programs\n",
      GetParam() == Part::G3507 ? "g3507" : "l1306", static_cast<unsigned long long>(s.cuts),
      static_cast<unsigned long long>(s.distinct), static_cast<unsigned long long>(s.programs));
}

INSTANTIATE_TEST_SUITE_P(Parts, RecordCuts, ::testing::Values(Part::L1306, Part::G3507));
#endif

}  // namespace
