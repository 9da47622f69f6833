// The firmware images themselves on the twin (build/<preset>/<preset>.elf; skipped when not built, as
// ./ci/test builds them before it tests):
// - the fast paths in CPU-counted time: ALERT (BQ76952) to the FETs off, nFAULT (BQ79616) to the fault
//   output, wherever in the scan period the edge comes, and while the image's own record store erases or
//   programs the flash (every flash read stalls then: the driver's wait acts on the line itself);
// - deliberately broken variants of an image, made here by patching its flash, each caught by the twin: the
//   MCAN interrupt never acknowledged (the MCANSS EOI store taken out), two interrupt vectors swapped, and
//   the watchdog never restarted (the WWDTCNTRST store taken out);
// - what every boot publishes first (the Startup message): the reset cause, the firmware version, and the
//   fault record only where the reset kept SRAM.
// - one broken image per kind of rules.hpp, each stopped with that rule named: a UART at 1.1 Mbaud, SCL at
//   1.6 MHz, CAN at 250 kbit/s, the 40 MHz crystal on the 16..32 MHz range, the UART RX pin without INENA,
//   WFI with interrupts enabled, the scheduler's post() without its critical section, clock stretching
//   switched off, an I2C flush never ended.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/command/e2e.hpp"
#include "board/board.hpp"
#include "can/bms.hpp"
#include "gtest/gtest.h"
#include "image_patch.hpp"
#include "sim/harness.hpp"

