// Every signal of the CAN catalogue that has a `not_available` value in bms.yaml goes out as that value when
// its reading is missing, starting from the state the images start from: the application's view and publish
// status in zero-filled storage (Zeroed<T>, as on the MSPM0 images, where .bss is their only initialisation).
// A default written into a struct (StateOfCharge's 255 once was) does not survive that, so StateOfCharge went
// out as 0 % on the images without a gauge.
//
// The signals come from bms.yaml as regmapgen reads it, and the values from the frames FramePlan builds,
// decoded here from the YAML's start and length (not from the generated packers). A signal with a
// not_available value and no case below fails the test, so a new one cannot go unchecked.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "app/publish/frame_plan.hpp"
#include "can/can_model.hpp"
#include "core/zeroed.hpp"

namespace {

using fw::app::BoardSample;
using fw::app::FramePlan;
using fw::app::PackView;
using fw::app::PublishStatus;
using regmapgen::Diagnostics;
using regmapgen::Sources;
namespace cm = regmapgen::can;

fw::Instant at(uint32_t tMs) {
  return fw::Instant{tMs * 1000};
}

// The view, status and samples of an application as an image builds them: zero bytes, then the shape its
// constructor sets (app/monitors/*_app.hpp), then what the monitor writes after each scan.
struct ZeroedPack {
  static constexpr int kBoards = 2;
  fw::Zeroed<PackView> view;
  fw::Zeroed<PublishStatus> status;
  std::vector<BoardSample> samples;  // Bq79616Storage's samples: zero bytes in .bss
  FramePlan plan{*view, *status, fw::ms(300)};