namespace {

using twin::Board;
using twin::ElfFile;

std::string elfPath(const std::string& preset) {
  return std::string(TWIN_IMAGES) + "/" + preset + "/" + preset + ".elf";
}

// One board on its own world clock, the pack at rest (3.7 V cells, as bms-sim's idle scenario).
struct Rig {
  explicit Rig(const std::string& preset, const ElfFile& elf)
      : board(*twin::imageByPreset(preset), h.clock, 2) {
    if (auto* e = board.bq769x()) {
      for (uint8_t c = 1; c <= 16; ++c)
        e->setCellMv(c, 3700);
    }
    if (auto* chain = board.chain()) {
      for (size_t d = 0; d < chain->size(); ++d) {
        for (int c = 1; c <= 16; ++c)
          chain->setCellMicrovolts(d, c, 3700000);
      }
    }
    loaded = board.load(elf);
  }
  uint64_t nowUs() { return board.machine().now() / board.machine().cyclesPerUs(); }
  bsp::host::Harness h;
  Board board;
  bool loaded = false;
};

// The warnings of a `us` run of the image, which must not stop (a warning rule names what silicon would only
// degrade).
std::vector<std::string> warningsOf(const std::string& preset, const ElfFile& elf, uint64_t us) {
  Rig r(preset, elf);
  r.board.runUntilUs(us);
  EXPECT_EQ(r.board.machine().stopReason(), "");
  return r.board.warnings();
}

std::unique_ptr<ElfFile> loadElf(const std::string& preset) {
  auto elf = std::make_unique<ElfFile>();
  if (!std::filesystem::exists(elfPath(preset)) || !elf->load(elfPath(preset))) return nullptr;
  return elf;
}

#define LOAD_OR_SKIP(elf, preset)                                                     \
  auto elf = loadElf(preset);                                                         \
  if (!elf) GTEST_SKIP() << elfPath(preset) << " is not built (./ci/test builds it)"; \
  static_assert(true)

// The start (us) of the first scan at or after `fromUs`: its first access on the monitor's bus (I2C images:
// the write of the first scan block's command, `firstRead`).
uint64_t nextScanUs(Rig& r, uint64_t fromUs, const std::string& firstRead) {
  for (uint64_t t = fromUs; t < fromUs + 200000; t += 100) {
    r.board.runUntilUs(t);
    if (r.board.chain() != nullptr) {
      for (const auto& c : r.board.chainCommands()) {
        if (c.reg == 0x568 && c.cycle / 32 >= fromUs) return c.cycle / 32;
      }
    } else {
      for (const auto& tr : r.board.i2cLog()) {
        if (tr.text.rfind(firstRead, 0) == 0 && tr.startCycle / 32 >= fromUs) return tr.startCycle / 32;
      }
    }
  }
  return 0;
}

// Cycles from the monitor's signal falling to the action: the FETs leaving "both on", or the fault output
// rising; on the BQ769x images also to the FET-off command complete (BQ76952: the end of the read that found
// ALL_FETS_OFF echoed in 0x3E/0x3F; BQ76907: the FET Control write; what the protection log records as
// `acted`). Swept on a 50 us grid over the first 3 ms of a scan (where the bus is busy; after it the time is
// flat, and 0 is the scan's first access, as when the signal lands on the scan tick) and the last
// millisecond before the next one (where a scan may start under the action).
void sweepFastPath(const std::string& preset, const char* what) {
  LOAD_OR_SKIP(elf, preset);
  uint64_t worst = 0, worstAt = 0, worstDone = 0, worstDoneAt = 0;
  // The scan's first read: BQ769x2 0x0A (PF Status and the voltages), BQ7690x 0x12 (Battery Status and the
  // voltages): drivers/bq769x2 Variant::blocks.
  // The FET-off command complete: BQ769x2 the read that finds ALL_FETS_OFF echoed in 0x3E/0x3F; BQ7690x the
  // write of FET Control (0x68) with CHG_OFF and DSG_OFF (SLUUCJ0), a direct command with no echo.
  const bool bq7690x = preset.find("bq7690") != std::string::npos;
  const std::string firstRead = bq7690x ? "S 10 12 " : "S 10 0A ";
  const std::string fetsOffDone = bq7690x ? "S 10 68 0C" : "S 10 3E Sr 11 [95 00]";
  std::vector<uint64_t> offsets;
  for (uint64_t us = 0; us < 3000; us += 50)
    offsets.push_back(us);
  for (uint64_t us = 99000; us < 100000; us += 50)
    offsets.push_back(us);
  for (uint64_t offset : offsets) {
    Rig r(preset, *elf);
    ASSERT_TRUE(r.loaded) << r.board.error();
    const uint64_t scan = nextScanUs(r, 1000000, firstRead);
    ASSERT_NE(scan, 0U) << "no scan after 1 s";
    r.board.runUntilUs(scan + offset);
    const uint64_t t0 = r.board.machine().now();
    r.board.driveMonitorSignal(false);
    const bool fets = r.board.bq769x() != nullptr;
    uint64_t acted = 0, done = 0;
    for (uint64_t t = r.nowUs(); t < scan + offset + 20000 && (acted == 0 || (fets && done == 0)); t += 50) {
      r.board.runUntilUs(t);
      const auto& edges = fets ? r.board.fetsOn() : r.board.faultOutput();
      for (const auto& e : edges) {
        const bool off = fets ? !e.level : e.level;
        if (acted == 0 && off && e.cycle >= t0) acted = e.cycle;
      }
      if (!fets) continue;
      for (const auto& tr : r.board.i2cLog()) {
        if (done == 0 && tr.startCycle >= t0 && tr.text.rfind(fetsOffDone, 0) == 0) done = tr.endCycle;
      }
    }
    ASSERT_FALSE(r.board.machine().stopped()) << r.board.machine().stopReason();
    ASSERT_NE(acted, 0U) << what << " never acted, signal at " << offset << " us into the scan";
    const uint64_t took = (acted - t0) / 32;
    EXPECT_LE(took, 2000U) << what << " took " << took << " us with the signal " << offset
                           << " us into the scan";
    if (took > worst) worst = took, worstAt = offset;
    if (!fets) continue;
    ASSERT_NE(done, 0U) << "no FET-off command completed, signal at " << offset << " us into the scan";
    const uint64_t complete = (done - t0) / 32;
    EXPECT_LE(complete, 2000U) << "the FET-off command completed " << complete << " us after the signal, "
                               << offset << " us into the scan";
    if (complete > worstDone) worstDone = complete, worstDoneAt = offset;
  }
  std::printf(
      "REPORT twin.%s.%s_worst_us=%llu (signal %llu us into the scan, 50 us grid; budget 2000; CPU-counted "
      "time)\n",
      preset.c_str(), what, static_cast<unsigned long long>(worst), static_cast<unsigned long long>(worstAt));
  if (worstDone != 0)
    std::printf(
        "REPORT twin.%s.%s_command_complete_worst_us=%llu (signal %llu us into the scan; budget 2000)\n",
        preset.c_str(), what, static_cast<unsigned long long>(worstDone),
        static_cast<unsigned long long>(worstDoneAt));
}

// Every built image names itself (its `.bms_image` section, bsp/mspm0/CMakeLists.txt), and the twin takes
// the part and the monitor from that name: nothing is guessed from symbols or addresses.
TEST(ImageIdentity, EveryBuiltImageNamesItselfAndTheTwinReadsItsPartAndMonitor) {
  int seen = 0;
  if (!std::filesystem::is_directory(TWIN_IMAGES)) GTEST_SKIP() << TWIN_IMAGES << " has no images";
  for (const auto& dir : std::filesystem::directory_iterator(TWIN_IMAGES)) {
    const std::string preset = dir.path().filename().string();
    if (preset.rfind("lp-", 0) != 0 || !std::filesystem::exists(elfPath(preset))) continue;
    ElfFile elf;
    ASSERT_TRUE(elf.load(elfPath(preset))) << elf.error();
    EXPECT_EQ(elf.imageName(), preset);
    std::string error;
    const auto id = twin::identify(elf, error);
    ASSERT_TRUE(id) << error;
    EXPECT_EQ(id->preset, preset);
    EXPECT_EQ(id->part,
              preset.find("mspm0l1306") != std::string::npos ? twin::Part::L1306 : twin::Part::G3507);
    const bool bq769x = id->family == twin::Family::Bq76952 || id->family == twin::Family::Bq76907;
    EXPECT_EQ(bq769x, preset.find("-bq769") != std::string::npos) << preset;
    ++seen;
  }
  if (seen == 0) GTEST_SKIP() << "no image is built (./ci/test builds them)";
}

TEST(ImageIdentity, NamesOfPartsOrMonitorsTheTwinCannotWireAreRefused) {
  EXPECT_TRUE(
      twin::imageByPreset("lp-mspm0g3507-bq76907"));  // a pairing no image has yet: the board wires it
  EXPECT_FALSE(twin::imageByPreset("lp-mspm0c1104-bq76952"));
  EXPECT_FALSE(twin::imageByPreset("lp-mspm0l1306-bq76940"));
  EXPECT_FALSE(twin::imageByPreset("lp-mspm0l1306-bq76952-x"));
}

#ifdef TWIN_PROGRAMS
// An ELF that is not one of the repository's images (here a twin test program) has no name: refused, with
// why.
TEST(ImageIdentity, AnElfWithoutItsNameIsRefused) {
  ElfFile elf;
  ASSERT_TRUE(elf.load(std::string(TWIN_PROGRAMS) + "/sleep_on_exit.elf")) << elf.error();
  EXPECT_EQ(elf.imageName(), "");
  std::string error;
  EXPECT_FALSE(twin::identify(elf, error));
  EXPECT_NE(error.find("no .bms_image section"), std::string::npos) << error;
}
#endif

TEST(FastPath, Bq76952AlertToFetsOffOnTheG3507) {
  sweepFastPath("lp-mspm0g3507-bq76952", "alert_to_fets_off");
}

TEST(FastPath, Bq76952AlertToFetsOffOnTheL1306) {
  sweepFastPath("lp-mspm0l1306-bq76952", "alert_to_fets_off");
}

TEST(FastPath, Bq76907AlertToFetsOffOnTheL1306) {
  sweepFastPath("lp-mspm0l1306-bq76907", "alert_to_fets_off");
}

TEST(FastPath, Bq79616NfaultToFaultOutput) {
  sweepFastPath("lp-mspm0g3507-bq79616", "nfault_to_fault_output");
}

// --- broken images ----------------------------------------------------------------------------------------

// Every instruction address that stores to `address` in the first `us` of a run.
std::vector<uint32_t> storesTo(const std::string& preset, const ElfFile& elf, uint32_t address, uint64_t us) {
  Rig r(preset, elf);
  std::vector<uint32_t> pcs;
  twin::Machine& m = r.board.machine();
  m.map().onStore([&](uint32_t a, uint32_t) {
    if (a == address && std::find(pcs.begin(), pcs.end(), m.core().pc()) == pcs.end())
      pcs.push_back(m.core().pc());
  });
  r.board.runUntilUs(us);
  return pcs;
}

// Replaces each 16-bit store with a NOP (0xBF00): the image without that register write.
void removeStores(ElfFile& elf, const std::vector<uint32_t>& pcs) {
  for (uint32_t pc : pcs) {
    const auto& flash = elf.flashImage();
    const uint16_t op = static_cast<uint16_t>(flash[pc] | flash[pc + 1] << 8);
    const bool store16 = (op >> 11) == 0x0C || (op & 0xFE00) == 0x5000;  // STR imm5 / STR register
    ASSERT_TRUE(store16) << "the store at 0x" << std::hex << pc << " is not a 16-bit STR";
    elf.patch16(pc, 0xBF00);
  }
}

uint64_t packSummariesAfter(const Board& b, uint64_t fromUs) {
  uint64_t n = 0;
  for (const auto& f : b.canFrames()) {
    if (f.frame.id == 0x100 && f.endCycle / 32 > fromUs) ++n;
  }
  return n;
}

TEST(BrokenImage, AnMcanInterruptNeverAcknowledgedIsCaught) {
  // MCANSS_EOI "will clear the associated interrupt" (hw_mcan.h): without it the line's first interrupt is
  // its last. The images send without waiting for TC and notice bus-off by polling PSR, so their frames keep
  // coming; the twin catches the line left waiting.
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto eoi = storesTo(preset, *elf, 0x40508000 + 0x7220, 500000);
  ASSERT_FALSE(eoi.empty()) << "the image never writes MCANSS_EOI";
  const auto clean = warningsOf(preset, *elf, 1000000);
  EXPECT_TRUE(clean.empty()) << clean.front();
  removeStores(*elf, eoi);
  const auto caught = warningsOf(preset, *elf, 1000000);
  ASSERT_EQ(caught.size(), 1U);
  EXPECT_NE(caught[0].find("waiting for MCANSS_EOI"), std::string::npos) << caught[0];
}

TEST(BrokenImage, SwappedVectorsStopThePublishingAndAreNamed) {
  // The I2C driver's handler entered through TIMG0's vector (exception 32) writes the driver's state while
  // Thread code updates it unguarded, with TIMG0's interrupt able to come: the race rule names it. (Before
  // that rule the run went on publishing nothing until the watchdog reset the chip.)
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  // Vector table entries 16 + IRQ (tsv irq rows): TIMG0 is IRQ 16 (0x80), I2C0 IRQ 24 (0xA0).
  const auto& flash = elf->flashImage();
  auto word = [&](uint32_t at) {
    return static_cast<uint32_t>(flash[at] | flash[at + 1] << 8 | flash[at + 2] << 16) |
           static_cast<uint32_t>(flash[at + 3]) << 24;
  };
  const uint32_t timg0 = word(0x80), i2c0 = word(0xA0);
  auto run = [&](const ElfFile& image, uint64_t& summaries, size_t& resets, std::string& stop) {
    Rig r(preset, image);
    r.board.runUntilUs(1500000);  // past the watchdog's 1 s period
    summaries = packSummariesAfter(r.board, 0);
    resets = r.board.machine().resets().size() - 1;
    stop = r.board.machine().stopReason();
  };
  uint64_t good = 0, bad = 0;
  size_t goodResets = 0, badResets = 0;
  std::string goodStop, badStop;
  run(*elf, good, goodResets, goodStop);
  elf->patch32(0x80, i2c0);
  elf->patch32(0xA0, timg0);
  run(*elf, bad, badResets, badStop);
  EXPECT_GE(good, 12U);
  EXPECT_EQ(goodResets, 0U);
  EXPECT_EQ(goodStop, "");
  EXPECT_EQ(bad, 0U) << "the timer interrupt lands in the I2C handler: nothing may come out";
  EXPECT_NE(badStop.find("[RACE-ISR-RMW]"), std::string::npos) << badStop;
  EXPECT_NE(badStop.find("exception 32"), std::string::npos) << badStop;
  EXPECT_NE(badStop.find("I2cController"), std::string::npos) << badStop;
}

TEST(BrokenImage, AWatchdogNeverRestartedResetsTheChip) {
  // Both chips: the L1306 images are supervised by WWDT0 as well (bsp/mspm0/README.md said they were not).
  for (const std::string preset : {"lp-mspm0g3507-bq76952", "lp-mspm0l1306-bq76952"}) {
    SCOPED_TRACE(preset);
    LOAD_OR_SKIP(elf, preset);
    const auto feeds = storesTo(preset, *elf, 0x40080000 + 0x1108, 600000);
    ASSERT_FALSE(feeds.empty()) << "the image never restarts WWDT0";
    removeStores(*elf, feeds);
    Rig r(preset, *elf);
    r.board.runUntilUs(2500000);
    ASSERT_GE(r.board.machine().resets().size(), 2U);
    EXPECT_NE(r.board.machine().resets()[1].find("WWDT0 violation"), std::string::npos)
        << r.board.machine().resets()[1];
  }
}

// --- Startup message (bms.yaml Startup, 0x1F0)
// ---------------------------------------------------------------

// The payloads of the Startup frames the board sent, in order: CAN frames on the G3507 images, SLCAN text
// ("t1F08" and 16 hex digits) on the L1306 ones.
std::vector<std::array<uint8_t, 8>> startupFrames(const Board& b) {
  std::vector<std::array<uint8_t, 8>> out;
  for (const auto& f : b.canFrames()) {
    if (f.frame.id == 0x1F0) out.push_back(f.frame.data);
  }
  for (const auto& line : b.slcanLines()) {
    if (line.text.rfind("t1F08", 0) != 0 || line.text.size() < 5 + 16) continue;
    std::array<uint8_t, 8> d{};
    for (size_t i = 0; i < d.size(); ++i)
      d[i] = static_cast<uint8_t>(std::stoul(line.text.substr(5 + 2 * i, 2), nullptr, 16));
    out.push_back(d);
  }
  return out;
}

// Whether the image builds the record store (FW_RECORD_STORE): it then links the FLASHCTL driver
// (bsp/mspm0/images/common/data_flash.cpp), whose vtable is in the symbol table.
bool hasRecordStore(const ElfFile& elf) {
  return elf.symbol("_ZTVN3bsp5mspm015FlashctlStorageE").has_value();
}
uint16_t faultLine(const std::array<uint8_t, 8>& d) {
  return static_cast<uint16_t>(d[5] | d[6] << 8);
}

TEST(Startup, EveryBootPublishesItsResetCauseAndAWatchdogResetItsFlashRecord) {
  // A WWDT0 violation is a BOOTRST, which resets SRAM (SLAU846B WWDT overview, Table 2-12): the next boot
  // publishes RSTCAUSE 0x0E and the fault record the store wrote for it; the power-on before it published
  // 0x01 and no record.
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto feeds = storesTo(preset, *elf, 0x40080000 + 0x1108, 600000);
  ASSERT_FALSE(feeds.empty());
  removeStores(*elf, feeds);
  Rig r(preset, *elf);
  r.board.runUntilUs(1300000);  // one watchdog period (1 s) and the next boot's first cycle
  ASSERT_EQ(r.board.machine().resets().size(), 2U);
  const auto frames = startupFrames(r.board);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(frames[0][0], 0x01) << "power-on: VDD < POR-";
  EXPECT_EQ(frames[0][1], 0);  // firmware version 0.1.0 (CMake project version)
  EXPECT_EQ(frames[0][2], 1);
  EXPECT_EQ(frames[0][3], 0);
  EXPECT_EQ(frames[0][4], 0xFF) << "no fault record at power-on";
  EXPECT_EQ(faultLine(frames[0]), 0xFFFF);
  EXPECT_EQ(frames[1][0], 0x0E) << "WWDT0 violation";
  // A BOOTRST leaves no SRAM record; the record store (G3507 images) writes the watchdog's own fault record
  // (fw::Module::Bsp, code 0xFFFC) and publishes it as this reset's (FaultSource last_reset).
  EXPECT_EQ(frames[1][4], 30);
  EXPECT_EQ(faultLine(frames[1]), 0xFFFC);
  EXPECT_EQ((frames[1][7] >> 4) & 3, 1);
}

TEST(Startup, AFaultRecordSurvivesTheSoftwareSysrstAndIsPublished) {
  // fw::onFault stores the record in .noinit and issues a software SYSRST, which keeps SRAM (SLAU846B Table
  // 2-12): the next boot publishes RSTCAUSE 0x1B with the record. The fault: the stack guard words
  // overwritten, which the next watchdog feed checks (watchdog.hpp).
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto guard = elf->symbol("__stack_limit__");
  ASSERT_TRUE(guard.has_value());
  Rig r(preset, *elf);
  r.board.runUntilUs(500000);
  ASSERT_EQ(r.board.machine().resets().size(), 1U);
  ASSERT_TRUE(r.board.machine().busWrite(guard->value, 4, 0));
  r.board.runUntilUs(1000000);
  ASSERT_EQ(r.board.machine().resets().size(), 2U);
  EXPECT_NE(r.board.machine().resets()[1].find("software SYSRST"), std::string::npos)
      << r.board.machine().resets()[1];
  const auto frames = startupFrames(r.board);
  ASSERT_EQ(frames.size(), 2U);
  EXPECT_EQ(frames[1][0], 0x1B) << "software SYSRST";
  EXPECT_EQ(frames[1][4], 30) << "fw::Module::Bsp";
  EXPECT_NE(faultLine(frames[1]), 0xFFFF);
}

// --- records kept in flash (app/store/persistence.hpp) on the images that build the store ----------------

// A protection trip, a watchdog reset and a power cycle: every boot after them publishes what the flash kept.
// Cell 1 stands at 4.5 V from power-on (cell_ov trips on the first scans, the BQ76952's own COV with it; the
// BQ4050 image: the gauge reads 100 C, otd trips);
// the watchdog feeds are patched out, so WWDT0 resets the chip after 1 s; 300 ms into the second boot
// power fails and comes back (Mspm0::cutPower: the flash keeps its content, SRAM does not).
void keptAcrossResets(const std::string& preset) {
  SCOPED_TRACE(preset);
  LOAD_OR_SKIP(elf, preset);
  if (!hasRecordStore(*elf)) GTEST_SKIP() << preset << " builds the record store out (FW_RECORD_STORE=0)";
  const auto feeds = storesTo(preset, *elf, 0x40080000 + 0x1108, 600000);
  ASSERT_FALSE(feeds.empty());
  removeStores(*elf, feeds);
  Rig r(preset, *elf);
  ASSERT_TRUE(r.loaded) << r.board.error();
  if (auto* e = r.board.bq769x()) e->setCellMv(1, 4500);
  if (auto* chain = r.board.chain()) chain->setCellMicrovolts(0, 1, 4500000);
  if (auto* gauge = r.board.bq4050()) gauge->setTemperature(3731);  // 100 C: over the discharge limit
  uint64_t t = 0;
  while (r.board.machine().resets().size() < 2 && t < 1500000)
    r.board.runUntilUs(t += 10000);
  ASSERT_EQ(r.board.machine().resets().size(), 2U) << "no watchdog reset";
  r.board.runUntilUs(t += 300000);
  r.board.chip().cutPower();
  r.board.runUntilUs(t += 300000);
  ASSERT_FALSE(r.board.machine().stopped()) << r.board.machine().stopReason();
  ASSERT_EQ(r.board.machine().resets().size(), 3U);
  const auto frames = startupFrames(r.board);
  ASSERT_EQ(frames.size(), 3U);
  auto logEntries = [](const std::array<uint8_t, 8>& d) { return d[7] & 0x0F; };
  auto source = [](const std::array<uint8_t, 8>& d) { return (d[7] >> 4) & 0x03; };
  // Power-on into a blank region: nothing restored, nothing to say.
  EXPECT_EQ(frames[0][0], 0x01);
  EXPECT_EQ(logEntries(frames[0]), 0);
  EXPECT_EQ(source(frames[0]), 0) << "none";
  // After the watchdog: the reset cause, the watchdog's fault record (Bsp, 0xFFFC) now in flash, and the
  // trips of the first boot.
  EXPECT_EQ(frames[1][0], 0x0E) << "WWDT0 violation";
  EXPECT_EQ(frames[1][4], 30) << "fw::Module::Bsp";
  EXPECT_EQ(faultLine(frames[1]), 0xFFFC) << "watchdog expiry";
  EXPECT_EQ(source(frames[1]), 1) << "last_reset";
  EXPECT_GE(logEntries(frames[1]), 1) << "the first boot's trip";
  // After the power cycle: a power-on, SRAM gone; the fault record and the log come from flash alone.
  EXPECT_NE(frames[2][0], 0x0E);
  EXPECT_EQ(frames[2][4], 30);
  EXPECT_EQ(faultLine(frames[2]), 0xFFFC);
  EXPECT_EQ(source(frames[2]), 2) << "stored";
  EXPECT_GE(logEntries(frames[2]), logEntries(frames[1])) << "the trips survive the power cycle";
  std::printf(
      "REPORT twin.%s.kept_records: boot 1 cause 0x%02X log %d; watchdog boot cause 0x%02X log %d "
      "source %d; power-cycled boot cause 0x%02X log %d source %d\n",
      preset.c_str(), frames[0][0], logEntries(frames[0]), frames[1][0], logEntries(frames[1]),
      source(frames[1]), frames[2][0], logEntries(frames[2]), source(frames[2]));
}

TEST(KeptRecords, TripAndWatchdogSurviveResetsOnTheG3507Bq76952) {
  keptAcrossResets("lp-mspm0g3507-bq76952");
}

TEST(KeptRecords, TripAndWatchdogSurviveResetsOnTheG3507Bq79616) {
  keptAcrossResets("lp-mspm0g3507-bq79616");
}

TEST(KeptRecords, TripAndWatchdogSurviveResetsOnTheG3507Bq4050) {
  keptAcrossResets("lp-mspm0g3507-bq4050");
}

// The L1306 images build the store out until it fits their 16 KiB (options.cmake): this runs once an
// L1306-BQ76952 image with FW_RECORD_STORE=1 is in build/ (no ECC on the L1306's flash, data_flash.cpp).
TEST(KeptRecords, TripAndWatchdogSurviveResetsOnTheL1306Bq76952) {
  keptAcrossResets("lp-mspm0l1306-bq76952");
}

// --- the fast path while the store programs or erases the flash (bsp/mspm0/flashctl.hpp, the wait's watch)
// --

// The data region (bsp/mspm0/linker: 4 KiB at 0x7000, sectors 28..31) as a store that must erase at its first
// job (app/store/README.md "Format"): sector 0 active (generation 1) with all 12 slots used (a torn header in
// each: used, never read), sectors 1..3 dirty (one programmed byte each). Once the monitor runs, the settled
// scans erase the dirty sectors one by one (and on BQ76952 the first state-of-charge record compacts into the
// first of them), from the image's own store task.
void prepareStoreThatMustErase(std::vector<uint8_t>& flash) {
  constexpr uint32_t kRegion = 0x7000, kSector = 1024, kSlotBytes = 80;
  const uint8_t header[8] = {1, 0, 0, 0, 0xFE, 0xFF, 0xFF, 0xFF};  // generation 1, its complement
  std::copy(std::begin(header), std::end(header), flash.begin() + kRegion);
  for (uint32_t slot = 0; slot < 12; ++slot)
    flash[kRegion + 8 + slot * kSlotBytes] = 0;
  for (uint32_t sector = 1; sector < 4; ++sector)
    flash[kRegion + sector * kSector] = 0;
}

struct FlashOp {
  uint64_t startCycle;  // a cycle into the CMDEXEC store: running to it executes the store
  bool erase;           // else a word program
};

// The image on the prepared store, with a SettingWrite (cell_uv_trip 2750 mV, for every node) at
// `settingAtUs`, so its Settings record is programmed at the next settled scan.
struct FlashWorkRig : Rig {
  FlashWorkRig(const std::string& preset, const ElfFile& elf, uint64_t settingAtUs)
      : Rig(preset, elf), settingAtUs_(settingAtUs) {
    prepareStoreThatMustErase(board.machine().flash());
  }
  // Runs to `us` (world time), the SettingWrite sent on the way.
  void runUntilUs(uint64_t us) {
    if (!sent_ && us >= settingAtUs_) {
      board.runUntilUs(settingAtUs_);
      fw::can::bms::SettingWrite w{};
      w.target = 255, w.setting = 2, w.value = 2750;
      fw::hal::CanFrame f = w.pack();
      f.data[0] = fw::app::command::frameCrc(f.id, f.data.data(), f.dlc);
      board.sendCan(f);
      sent_ = true;
    }
    board.runUntilUs(us);
  }
  // The same to a CPU cycle (before the setting's time).
  void runUntilCycle(uint64_t cycle) {
    runUntilUs(cycle / board.machine().cyclesPerUs());
    board.machine().run(cycle);
  }

 private:
  uint64_t settingAtUs_;
  bool sent_ = false;
};

// Every program and erase the image starts (its CMDEXEC writes: FLASHCTL_BASE 0x400CD000 + 0x1100, CMDTYPE
// at + 0x1104, hw_flashctl.h) in the first `us`.
std::vector<FlashOp> flashOps(const std::string& preset, const ElfFile& elf, uint64_t settingAtUs,
                              uint64_t us) {
  std::vector<FlashOp> ops;
  FlashWorkRig r(preset, elf, settingAtUs);
  twin::Machine& m = r.board.machine();
  m.map().onStore([&ops, &m](uint32_t a, uint32_t) {
    uint32_t type = 0;
    if (a == 0x400CE100 && m.map().load(0x400CE104, 4, type)) ops.push_back({m.now() + 1, type == 0x42});
  });
  r.runUntilUs(us);
  EXPECT_FALSE(m.stopped()) << m.stopReason();
  return ops;
}

// The fast path's action (FETs leaving "both on"; the fault output rising) at or after `from`, 0 if none.
uint64_t actedAt(Board& b, uint64_t from) {
  const bool fets = b.bq769x() != nullptr;
  for (const auto& e : fets ? b.fetsOn() : b.faultOutput()) {
    if (e.cycle >= from && (fets ? !e.level : e.level)) return e.cycle;
  }
  return 0;
}

// ALERT (BQ76952) / nFAULT (BQ79616) falling at each onset of a grid over a whole sector erase, a whole word
// program and a whole record write (its programs and the CPU's work between them) that the image's store
// starts itself, to the pins acting: within the fast path's budget
// (2 ms), as without flash work. Before the driver's wait watched the line, the action waited for the end of
// the operation (a sector erase: 4 ms typical on the twin, data sheet 7.7), the vector and the handler being
// in flash. Then protection, run by the edge interrupt after the operation, has the pins: the monitor reports
// no fault of its own, so the next scan releases them (within the 20 ms observed).
void sweepDuringFlashWork(const std::string& preset, const char* what) {
  SCOPED_TRACE(preset);
  LOAD_OR_SKIP(elf, preset);
  if (!hasRecordStore(*elf)) GTEST_SKIP() << preset << " builds the record store out";
  constexpr uint64_t kSettingAtUs = 600000;
  const auto ops = flashOps(preset, *elf, kSettingAtUs, 1000000);
  // The last erase before the setting (the monitor has run for a while) and the first program after it.
  const FlashOp* erase = nullptr;
  const FlashOp* program = nullptr;
  uint64_t writeEnd = 0;  // the end of the record write's last program (its programs follow within 1 ms)
  for (const auto& op : ops) {
    if (op.erase && op.startCycle < kSettingAtUs * 32) erase = &op;
    if (!op.erase && program == nullptr && op.startCycle >= kSettingAtUs * 32) program = &op;
    if (!op.erase && program != nullptr && (writeEnd == 0 || op.startCycle < writeEnd + 32000))
      writeEnd = op.startCycle + twin::Flashctl::kProgramUs * 32;
  }
  ASSERT_NE(erase, nullptr) << "no sector erase before " << kSettingAtUs << " us";
  ASSERT_NE(program, nullptr) << "no word program after the SettingWrite";
  struct Sweep {
    uint64_t startCycle, lengthUs, gridUs;
    const char* name;
    bool busy;  // every onset lies in the operation (else also in the CPU's work between programs)
  };
  const uint64_t writeUs = (writeEnd - program->startCycle) / 32;
  for (const Sweep& s : {Sweep{erase->startCycle, twin::Flashctl::kEraseUs, 250, "erase", true},
                         Sweep{program->startCycle, twin::Flashctl::kProgramUs, 5, "program", true},
                         Sweep{program->startCycle, writeUs, 25, "record_write", false}}) {
    uint64_t worst = 0, worstAt = 0;
    int onsets = 0;
    for (uint64_t offset = 0; offset < s.lengthUs; offset += s.gridUs) {
      FlashWorkRig r(preset, *elf, kSettingAtUs);
      ASSERT_TRUE(r.loaded) << r.board.error();
      twin::Machine& m = r.board.machine();
      const uint64_t t0 = s.startCycle + offset * 32;
      r.runUntilCycle(t0);
      if (s.busy) {
        ASSERT_NE(r.board.chip().flashctl().busy(), twin::Flashctl::Op::None)
            << s.name << " not in progress " << offset << " us after its start";
      }
      r.board.driveMonitorSignal(false);
      uint64_t acted = 0;
      for (uint64_t u = r.nowUs() + 50; u < t0 / 32 + 20000; u += 50) {
        r.runUntilUs(u);
        if (acted == 0) acted = actedAt(r.board, t0);
      }
      ASSERT_FALSE(m.stopped()) << m.stopReason();
      ASSERT_NE(acted, 0U) << what << " never acted, signal " << offset << " us into the " << s.name;
      const uint64_t took = (acted - t0) / 32;
      EXPECT_LE(took, 2000U) << what << " took " << took << " us, signal " << offset << " us into the "
                             << s.name;
      // The monitor reports no fault of its own (the line was driven by the test): the scan after the
      // signal releases the paths. Only protection does that, and only if it opened them itself: had the
      // watch driven the pins while protection did not take the line as a fault, they would stay off.
      const bool fets = r.board.bq769x() != nullptr;
      uint64_t released = 0;
      for (const auto& e : fets ? r.board.fetsOn() : r.board.faultOutput()) {
        if (released == 0 && e.cycle > acted && (fets ? e.level : !e.level)) released = e.cycle;
      }
      EXPECT_NE(released, 0U) << "the paths were not released within 20 ms of the signal " << offset
                              << " us into the " << s.name;
      if (took > worst) worst = took, worstAt = offset;
      ++onsets;
    }
    std::printf(
        "REPORT twin.%s.%s_during_%s_worst_us=%llu (signal %llu us into a %llu us %s the image's store "
        "started, %d onsets on a %llu us grid; budget 2000; CPU-counted time)\n",
        preset.c_str(), what, s.name, static_cast<unsigned long long>(worst),
        static_cast<unsigned long long>(worstAt), static_cast<unsigned long long>(s.lengthUs), s.name, onsets,
        static_cast<unsigned long long>(s.gridUs));
  }
}

TEST(FastPath, Bq76952AlertToFetsOffWhileTheStoreErasesAndPrograms) {
  sweepDuringFlashWork("lp-mspm0g3507-bq76952", "alert_to_fets_off");
}

TEST(FastPath, Bq79616NfaultToFaultOutputWhileTheStoreErasesAndPrograms) {
  sweepDuringFlashWork("lp-mspm0g3507-bq79616", "nfault_to_fault_output");
}

TEST(Startup, TheL1306SendsItFirstAsSlcanText) {
  // The SLCAN images send the same frame as text, once: "t1F08" and the payload; power-on cause 0x01,
  // version 0.1.0, no record.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  Rig r(preset, *elf);
  r.board.runUntilUs(300000);
  std::vector<std::string> startup;
  for (const auto& line : r.board.slcanLines()) {
    if (line.text.rfind("t1F0", 0) == 0) startup.push_back(line.text);
  }
  ASSERT_EQ(startup.size(), 1U);
  // Byte 7: ProtectionLogEntries and FaultSource; 0x3F not available where the image builds the store out
  // (FW_RECORD_STORE=0, the L1306 images for now), 0x00 (no entries, no fault) with the store, blank flash.
  EXPECT_EQ(startup[0], hasRecordStore(*elf) ? "t1F0801000100FFFFFF00\r" : "t1F0801000100FFFFFF3F\r");
}

// --- broken images, one per kind of rules.hpp --------------------------------------------------------------

using StoreSite = twinpatch::Store;

// Every store to `address` in the first `us` of a run: the instruction, LR then, the value.
std::vector<StoreSite> storeSites(const std::string& preset, const ElfFile& elf, uint32_t address,
                                  uint64_t us) {
  Rig r(preset, elf);
  std::vector<StoreSite> sites;
  twin::Machine& m = r.board.machine();
  m.map().onStore([&](uint32_t a, uint32_t v) {
    if (a != address) return;
    for (const auto& s : sites) {
      if (s.pc == m.core().pc() && s.value == v) return;
    }
    StoreSite site;
    site.pc = m.core().pc(), site.lr = m.core().reg(14), site.value = v;
    for (int i = 0; i < 8; ++i)
      site.regs[i] = m.core().reg(i);
    sites.push_back(site);
  });
  r.board.runUntilUs(us);
  return sites;
}

// The image with the store at `site` writing `value` instead (image_patch.hpp).
::testing::AssertionResult storeValue(ElfFile& elf, const StoreSite& site, uint32_t value) {
  std::string why;
  if (twinpatch::setStoredValue(elf, site, value, why)) return ::testing::AssertionSuccess();
  char pc[16];
  std::snprintf(pc, sizeof pc, "0x%X", site.pc);
  return ::testing::AssertionFailure() << "the store at " << pc << ": " << why;
}

// Runs the image `us` and returns why the twin stopped ("" if it did not).
std::string stopOf(const std::string& preset, const ElfFile& elf, uint64_t us,
                   const std::function<void(Board&)>& setup = {}) {
  Rig r(preset, elf);
  if (setup) setup(r.board);
  r.board.runUntilUs(us);
  return r.board.machine().stopReason();
}

#define EXPECT_RULE(stop, rule) EXPECT_NE((stop).find("[" rule "]"), std::string::npos) << (stop)

// The first store of `value` to `address`.
StoreSite siteOf(const std::vector<StoreSite>& sites, uint32_t value) {
  for (const auto& s : sites) {
    if (s.value == value) return s;
  }
  return {};
}

TEST(BrokenImage, AUartAt1Point1MbaudIsStoppedByTheWireRule) {
  // IBRD 1 + FBRD 52/64 at 16x from 32 MHz: 1 103 448 Bd against the BQ79616's 1 Mbps (+-1 %).
  const std::string preset = "lp-mspm0g3507-bq79616";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_EQ(stopOf(preset, *elf, 300000), "");
  const auto ibrd = storeSites(preset, *elf, 0x40108000 + 0x1110, 50000);
  const auto fbrd = storeSites(preset, *elf, 0x40108000 + 0x1114, 50000);
  ASSERT_EQ(ibrd.size(), 1U);
  ASSERT_EQ(fbrd.size(), 1U);
  ASSERT_TRUE(storeValue(*elf, ibrd[0], 1));
  ASSERT_TRUE(storeValue(*elf, fbrd[0], 52));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "WIRE-UART-BAUD");
  EXPECT_NE(stop.find("1103448 Bd"), std::string::npos) << stop;
  EXPECT_NE(stop.find("BQ79616"), std::string::npos) << stop;
}