  ZeroedPack() : samples(kBoards) {
    std::memset(static_cast<void*>(samples.data()), 0, samples.size() * sizeof(BoardSample));
    view->cellsPerBoard = 16;
    view->tempsPerBoard = 2;
    view->boards = samples;
  }
  // A monitor's validated scan of board `b`: every cell and sensor with a reading.
  void measure(int b, uint32_t tMs) {
    BoardSample& s = samples[static_cast<size_t>(b)];
    s.valid = true;
    s.last = fw::Status::Ok;
    s.takenAt = at(tMs);
    for (int c = 0; c < 16; ++c)
      s.cellMv[c] = static_cast<int16_t>(3600 + 10 * b + c);
    for (int t = 0; t < 4; ++t)
      s.tempDeciK[t] = static_cast<int16_t>(2982 + t + b);
  }
  // Every board validated, the current measured, a gauge's state of charge: every signal has a reading.
  void healthy(uint32_t tMs) {
    for (int b = 0; b < kBoards; ++b)
      measure(b, tMs);
    view->hasCurrent = true;
    view->currentMa = -1234;
    view->soc.set(573, 1433, 2500, fw::app::SocBasis::Ocv);
    view->storage.period = fw::ms(100);  // a monitor with a storage mode (storage_mode.hpp) sets it
    status->pathsKnown = true;           // protection confirmed the paths (FET read-back, or the fault pin)
    status->chargeOn = status->dischargeOn = true;
    // The previous run left a fault record that survived the reset (a software SYSRST keeps SRAM).
    fw::app::StartupInfo startup;
    startup.resetCause = 27;  // sys_software
    startup.faultValid = true;
    startup.faultModule = 21;
    startup.faultLine = 300;
    startup.kept.logEntries = 2;  // the record store restored two trips and keeps this fault
    startup.kept.faultSource = fw::app::FaultSource::LastReset;
    plan.announceStartup(startup);
  }
  void scanned(uint32_t tMs) { fw::app::summarize(*view, at(tMs)); }
  std::vector<fw::hal::CanFrame> slowCycle(uint32_t tMs) {
    std::vector<fw::hal::CanFrame> out;
    plan.beginSlow();
    fw::hal::CanFrame f;
    while (out.size() < 200 && plan.build(at(tMs), f)) {
      out.push_back(f);
      plan.advance();
    }
    return out;
  }
};

// A signal's raw value in slot `slot` of a frame, read from bms.yaml's layout (Intel order, as every signal
// with a not-available value is; checked below), sign-extended for signed signals.
int64_t rawOf(const cm::Signal& s, const fw::hal::CanFrame& f, uint32_t slot) {
  const uint32_t start = s.slotStart(slot);
  uint64_t bits = 0;
  for (uint32_t i = 0; i < s.length; ++i) {
    const uint32_t bit = start + i;
    bits |= static_cast<uint64_t>((f.data[bit / 8] >> (bit % 8)) & 1U) << i;
  }
  if (s.isSigned && (bits >> (s.length - 1)) != 0)
    return static_cast<int64_t>(bits) - (int64_t{1} << s.length);
  return static_cast<int64_t>(bits);
}

// Which instances of the signal a case looks at: a frame of its message and a slot in it.
using Selects = std::function<bool(const fw::hal::CanFrame& frame, uint32_t slot)>;
// How a case takes the reading away: applied after healthy() (so everything else has a reading).
using Removes = std::function<void(ZeroedPack& p)>;
struct Case {
  const char* why;  // the condition, as bms.yaml and the README state it
  Removes remove;
  Selects selects;
};

bool any(const fw::hal::CanFrame&, uint32_t) {
  return true;
}
// CellVoltages / Temperatures: board `b`'s slots that hold item < `items` (byte 0 is the board, byte 1's low
// nibble the frame index, bms.yaml).
Selects itemsOfBoard(uint8_t b, uint32_t items) {
  return [b, items](const fw::hal::CanFrame& f, uint32_t slot) {
    return f.data[0] == b && (f.data[1] & 0x0FU) * 3U + slot < items;
  };
}

void boardOneSilent(ZeroedPack& p) {
  p.samples[1].last = fw::Status::NoResponse;  // it answered once; its old values stay in the sample
}
void everyBoardSilent(ZeroedPack& p) {
  for (auto& s : p.samples)
    s.last = fw::Status::Timeout;
}
void noTemperature(ZeroedPack& p) {
  for (auto& s : p.samples) {
    for (auto& t : s.tempDeciK)
      t = fw::app::kNoReading;
  }
}

void boardOneNeverMeasured(ZeroedPack& p) {
  p.samples[1] = {};  // never validated since start-up: no age to give
}

void noSoc(ZeroedPack& p) {
  p.view->soc = {};  // basis Unknown, as a monitor leaves it until the first value
}

void noFaultRecord(ZeroedPack& p) {
  fw::app::StartupInfo startup;
  startup.resetCause = 14;  // boot_wwdt0: a BOOTRST clears SRAM and the record with it
  p.plan.announceStartup(startup);
}

void noRecordStore(ZeroedPack& p) {
  fw::app::StartupInfo startup;  // kept left as it starts: what an image without the store announces
  startup.resetCause = 1;
  p.plan.announceStartup(startup);
}

// By "Message.Signal": the state in which that signal has no reading, and where to look for it.
const std::map<std::string, Case>& cases() {
  static const std::map<std::string, Case> table = {
      {"PackSummary.PackVoltage",
       {"a board's last scan failed: the sum is not the pack", boardOneSilent, any}},
      {"PackSummary.PackCurrent",
       {"no current sensor (the BQ79616 images)", [](ZeroedPack& p) { p.view->hasCurrent = false; }, any}},
      {"PackSummary.StateOfCharge", {"no state of charge known yet (or ever: BQ79616, L1306)", noSoc, any}},
      {"StateOfCharge.Soc", {"no state of charge known yet (or ever: BQ79616, L1306)", noSoc, any}},
      {"StateOfCharge.RemainingCapacity", {"no state of charge known yet", noSoc, any}},
      {"StateOfCharge.FullChargeCapacity", {"no state of charge known yet", noSoc, any}},
      {"StateOfCharge.Basis", {"no state of charge known yet", noSoc, any}},
      {"PackSummary.ChargeFet",
       {"nothing confirms the paths (a failed scan, stale data, comm loss)",
        [](ZeroedPack& p) { p.status->pathsKnown = false; }, any}},
      {"PackSummary.DischargeFet",
       {"nothing confirms the paths (a failed scan, stale data, comm loss)",
        [](ZeroedPack& p) { p.status->pathsKnown = false; }, any}},
      {"CellExtremes.MaxCellVoltage", {"no board validated", everyBoardSilent, any}},
      {"CellExtremes.MaxCellIndex", {"no board validated", everyBoardSilent, any}},
      {"CellExtremes.MinCellVoltage", {"no board validated", everyBoardSilent, any}},
      {"CellExtremes.MinCellIndex", {"no board validated", everyBoardSilent, any}},
      {"TemperatureExtremes.MaxTemperature", {"no sensor read", noTemperature, any}},
      {"TemperatureExtremes.MaxTemperatureIndex", {"no sensor read", noTemperature, any}},
      {"TemperatureExtremes.MinTemperature", {"no sensor read", noTemperature, any}},
      {"TemperatureExtremes.MinTemperatureIndex", {"no sensor read", noTemperature, any}},
      {"CellVoltages.Cell", {"the board's last scan failed", boardOneSilent, itemsOfBoard(1, 16)}},
      {"Startup.FaultModule",
       {"no fault record survived the reset (SRAM cleared, or the run ended without a fault)", noFaultRecord,
        any}},
      {"Startup.FaultLine",
       {"no fault record survived the reset (SRAM cleared, or the run ended without a fault)", noFaultRecord,
        any}},
      {"Startup.ProtectionLogEntries",
       {"an image without the record store (the L1306 images)", noRecordStore, any}},
      {"Startup.FaultSource", {"an image without the record store (the L1306 images)", noRecordStore, any}},
      {"StorageStatus.MeasurementAge",
       {"a board never validated since start-up", boardOneNeverMeasured, any}},
      {"Temperatures.Temp",
       {"the sensors of a scan that validated had no reading", noTemperature, itemsOfBoard(0, 2)}},
  };
  return table;
}

cm::Catalogue load(Sources& sources) {
  std::string text;
  EXPECT_TRUE(regmapgen::readFile(BMS_CAN_YAML, text)) << BMS_CAN_YAML;
  const int file = sources.add(BMS_CAN_YAML, text);
  Diagnostics diag(sources);
  auto cat = cm::buildCatalogue(sources, file, diag);
  EXPECT_EQ(diag.errorCount(), 0u);
  return cat;
}

struct Checked {
  size_t notAvailable = 0, readings = 0;
};

// The instances `selects` picks among the frames of `message`: how many are not available, how many carry
// a reading.
Checked count(const cm::Message& message, const cm::Signal& signal,
              const std::vector<fw::hal::CanFrame>& frames, const Selects& selects) {
  Checked out;
  for (const auto& f : frames) {
    if (f.id != message.id) continue;
    for (uint32_t slot = 0; slot < signal.count; ++slot) {
      if (!selects(f, slot)) continue;
      ++(rawOf(signal, f, slot) == *signal.notAvailable ? out.notAvailable : out.readings);
    }
  }
  return out;
}

TEST(CanNotAvailable, EverySignalWithoutItsReadingGoesOutNotAvailableFromZeroedState) {
  Sources sources;
  const auto cat = load(sources);
  size_t signals = 0;
  for (const auto& m : cat.messages) {
    for (const auto& s : m.signals) {
      if (!s.notAvailable) continue;
      const std::string name = m.name + "." + s.name;
      ++signals;
      ASSERT_FALSE(s.bigEndian) << name << ": rawOf() reads Intel-order signals only";
      const auto it = cases().find(name);
      ASSERT_NE(it, cases().end()) << name << " has a not_available value in bms.yaml and no case here: say "
                                   << "when it has no reading, and the test checks that it goes out so";
      const Case& c = it->second;
      // With every reading there: the selected instances carry readings (else the case proves nothing).
      ZeroedPack with;
      with.healthy(100);
      with.scanned(100);
      const Checked h = count(m, s, with.slowCycle(110), c.selects);
      EXPECT_GT(h.readings, 0u) << name << ": the case selects nothing that carries a reading";
      EXPECT_EQ(h.notAvailable, 0u) << name << " is not available although every reading is there";
      // Without it: every selected instance is not available.
      ZeroedPack without;
      without.healthy(100);
      c.remove(without);
      without.scanned(100);
      const Checked n = count(m, s, without.slowCycle(110), c.selects);
      EXPECT_GT(n.notAvailable, 0u) << name << ": no instance checked (" << c.why << ")";
      EXPECT_EQ(n.readings, 0u) << name << " goes out as a reading when " << c.why << " (raw "
                                << "not_available is " << *s.notAvailable << ")";
    }
  }
  EXPECT_EQ(signals, cases().size()) << "cases() names a signal bms.yaml gives no not_available value";
}

// Before the first scan nothing has a reading: every such signal of every frame is not available, whatever
// bms.yaml adds (no case needed).
TEST(CanNotAvailable, BeforeTheFirstScanEverySignalThatCanLackAReadingIsNotAvailable) {
  Sources sources;
  const auto cat = load(sources);
  ZeroedPack p;
  const auto frames = p.slowCycle(50);
  size_t checked = 0;
  for (const auto& m : cat.messages) {
    for (const auto& s : m.signals) {
      if (!s.notAvailable) continue;
      const Checked c = count(m, s, frames, any);
      EXPECT_EQ(c.readings, 0u) << m.name << "." << s.name << " carries a value before any scan";
      checked += c.notAvailable;
    }
  }
  EXPECT_GT(checked, 0u);
}

}  // namespace