TEST(BrokenImage, AnSclFourTimesTheBq76952MaximumIsStoppedByTheWireRule) {
  // MTPR.TPR 1 instead of 7: (1 + 1) x 10 clocks of 32 MHz, 1.6 MHz against the BQ76952's 400 kHz.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_EQ(stopOf(preset, *elf, 300000), "");
  const auto mtpr = storeSites(preset, *elf, 0x400F0000 + 0x1224, 50000);
  ASSERT_FALSE(mtpr.empty());
  ASSERT_EQ(mtpr[0].value, 7U);
  ASSERT_TRUE(storeValue(*elf, mtpr[0], 1));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "WIRE-I2C-SCL");
  EXPECT_NE(stop.find("SCL 1600000 Hz"), std::string::npos) << stop;
}

TEST(BrokenImage, ACanBitRateOfHalfTheBusIsStoppedByTheWireRule) {
  // NBTP.NBRP 1 instead of 0: 250 kbit/s on the 500 kbit/s bus.
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_EQ(stopOf(preset, *elf, 300000), "");
  const auto nbtp = storeSites(preset, *elf, 0x40508000 + 0x701C, 50000);
  ASSERT_EQ(nbtp.size(), 1U);
  ASSERT_TRUE(storeValue(*elf, nbtp[0], nbtp[0].value | (1U << 16)));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "WIRE-CAN-BITRATE");
  EXPECT_NE(stop.find("250000 bit/s"), std::string::npos) << stop;
}

TEST(BrokenImage, TheCrystalOnTheWrongRangeIsStoppedByTheWireRule) {
  // HFCLKCLKCFG.HFXTRSEL 2 (16..32 MHz) for the LaunchPad's 40 MHz crystal.
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto cfg = storeSites(preset, *elf, 0x400AF000 + 0x1110, 50000);
  const StoreSite first = siteOf(cfg, 0x300A);
  ASSERT_NE(first.pc, 0U) << "no HFCLKCLKCFG write of 0x300A (range 3, HFXTTIME 10)";
  ASSERT_TRUE(storeValue(*elf, first, 0x200A));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "WIRE-HFXT-RANGE");
}

TEST(BrokenImage, AUartRxPinWithoutInputEnableIsStoppedByThePinRule) {
  // PINCM22 (PA11, UART0 RX) written with the pull-up but without INENA: silicon receives nothing.
  const std::string preset = "lp-mspm0g3507-bq79616";
  LOAD_OR_SKIP(elf, preset);
  const auto rx = storeSites(preset, *elf, 0x40428000 + 4 * 22, 50000);
  ASSERT_FALSE(rx.empty());
  ASSERT_NE(rx[0].value & 0x40000U, 0U) << "the image sets INENA on PA11";
  ASSERT_TRUE(storeValue(*elf, rx[0], rx[0].value & ~0x40000U));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "PIN-INENA");
  EXPECT_NE(stop.find("UART0 RX on PA11"), std::string::npos) << stop;
}

TEST(BrokenImage, AnSlcanRxPinWithoutInputEnableIsStoppedByThePinRuleOnTheL1306) {
  // PINCM10 (PA9, UART0 RX from the XDS110 on the LP-MSPM0L1306) without INENA: silicon receives no SLCAN
  // command. The PC's text arrives after bring-up; the board delivered it without asking the pin before.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  auto stopWithCommand = [&](const ElfFile& image) {
    Rig r(preset, image);
    r.board.runUntilUs(100000);
    EXPECT_TRUE(r.board.sendSerial("V\r"));
    r.board.runUntilUs(300000);
    return r.board.machine().stopReason();
  };
  EXPECT_EQ(stopWithCommand(*elf), "");
  const auto rx = storeSites(preset, *elf, 0x40428000 + 4 * 10, 50000);
  ASSERT_FALSE(rx.empty());
  ASSERT_NE(rx[0].value & 0x40000U, 0U) << "the image sets INENA on PA9";
  ASSERT_TRUE(storeValue(*elf, rx[0], rx[0].value & ~0x40000U));
  const std::string stop = stopWithCommand(*elf);
  EXPECT_RULE(stop, "PIN-INENA");
  EXPECT_NE(stop.find("UART0 RX on PA9"), std::string::npos) << stop;
}

// The address of the first `op` in the function whose name contains `function`, or 0.
uint32_t findInstruction(const ElfFile& elf, const std::string& function, uint16_t op) {
  for (const auto& s : elf.symbols()) {
    if (!s.function || elf.symbolAt(s.value & ~1U).find(function) == std::string::npos) continue;
    for (uint32_t at = s.value & ~1U; at < (s.value & ~1U) + s.size; at += 2) {
      if (twinpatch::half(elf, at) == op) return at;
    }
  }
  return 0;
}

// The target of the 32-bit Thumb BL at `at` (ARMv6-M ARM DDI 0419E A6.7.13), 0 if it is none.
uint32_t blTarget(const ElfFile& elf, uint32_t at) {
  const uint32_t first = twinpatch::half(elf, at), second = twinpatch::half(elf, at + 2);
  if ((first & 0xF800U) != 0xF000U || (second & 0xD000U) != 0xD000U) return 0;
  const uint32_t s = (first >> 10) & 1U, j1 = (second >> 13) & 1U, j2 = (second >> 11) & 1U;
  const uint32_t i1 = 1U - (j1 ^ s), i2 = 1U - (j2 ^ s);
  uint32_t offset = (s << 24) | (i1 << 23) | (i2 << 22) | ((first & 0x3FFU) << 12) | ((second & 0x7FFU) << 1);
  if (s != 0) offset |= 0xFE000000U;
  return at + 4 + offset;
}

// Takes the masking out of the critical section in `function` only: its CPSID when the compiler put the
// CriticalSection inline, else its call of the out-of-line constructor (MRS r3, PRIMASK; CPSID i;
// STR r3, [r0]) becomes MOVS r3, #0; STR r3, [r0]: the section then saves "interrupts enabled" and masks
// nothing, and its destructor restores that.
bool removeCriticalSection(ElfFile& elf, const std::string& function) {
  if (const uint32_t cpsid = findInstruction(elf, function, 0xB672)) return elf.patch16(cpsid, 0xBF00);
  for (const auto& s : elf.symbols()) {
    if (!s.function || elf.symbolAt(s.value & ~1U).find(function) == std::string::npos) continue;
    for (uint32_t at = s.value & ~1U; at + 4 <= (s.value & ~1U) + s.size; at += 2) {
      const uint32_t target = blTarget(elf, at);
      if (target == 0 || elf.symbolAt(target).find("CriticalSection::CriticalSection") == std::string::npos)
        continue;
      return elf.patch16(at, 0x2300) && elf.patch16(at + 2, 0x6003);
    }
  }
  return false;
}

TEST(BrokenImage, WfiWithInterruptsEnabledIsStoppedByTheIdleRule) {
  // The CPSID before the scheduler's WFI taken out.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  // The scheduler's WFI: the first with a CPSID before it in the same function (how far before is the
  // compiler's choice; the power policy's own WFI runs inside the scheduler's masked section, in another
  // function, and may come first in the image now that the loop is inlined into main).
  uint32_t cpsid = 0;
  for (uint32_t wfi = 0; wfi + 2 <= elf->flashImage().size() && cpsid == 0; wfi += 2) {
    if (twinpatch::half(*elf, wfi) != 0xBF30) continue;
    const std::string function = elf->symbolAt(wfi);
    for (uint32_t at = wfi; at >= 2 && elf->symbolAt(at) == function && cpsid == 0; at -= 2) {
      if (twinpatch::half(*elf, at) == 0xB672) cpsid = at;
    }
  }
  ASSERT_NE(cpsid, 0U) << "no CPSID before a WFI";
  elf->patch16(cpsid, 0xBF00);
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "IDLE-WFI");
}

TEST(BrokenImage, ThePostWithoutItsCriticalSectionIsStoppedByTheRaceRule) {
  // fw::sched::Scheduler::post() updates the pending events and the ready set with PRIMASK set; interrupt
  // handlers post too (the I2C driver's completion). Its masking taken out, a Thread post (a timer's) is an
  // unguarded update of the ready set while the I2C interrupt can come. (The scheduler lives in main()'s
  // frame: the rule watches the stack as well as .data and .bss.)
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_EQ(stopOf(preset, *elf, 1000000), "");
  ASSERT_TRUE(removeCriticalSection(*elf, "fw::sched::Scheduler::post("));
  const std::string stop = stopOf(preset, *elf, 1000000);
  EXPECT_RULE(stop, "RACE-ISR-RMW");
  EXPECT_NE(stop.find("Scheduler::post"), std::string::npos) << stop;
}

TEST(BrokenImage, AUartThatLeavesEotEnabledAfterItsLastByteIsStoppedByTheRaceRule) {
  // The SLCAN UART masks its transmit interrupts (IMASK = the receive ones) before it clears its busy flag,
  // and write() tests and sets that flag in Thread mode while only reception can interrupt: no race, and the
  // image runs clean. Without that IMASK write, EOT stays enabled, so the handler's flag-clearing path can
  // preempt the test-and-set: the rule must stop the run there.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_EQ(stopOf(preset, *elf, 1000000), "");
  const auto imask = storeSites(preset, *elf, 0x40108000 + 0x1028, 300000);
  std::vector<uint32_t> finishMask;
  uint32_t receiveOnly = 0;
  for (const auto& s : imask) {
    if (elf->symbolAt(s.pc).find("UartSerial::doWrite") != std::string::npos) continue;
    if (elf->symbolAt(s.pc).find("IRQHandler") == std::string::npos &&
        elf->symbolAt(s.pc).find("UartSerial::finish") == std::string::npos)
      receiveOnly = s.value;  // init(): the receive interrupts alone
  }
  ASSERT_NE(receiveOnly, 0U);
  for (const auto& s : imask) {
    const std::string where = elf->symbolAt(s.pc);
    if (s.value == receiveOnly && (where.find("IRQHandler") != std::string::npos ||
                                   where.find("UartSerial::finish") != std::string::npos))
      finishMask.push_back(s.pc);
  }
  ASSERT_FALSE(finishMask.empty()) << "no IMASK write back to the receive interrupts in the handler";
  removeStores(*elf, finishMask);
  const std::string stop = stopOf(preset, *elf, 1000000);
  EXPECT_RULE(stop, "RACE-ISR-RMW");
  EXPECT_NE(stop.find("UartSerial::doWrite"), std::string::npos) << stop;
}

TEST(BrokenImage, ClockStretchingSwitchedOffIsStoppedWhenTheDeviceStretches) {
  // MCR = ACTIVE without CLKSTRETCH. The BQ76952 may stretch SCL (SLUUBY2B 9): the first transaction to it
  // is stopped, whether or not it stretches in this run; stretching 5 us on every byte, the same.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  auto stretching = [](Board& b) { b.setI2cStretch(fw::us(5)); };
  EXPECT_EQ(stopOf(preset, *elf, 300000, stretching), "");
  const auto mcr = storeSites(preset, *elf, 0x400F0000 + 0x1228, 50000);
  const StoreSite active = siteOf(mcr, 5);
  ASSERT_NE(active.pc, 0U);
  ASSERT_TRUE(storeValue(*elf, active, 1));
  const std::string quiet = stopOf(preset, *elf, 300000);
  EXPECT_RULE(quiet, "I2C-CLKSTRETCH");
  EXPECT_NE(quiet.find("the BQ76952 may stretch SCL"), std::string::npos) << quiet;
  const std::string stop = stopOf(preset, *elf, 300000, stretching);
  EXPECT_RULE(stop, "I2C-CLKSTRETCH");
}

TEST(BrokenImage, AnI2cClockLowTimeoutLeftOffIsNamedOnTheFirstTransaction) {
  // The TIMEOUT_CTL write (TCLKAEN | count) taken out: timeout A stays off, so a BQ76952 holding SCL low
  // (it may stretch, SLUUBY2B 9) would hang the controller without a bound (SLAU846B 20.2 / SLAU847D 21.2
  // clock low timeout). The image runs on, so the twin warns (mutant i2c-timeout-disabled).
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto clean = warningsOf(preset, *elf, 300000);
  EXPECT_TRUE(clean.empty()) << clean.front();
  const auto timeoutCtl = storesTo(preset, *elf, 0x400F0000 + 0x1204, 50000);
  ASSERT_EQ(timeoutCtl.size(), 1U);
  removeStores(*elf, timeoutCtl);
  const auto caught = warningsOf(preset, *elf, 300000);
  ASSERT_FALSE(caught.empty());
  for (const auto& w : caught)  // one per addressing site (the PC differs), each this rule
    EXPECT_NE(w.find("[I2C-NO-TIMEOUT] I2C0: addressing the BQ76952 with the clock-low timeout A off"),
              std::string::npos)
        << w;
}

TEST(BrokenImage, ATimerPrescaledBy33IsStoppedByTheTickRule) {
  // CPS.PCNT 32 instead of 31 (reg::timg::prescalerFor1MHz off by one): the firmware's microsecond clock
  // would run at 32 MHz / 33 = 969 697 Hz, every period and timeout 3 % long. The image passes the prescaler
  // to a function, so the broken setting is made after bring-up through the bus, as a debugger would: the
  // counter stopped, CPS written, the counter enabled again (with 31 again, the same steps run clean).
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  uint32_t timg = 0;
  for (uint32_t base : {0x40084000U, 0x40086000U, 0x40088000U, 0x4008C000U}) {
    for (const auto& s : storeSites(preset, *elf, base + 0x110C, 50000)) {
      if (timg == 0 && s.value == 31) timg = base;
    }
  }
  ASSERT_NE(timg, 0U) << "no CPS write of 31 (1 MHz from 32 MHz)";
  auto restart = [&](uint32_t pcnt) {
    Rig r(preset, *elf);
    r.board.runUntilUs(100000);
    twin::AddressMap& map = r.board.machine().map();
    uint32_t ctrctl = 0;
    EXPECT_TRUE(map.load(timg + 0x1804, 4, ctrctl));
    EXPECT_NE(ctrctl & 1U, 0U) << "the counter runs";
    EXPECT_TRUE(map.store(timg + 0x1804, 4, ctrctl & ~1U));
    EXPECT_TRUE(map.store(timg + 0x110C, 4, pcnt));
    EXPECT_TRUE(map.store(timg + 0x1804, 4, ctrctl | 1U));
    r.board.runUntilUs(101000);
    return r.board.machine().stopped() ? r.board.machine().stopReason() : std::string();
  };
  EXPECT_EQ(restart(31).find("[TIMER-TICK]"), std::string::npos);
  const std::string stop = restart(32);
  EXPECT_RULE(stop, "TIMER-TICK");
  EXPECT_NE(stop.find("969696 Hz"), std::string::npos) << stop;
}

TEST(BrokenImage, AnI2cFlushNeverEndedIsStoppedByTheFlushRule) {
  // The driver's flush sets TXFLUSH and RXFLUSH, polls MFIFOSR, then clears them; the clearing store taken
  // out, the flush goes on and the next byte written is lost.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto ctl = storeSites(preset, *elf, 0x400F0000 + 0x1238, 50000);
  std::vector<uint32_t> clears;
  bool afterFlush = false;
  for (const auto& s : ctl) {
    if (s.value & 0x8080U) {
      afterFlush = true;
    } else if (afterFlush) {
      clears.push_back(s.pc);
      afterFlush = false;
    }
  }
  ASSERT_FALSE(clears.empty()) << "no store ends a flush";
  removeStores(*elf, clears);
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "I2C-FLUSH");
}

TEST(BrokenImage, SevenDataBitsOnTheBq79616LinkAreStoppedByTheFrameRule) {
  // LCRH 0x20 (WLEN 7 bits) instead of 0x30 (8N1): the BQ79616 frames 8 data bits (SLUSE81E DEV_CONF; TI's
  // BQ79616 example configures the MSPM0 8N1), so every byte is misread on both sides.
  const std::string preset = "lp-mspm0g3507-bq79616";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_EQ(stopOf(preset, *elf, 300000), "");
  const auto lcrh = storeSites(preset, *elf, 0x40108000 + 0x1104, 50000);
  const StoreSite site = siteOf(lcrh, 0x30);
  ASSERT_NE(site.pc, 0U) << "no LCRH write of 0x30 (8N1)";
  ASSERT_TRUE(storeValue(*elf, site, 0x20));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "WIRE-UART-FRAME");
  EXPECT_NE(stop.find("7 data bits"), std::string::npos) << stop;
  EXPECT_NE(stop.find("BQ79616"), std::string::npos) << stop;
}

TEST(BrokenImage, TheFclWrittenWithoutItsKeyIsNamedByTheKeyRule) {
  // SYSOSCFCLCTL without KEY 0x2A: the part ignores the write (hw_sysctl SYSOSCFCLCTL.KEY), SYSOSC stays
  // without its frequency correction loop; the image would run on, so the twin warns.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto clean = warningsOf(preset, *elf, 300000);
  EXPECT_TRUE(clean.empty()) << clean.front();
  const auto fcl = storeSites(preset, *elf, 0x400AF000 + 0x1310, 50000);
  ASSERT_EQ(fcl.size(), 1U);
  ASSERT_EQ(fcl[0].value >> 24, 0x2AU);
  ASSERT_TRUE(storeValue(*elf, fcl[0], fcl[0].value & 0x00FFFFFFU));
  const auto caught = warningsOf(preset, *elf, 300000);
  ASSERT_EQ(caught.size(), 1U);
  EXPECT_NE(caught[0].find("[KEY-WRITE] SYSCTL SYSOSCFCLCTL"), std::string::npos) << caught[0];
}

TEST(BrokenImage, AWatchdogNeverStartedIsNamedWhenBringUpEnds) {
  // The WWDTCTL0 write that starts WWDT0 taken out: nothing in a run hangs, so nothing needs the watchdog,
  // but the part is then unsupervised: the twin warns at the first idle WFI.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto clean = warningsOf(preset, *elf, 500000);
  EXPECT_TRUE(clean.empty()) << clean.front();
  const auto start = storesTo(preset, *elf, 0x40080000 + 0x1100, 50000);
  ASSERT_EQ(start.size(), 1U);
  removeStores(*elf, start);
  const auto caught = warningsOf(preset, *elf, 500000);
  ASSERT_EQ(caught.size(), 1U);
  EXPECT_NE(caught[0].find("[WWDT-STOPPED]"), std::string::npos) << caught[0];
  EXPECT_NE(caught[0].find("WWDT0 never started"), std::string::npos) << caught[0];
}

TEST(BrokenImage, TheSlcanTxPinMuxedAsGpioIsStoppedByTheRoutingRule) {
  // PINCM9 (PA8, UART0 TX to the XDS110 on the LP-MSPM0L1306) with PF 1 (GPIO) instead of PF 2: the UART
  // sends, the pin does not carry it.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_EQ(stopOf(preset, *elf, 300000), "");
  const auto tx = storeSites(preset, *elf, 0x40428000 + 4 * 9, 50000);
  ASSERT_FALSE(tx.empty());
  ASSERT_EQ(tx[0].value & 0x3FU, 2U) << "the image muxes PA8 to UART0 TX";
  ASSERT_TRUE(storeValue(*elf, tx[0], (tx[0].value & ~0x3FU) | 1U));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "PIN-UNROUTED");
  EXPECT_NE(stop.find("UART0 TX"), std::string::npos) << stop;
  EXPECT_NE(stop.find("PA8"), std::string::npos) << stop;
}

TEST(BrokenImage, ATxDmaChannelOnTheRxTriggerIsStoppedByTheTriggerRule) {
  // DMATCTL.DMATSEL 17 (UART0 RX) for the channel that feeds UART0 TXDATA (TX trigger 18 on the G3507).
  const std::string preset = "lp-mspm0g3507-bq79616";
  LOAD_OR_SKIP(elf, preset);
  std::vector<StoreSite> tx;
  for (uint32_t ch = 0; ch < 7 && tx.empty(); ++ch) {
    for (const auto& s : storeSites(preset, *elf, 0x4042A000 + 0x1110 + 4 * ch, 50000)) {
      if (s.value == 18) tx.push_back(s);
    }
  }
  ASSERT_FALSE(tx.empty()) << "no DMATCTL write of UART0's TX trigger";
  ASSERT_TRUE(storeValue(*elf, tx[0], 17));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "DMA-TRIGGER");
  EXPECT_NE(stop.find("to UART0 TX"), std::string::npos) << stop;
  EXPECT_NE(stop.find("trigger 17 (UART0 RX)"), std::string::npos) << stop;
}

TEST(BrokenImage, AUartDmaOnTheHalfEmptyLevelIsNamedByTheLevelRule) {
  // IFLS TXIFLSEL 2 (half empty) instead of 7 under the TX DMA: the trigger waits for a transition an empty
  // FIFO never makes (hw_uart.h IFLS: 7 "esp. required for DMA Trigger").
  const std::string preset = "lp-mspm0g3507-bq79616";
  LOAD_OR_SKIP(elf, preset);
  const auto ifls = storeSites(preset, *elf, 0x40108000 + 0x110C, 50000);
  ASSERT_EQ(ifls.size(), 1U);
  ASSERT_EQ(ifls[0].value & 7U, 7U);
  ASSERT_TRUE(storeValue(*elf, ifls[0], (ifls[0].value & ~7U) | 2U));
  const auto warnings = warningsOf(preset, *elf, 300000);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("[UART-DMA-LEVEL]"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("TXIFLSEL 2"), std::string::npos) << warnings[0];
}

TEST(BrokenImage, AnAlertHandlerThatNeverClearsItsFlagIsNamedByTheStormRule) {
  // The GPIO handler's ICLR write taken out: the first ALERT edge leaves GPIOA's RIS set, INT_GROUP1 stays
  // asserted, and the handler is re-entered as soon as it returns.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  auto alertRun = [&](const ElfFile& image, std::vector<uint32_t>* iclr) {
    Rig r(preset, image);
    twin::Machine& m = r.board.machine();
    m.map().onStore([&](uint32_t a, uint32_t) {
      if (iclr != nullptr && a == 0x400A0000 + 0x1048 &&
          std::find(iclr->begin(), iclr->end(), m.core().pc()) == iclr->end())
        iclr->push_back(m.core().pc());
    });
    r.board.runUntilUs(1000000);
    r.board.driveMonitorSignal(false);
    r.board.runUntilUs(1300000);
    return r.board.warnings();
  };
  std::vector<uint32_t> iclr;
  const auto clean = alertRun(*elf, &iclr);
  EXPECT_TRUE(clean.empty()) << clean.front();
  ASSERT_FALSE(iclr.empty()) << "the handler never writes GPIOA ICLR";
  removeStores(*elf, iclr);
  const auto caught = alertRun(*elf, nullptr);
  ASSERT_FALSE(caught.empty());
  EXPECT_NE(caught[0].find("[IRQ-STORM] exception 17"), std::string::npos) << caught[0];
}

TEST(BrokenImage, AnRxDmaWithoutDestinationIncrementIsNamed) {
  // The BQ79616 response DMA (UART0 RXDATA to SRAM) without DMADSTINCR: every byte lands on the first.
  const std::string preset = "lp-mspm0g3507-bq79616";
  LOAD_OR_SKIP(elf, preset);
  StoreSite rx;
  for (uint32_t ch = 0; ch < 7 && rx.pc == 0; ++ch) {
    for (const auto& s : storeSites(preset, *elf, 0x4042A000 + 0x1200 + 0x10 * ch, 300000)) {
      if ((s.value & 2U) && ((s.value >> 20) & 0xFU) == 3U && ((s.value >> 16) & 0xFU) == 0U) rx = s;
    }
  }
  ASSERT_NE(rx.pc, 0U) << "no DMACTL write enabling a channel with the destination incremented";
  ASSERT_TRUE(storeValue(*elf, rx, rx.value & ~(0xFU << 20)));
  const auto warnings = warningsOf(preset, *elf, 300000);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("[DMA-NO-INCREMENT]"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("from UART0 RX"), std::string::npos) << warnings[0];
}

TEST(BrokenImage, AnAlertTakenOnItsRisingEdgeIsNamedByTheEdgeRule) {
  // PA15's POLARITY (hw_gpio.h POLARITY15_0 DIO15, bits 31:30) rising (1) instead of falling (2): the
  // BQ76952's active-low ALERT then interrupts when it ends. The image computes the register value at run
  // time, so the broken setting is written after bring-up, through the bus, as a debugger would.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  auto alert = [&](bool rising) {
    Rig r(preset, *elf);
    r.board.runUntilUs(1000000);
    twin::AddressMap& map = r.board.machine().map();
    uint32_t polarity = 0;
    EXPECT_TRUE(map.load(0x400A0000 + 0x1390, 4, polarity));
    EXPECT_EQ((polarity >> 30) & 3U, 2U) << "the image takes ALERT on its falling edge";
    if (rising) {
      EXPECT_TRUE(map.store(0x400A0000 + 0x1390, 4, (polarity & ~(3U << 30)) | (1U << 30)));
    }
    r.board.driveMonitorSignal(false);
    r.board.runUntilUs(1010000);
    return r.board.warnings();
  };
  const auto clean = alert(false);
  EXPECT_TRUE(clean.empty()) << clean.front();
  const auto caught = alert(true);
  ASSERT_FALSE(caught.empty());
  EXPECT_NE(caught[0].find("[SIGNAL-EDGE] PA15"), std::string::npos) << caught[0];
}

}  // namespace

TEST(BrokenImage, BssLeftUnzeroedIsStoppedByTheUninitialisedReadRule) {
  // The start-up's zero fill of .bss (its first call of memset, after the .data copy) taken out: the image
  // then reads what SRAM held at power-up where C++ promises 0. Unpatched, the same run is clean.
  for (const std::string preset : {"lp-mspm0l1306-bq76952", "lp-mspm0g3507-bq76952"}) {
    LOAD_OR_SKIP(elf, preset);
    EXPECT_EQ(stopOf(preset, *elf, 300000), "") << preset;
    const auto reset = elf->symbol("Reset_Handler");
    ASSERT_TRUE(reset.has_value());
    uint32_t call = 0;
    for (uint32_t at = reset->value & ~1U; at + 4 <= (reset->value & ~1U) + reset->size && call == 0;
         at += 2) {
      const uint32_t target = blTarget(*elf, at);
      if (target != 0 && elf->symbolAt(target) == "memset") call = at;
    }
    ASSERT_NE(call, 0U) << preset << ": no memset call in Reset_Handler";
    ASSERT_TRUE(elf->patch16(call, 0xBF00) && elf->patch16(call + 2, 0xBF00));
    const std::string stop = stopOf(preset, *elf, 300000);
    EXPECT_RULE(stop, "BSS-UNINIT");
    EXPECT_NE(stop.find("no instruction stored since the reset"), std::string::npos) << stop;
  }
}

TEST(BrokenImage, StandbyWithAScanPendingIsStoppedByTheSleepEventRule) {
  // A power policy that picks STANDBY1 (SCR.SLEEPDEEP, PMODECFG.DSLEEP STANDBY, MCLKCFG.STOPCLKSTBY: the
  // fields DL_SYSCTL_setPowerPolicySTANDBY1 sets) while the scheduler's deadline is counted by a TIMG from
  // the 32 MHz BUSCLK and the scan's I2C transfers run from it, which that mode stops: the scan would come
  // late or stall (the first sleep names whichever is pending, at 101 ms an I2C transfer). Set through the
  // bus after bring-up, as a debugger would; the same image left in SLEEP runs clean (the image tests above).
  // Set while the core sleeps through a transfer's FIFO interrupts: a handler that posts (a transfer's STOP,
  // the clock's alarm) rewrites SCR before the next sleep (sleep-on-exit cleared), so a write just before one
  // of those is undone. At 100 ms it was, once the I2C driver took fewer interrupts (issue 32).
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  Rig r(preset, *elf);
  r.board.runUntilUs(101000);
  ASSERT_FALSE(r.board.machine().stopped()) << r.board.machine().stopReason();
  twin::AddressMap& map = r.board.machine().map();
  uint32_t mclkcfg = 0;
  EXPECT_TRUE(map.load(0x400AF000 + 0x1104, 4, mclkcfg));
  EXPECT_TRUE(map.store(0x400AF000 + 0x1140, 4, 1));                     // PMODECFG STANDBY
  EXPECT_TRUE(map.store(0x400AF000 + 0x1104, 4, mclkcfg | (1U << 21)));  // STOPCLKSTBY
  EXPECT_TRUE(map.store(0xE000ED10, 4, 0x2 | 0x4));                      // SLEEPONEXIT, SLEEPDEEP
  r.board.runUntilUs(200000);
  const std::string stop = r.board.machine().stopped() ? r.board.machine().stopReason() : std::string();
  EXPECT_RULE(stop, "SLEEP-EVENT-LOST");
  EXPECT_NE(stop.find("STANDBY1"), std::string::npos) << stop;
  EXPECT_TRUE(stop.find("TIMG") != std::string::npos || stop.find("I2C0 has a transfer") != std::string::npos)
      << stop;
}

// The power policy of the L1306-BQ76952 image (bsp/mspm0/power_policy.cpp, BSP_DEEP_IDLE) with one of its
// checks taken out: its first conditional branch (the I2C controller's MSR.BUSY: SLEEP0 while a transfer is
// in flight) made unconditional, or its second (the UART's STAT.BUSY) made a NOP. The policy then picks
// STANDBY1 with the transfer still running, whose bit timing needs the BUSCLK that mode stops: the twin
// names the transfer (SLEEP-EVENT-LOST). Unpatched, the same run is clean (it sleeps in STANDBY1 between
// the scans: twin.*.lp-mspm0l1306-bq76952).
std::string stopWithPolicyBranchPatched(int branch, uint16_t (*patch)(uint16_t)) {
  const std::string preset = "lp-mspm0l1306-bq76952";
  auto elf = loadElf(preset);
  if (!elf) return "not built";
  if (stopOf(preset, *elf, 400000) != "") return "the unpatched image stopped";
  int seen = 0;
  for (const auto& s : elf->symbols()) {
    if (!s.function || elf->symbolAt(s.value & ~1U).find("StandbyIdle::doSleep") == std::string::npos)
      continue;
    for (uint32_t at = s.value & ~1U; at < (s.value & ~1U) + s.size; at += 2) {
      const uint16_t op = twinpatch::half(*elf, at);
      if ((op & 0xF000) != 0xD000 || (op & 0x0F00) >= 0x0E00) continue;  // B<cond> (A6.7.10 T1)
      if (++seen == branch) {
        if (!elf->patch16(at, patch(op))) return "patch failed";
        return stopOf(preset, *elf, 400000);
      }
    }
  }
  return "no such branch in StandbyIdle::doSleep";
}

TEST(BrokenImage, StandbyChosenWithAnI2cTransferInFlightIsStoppedByTheSleepEventRule) {
  LOAD_OR_SKIP(elf, "lp-mspm0l1306-bq76952");
  // BEQ (skip the return) becomes B with the same offset: the busy controller no longer keeps SLEEP0.
  const std::string stop = stopWithPolicyBranchPatched(
      1, [](uint16_t op) { return static_cast<uint16_t>(0xE000 | (op & 0x00FF)); });
  EXPECT_RULE(stop, "SLEEP-EVENT-LOST");
  EXPECT_NE(stop.find("STANDBY1"), std::string::npos) << stop;
  EXPECT_NE(stop.find("I2C0 has a transfer in flight"), std::string::npos) << stop;
}

TEST(BrokenImage, StandbyChosenWhileTheUartTransmitsIsStoppedByTheSleepEventRule) {
  LOAD_OR_SKIP(elf, "lp-mspm0l1306-bq76952");
  // BNE (to the return) becomes a NOP: a transmitting UART no longer keeps SLEEP0.
  const std::string stop = stopWithPolicyBranchPatched(2, [](uint16_t) { return uint16_t{0xBF00}; });
  EXPECT_RULE(stop, "SLEEP-EVENT-LOST");
  EXPECT_NE(stop.find("STANDBY1"), std::string::npos) << stop;
  EXPECT_NE(stop.find("UART0 is transmitting"), std::string::npos) << stop;
}

TEST(BrokenImage, AFaultOutputReleasedAtBootIsStoppedByTheFaultOutputRule) {
  // The DOUTSET31_0 store that asserts PB26 before its driver is enabled taken out (GpioOut::init(true)
  // become init(false), the mutation run's gpio-fault-output-released-at-boot): the output is driven low from
  // the reset on, and the pack path behind it could close before any scan. Named at the image's first CAN
  // frame, on the BQ79616 image (whose path the output opens) and the BQ76952 image (where it only
  // indicates).
  for (const std::string preset : {"lp-mspm0g3507-bq79616", "lp-mspm0g3507-bq76952"}) {
    SCOPED_TRACE(preset);
    LOAD_OR_SKIP(elf, preset);
    EXPECT_EQ(stopOf(preset, *elf, 300000), "");
    std::vector<uint32_t> asserts;
    for (const auto& s : storeSites(preset, *elf, 0x400A2000 + 0x1290, 20000)) {
      if (s.value == 1U << 26) asserts.push_back(s.pc);
    }
    ASSERT_EQ(asserts.size(), 1U);
    removeStores(*elf, asserts);
    const std::string stop = stopOf(preset, *elf, 300000);
    EXPECT_RULE(stop, "FAULT-OUT-RELEASED");
    EXPECT_NE(stop.find("PB26"), std::string::npos) << stop;
  }
}

TEST(BrokenImage, AGlobalFilterAcceptingEveryFrameIsNamedByTheFilterRule) {
  // GFC written with ANFS/ANFE 0 (accept non-matching frames into RX FIFO 0) instead of rejecting them, the
  // mutation run's mcan-accept-all: the command filter list then passes the bus's whole traffic. The image
  // keeps up with a full bus of foreign frames (bms-sim measured 12.5 % CPU instead of 1.7 %, no RF0L), so
  // only the configuration names it, at the first foreign frame. Unpatched, that frame is rejected silently.
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  auto foreignFrameWarnings = [&](const ElfFile& image) {
    Rig r(preset, image);
    r.board.runUntilUs(300000);
    r.board.sendCan({0x104, false, 8, {}});  // another node's telemetry
    r.board.runUntilUs(320000);
    EXPECT_EQ(r.board.machine().stopReason(), "");
    return r.board.warnings();
  };
  const auto clean = foreignFrameWarnings(*elf);
  EXPECT_TRUE(clean.empty()) << clean.front();
  const auto gfc = storeSites(preset, *elf, 0x40508000 + 0x7080, 50000);
  ASSERT_EQ(gfc.size(), 1U);
  ASSERT_EQ(gfc[0].value & 0x3CU, 0x28U);  // ANFS 2, ANFE 2: reject
  ASSERT_TRUE(storeValue(*elf, gfc[0], gfc[0].value & ~0x3CU));
  const auto caught = foreignFrameWarnings(*elf);
  ASSERT_EQ(caught.size(), 1U);
  EXPECT_NE(caught[0].find("[MCAN-FILTER-OPEN]"), std::string::npos) << caught[0];
  EXPECT_NE(caught[0].find("0x104"), std::string::npos) << caught[0];
}

TEST(BrokenImage, AnHfxtWaitWithoutABoundIsStoppedWhenTheCrystalIsMissing) {
  // startHfxt()'s poll of CLKSTATUS.HFCLKGOOD with its bound taken out (its loop's backward conditional
  // branch made unconditional: the mutation run's hfxt-wait-unbounded). With the crystal it still leaves at
  // HFCLKGOOD; on a board without one the start-up monitor sets HFCLKOFF after HFXTTIME and HFCLKGOOD never
  // comes (SLAU846A 2 HFXT startup monitor): the part hangs before the watchdog starts. Unpatched, the same
  // board gives up after ~5 ms and runs on without CAN, clean for 60 ms (at 105 ms it reads the MCAN it never
  // powered: bsp/twin/README.md, open).
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  const auto noCrystal = [](Board& b) { b.chip().sysctl().removeCrystal(); };
  {
    Rig r(preset, *elf);
    noCrystal(r.board);
    r.board.runUntilUs(60000);
    EXPECT_EQ(r.board.machine().stopReason(), "");
    EXPECT_TRUE(r.board.warnings().empty()) << r.board.warnings().front();
  }
  // The HFXT's start (HSCLKEN.HFXTEN), then the wait: the first backward conditional branch after it whose
  // target lies furthest back but still after the start is the poll loop's (an inner one is spin()'s delay).
  uint32_t startPc = 0;
  for (const auto& s : storeSites(preset, *elf, 0x400AF000 + 0x1108, 50000)) {
    if (s.value & 1U) startPc = s.pc;
  }
  ASSERT_NE(startPc, 0U) << "no HSCLKEN write with HFXTEN";
  uint32_t loopBranch = 0, loopTarget = UINT32_MAX;
  for (uint32_t at = startPc + 2; at < startPc + 2 + 2 * 48; at += 2) {
    const uint16_t op = twinpatch::half(*elf, at);
    if ((op & 0xF000) != 0xD000 || (op & 0x0F00) >= 0x0E00 || (op & 0x80) == 0) continue;  // Bcc backward
    const uint32_t target = at + 4 + static_cast<uint32_t>(static_cast<int8_t>(op & 0xFF) * 2);
    if (target > startPc && target < loopTarget) loopBranch = at, loopTarget = target;
  }
  ASSERT_NE(loopBranch, 0U) << "no backward branch after the HFXT start";
  const int32_t offset = (static_cast<int32_t>(loopTarget) - static_cast<int32_t>(loopBranch + 4)) / 2;
  ASSERT_TRUE(elf->patch16(loopBranch, static_cast<uint16_t>(0xE000 | (offset & 0x7FF))));  // B: no bound
  EXPECT_EQ(stopOf(preset, *elf, 300000), "");  // the crystal starts: the wait ends at HFCLKGOOD
  const std::string stop = stopOf(preset, *elf, 60000, noCrystal);
  EXPECT_RULE(stop, "HFXT-WAIT-UNBOUNDED");
  EXPECT_NE(stop.find("HFCLKOFF"), std::string::npos) << stop;
}

TEST(BrokenImage, AClockCompareLeftMaskedIsNamedByTheCompareRule) {
  // TimgClock's IMASK written with LOAD only, CCU1 left out (the mutation run's timg-clock-no-ccu1): CC1 is
  // still set to the half period, its event comes every wrap and reaches nothing, so the widened clock counts
  // one half per wrap instead of two and jumps back. Named (a warning) at the third wrap, 197 ms; unpatched,
  // the same run is clean (CCU0, the alarm, is masked between alarms but was seen unmasked).
  const std::string preset = "lp-mspm0g3507-bq76952";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_TRUE(warningsOf(preset, *elf, 300000).empty());
  constexpr uint32_t kLoad = 1U << 1, kCcu1 = 1U << 9;
  const auto imask = storeSites(preset, *elf, 0x40084000 + 0x1028, 50000);
  const StoreSite start = siteOf(imask, kLoad | kCcu1);
  ASSERT_NE(start.pc, 0U) << "no TIMG0 IMASK write of LOAD | CCU1";
  ASSERT_TRUE(storeValue(*elf, start, kLoad));
  const auto caught = warningsOf(preset, *elf, 300000);
  ASSERT_EQ(caught.size(), 1U);
  EXPECT_NE(caught[0].find("[TIMER-COMPARE-UNSEEN]"), std::string::npos) << caught[0];
  EXPECT_NE(caught[0].find("CC1 (0x8000)"), std::string::npos) << caught[0];
}

TEST(BrokenImage, AWakeUpArmedWithoutItsRecheckIsStoppedByTheComparePassedRule) {
  // TimgClock::doWakeAt returning right after it unmasks CCU0 (the mutation run's timg-wake-no-recheck): the
  // re-read of the counter and the ISET for a deadline passed while arming are gone. The twin's run never
  // arms that close, so the late wake-up itself never happens; the rule names the arming the core sleeps
  // on without a look at the counter. Unpatched, the same run is clean.
  const std::string preset = "lp-mspm0l1306-bq76952";
  LOAD_OR_SKIP(elf, preset);
  EXPECT_EQ(stopOf(preset, *elf, 300000), "");
  constexpr uint32_t kCcu0 = 1U << 8;
  StoreSite arm;
  for (const auto& s : storeSites(preset, *elf, 0x40084000 + 0x1028, 50000)) {
    if ((s.value & kCcu0) != 0) arm = s;
  }
  ASSERT_NE(arm.pc, 0U) << "no TIMG0 IMASK write with CCU0";
  // The function's epilogue (POP {..., PC}) copied to the instruction after the IMASK store: return there.
  uint16_t pop = 0;
  for (uint32_t at = arm.pc + 2; at < arm.pc + 2 + 2 * 16 && pop == 0; at += 2) {
    const uint16_t op = twinpatch::half(*elf, at);
    if ((op & 0xFF00) == 0xBD00) pop = op;
  }
  ASSERT_NE(pop, 0U) << "no POP {..., PC} after the arming";
  ASSERT_TRUE(elf->patch16(arm.pc + 2, pop));
  const std::string stop = stopOf(preset, *elf, 300000);
  EXPECT_RULE(stop, "TIMER-COMPARE-PASSED");
  EXPECT_NE(stop.find("TIMG0: CC0"), std::string::npos) << stop;
}
