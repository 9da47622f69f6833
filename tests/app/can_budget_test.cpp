// The CAN bus budget (README "CAN and SLCAN output": "CAN bus load at 500 kbit/s, worst configuration (64
// boards): every message at its stated or documented period").
//
// Worst case on paper: every configuration the firmware supports (1..64 boards of a BQ79616 chain, both
// layouts, and the single-board images), every frame with its worst-case stuff bits, every message at its
// cycle_ms from bms.yaml (ProtectionEvent, which is sent on a fault change, every 100 ms as if a fault
// changed in every cycle). The load must leave each period room for its frames.
// In practice: the firmware's own publisher and frame plan on the host's 500 kbit/s CAN controller (real bit
// timing) for a few seconds, checking that every message instance goes out at its stated period.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <vector>

#include "app/balancing/balancing_status.hpp"
#include "app/publish/can_publisher.hpp"
#include "app/publish/frame_plan.hpp"
#include "app/publish/slcan.hpp"
#include "can/bms.hpp"
#include "sim/can.hpp"
#include "sim/harness.hpp"

namespace {

namespace bms = fw::can::bms;
namespace app = fw::app;

constexpr double kBitrate = bms::kBitrate;
static_assert(bms::kBitrate == 500000);

// Bits of a classic data frame with a standard identifier in the worst case (ISO 11898-1): 47 fixed bits
// (SOF, 11-bit id, RTR, IDE, r0, DLC 4, CRC 15, CRC delimiter, ACK 2, EOF 7, intermission 3) plus 8 per data
// byte, and one stuff bit per 4 bits after the first of the 34 + 8n bits from SOF to the CRC.
constexpr uint32_t worstBits(uint32_t dlc) {
  return 47 + 8 * dlc + (34 + 8 * dlc - 1) / 4;
}
static_assert(worstBits(8) == 135 && worstBits(0) == 55);

constexpr uint32_t framesPerBoard(uint32_t items, uint32_t perFrame) {
  return (items + perFrame - 1) / perFrame;
}

struct Config {
  const char* name;
  int boards;
  uint8_t cells;
  uint8_t temps;
  bool balances;  // BalancingStatus, one frame per board a second (every image but the BQ4050's)
};

// Frames per second each message needs at its stated period (cycle_ms; the TI set and ProtectionEvent,
// cycle 0, after every 100 ms scan / fast cycle).
struct Load {
  double framesPerSecond = 0;
  double busShare = 0;  // of 500 kbit/s, worst-case stuffing
  double periodMs = 0;  // worst-case bus time one 100 ms period needs (native: on average over a second)
};

Load nativeLoad(const Config& c) {
  const double fast = 1000.0 / bms::PackSummary::kCycleMs;  // per second
  static_assert(bms::PackSummary::kCycleMs == 100 && bms::CellExtremes::kCycleMs == 100);
  static_assert(bms::CellVoltages::kCycleMs == 1000 && bms::Temperatures::kCycleMs == 1000 &&
                bms::TemperatureExtremes::kCycleMs == 1000 && bms::StateOfCharge::kCycleMs == 1000 &&
                bms::BalancingStatus::kCycleMs == 1000);
  const double perFast = 3;  // PackSummary, CellExtremes, ProtectionEvent
  const double perSlow =
      c.boards * (framesPerBoard(c.cells, bms::CellVoltages::kCellPerFrame) +
                  framesPerBoard(c.temps, bms::Temperatures::kTempPerFrame) + (c.balances ? 1 : 0)) +
      2.0;  // TemperatureExtremes, StateOfCharge
  Load l;
  l.framesPerSecond = fast * perFast + perSlow;
  l.busShare = l.framesPerSecond * worstBits(8) / kBitrate;
  // The second's first period carries its fast frames and as much of the slow part as fits; the slow part
  // must be done before the next second, each later period starting with its own fast frames.
  l.periodMs = (perFast * 10 + perSlow) * worstBits(8) / kBitrate * 1000 / 10;
  return l;
}

Load tiLoad(const Config& c) {
  Load l;
  const double perScan = c.boards * 4;  // seed 001: four frames per board after every 100 ms scan
  l.framesPerSecond = perScan * 10;
  l.busShare = l.framesPerSecond * worstBits(8) / kBitrate;
  l.periodMs = perScan * worstBits(8) / kBitrate * 1000;
  return l;
}

TEST(CanBudget, EveryConfigurationFitsItsStatedPeriodsInTheWorstCase) {
  std::vector<Config> configs = {
      {"bq76952", 1, 16, 3, true}, {"bq76907", 1, 7, 1, true}, {"bq4050", 1, 4, 1, false}};
  for (int n = 1; n <= fw::app::kMaxBoards; ++n)
    configs.push_back({"bq79616", n, 16, 2, true});
  double worstNative = 0, worstTi = 0;
  for (const auto& c : configs) {
    const Load native = nativeLoad(c);
    // Every 100 ms period has room for its fast frames, and the slow part has the whole second: the average
    // of the ten periods must stay under 100 ms.
    EXPECT_LT(native.periodMs, 100.0) << c.name << " x" << c.boards;
    EXPECT_LT(native.busShare, 1.0) << c.name << " x" << c.boards;
    worstNative = std::max(worstNative, native.busShare);
    if (std::string(c.name) == "bq79616") {
      const Load ti = tiLoad(c);
      EXPECT_LT(ti.periodMs, 100.0) << "a TI set must go out within the scan period, x" << c.boards;
      worstTi = std::max(worstTi, ti.busShare);
    }
  }
  std::printf("REPORT can.bus_load_worst_native_pct=%.1f (64 boards, 500 kbit/s, worst-case stuff bits)\n",
              worstNative * 100);
  std::printf("REPORT can.bus_load_worst_ti_pct=%.1f (64 boards, a set after every 100 ms scan)\n",
              worstTi * 100);
  // The L1306 images' SLCAN text on the 115 200 Bd back-channel: one line per frame, 10 bits per character.
  const Load slcan = nativeLoad({"bq76952", 1, 16, 3, true});
  const double lineMs = fw::app::slcan::kStandardLength * 10 * 1000.0 / 115200;
  const double slcanShare = slcan.framesPerSecond * lineMs / 1000;
  std::printf("REPORT can.slcan_load_pct=%.1f (BQ76952 board, 115200 Bd, %.2f ms per line)\n",
              slcanShare * 100, lineMs);
  EXPECT_LT(slcanShare, 1.0);
}

// --- in practice
// --------------------------------------------------------------------------------------------

// A stand-in for the monitor: every 100 ms it marks every board freshly measured and tells the publisher.
class FakeMonitor final : public fw::sched::Task {
 public:
  static constexpr fw::sched::TaskId kId = 1;
  FakeMonitor(fw::sched::Scheduler& s, app::PackView& view, std::vector<app::BoardSample>& boards)
      : scheduler_(s), view_(view), boards_(boards) {}
  void start() {
    scheduler_.addTask(kId, *this);
    scheduler_.startTimer(timer_, kId, 1, fw::ms(100), fw::ms(100));
  }
  void run(fw::sched::EventMask) override {
    for (auto& b : boards_)
      b.takenAt = scheduler_.now();
    fw::app::summarize(view_, scheduler_.now());
    scheduler_.post(0, app::CanPublisher::kScanDone);
  }

 private:
  fw::sched::Scheduler& scheduler_;
  app::PackView& view_;
  std::vector<app::BoardSample>& boards_;
  fw::sched::Timer timer_;
};

struct Rig {
  bsp::host::Harness h;
  bsp::host::SimCan can{h.clock, h.irq, bms::kBitrate, 8};
  std::vector<app::BoardSample> boards;
  std::vector<int16_t> raw;
  app::PackView view;
  app::PublishStatus status;
  app::BalancingStatus balancing{};
  app::FramePlan plan{view, status, fw::ms(300)};
  app::CanPublisher publisher;
  FakeMonitor monitor{h.sched, view, boards};

  Rig(int n, app::CanLayout layout)
      : boards(n), raw(n * 16, 0x4BC7), publisher(h.sched, 0, can, plan, layout, fw::ms(100), 10) {
    view.boards = boards;
    view.cellsPerBoard = 16;
    view.tempsPerBoard = 2;
    view.rawCells = raw.data();
    view.balancing = &balancing;
    for (auto& b : boards) {
      b.valid = true;
      b.last = fw::Status::Ok;
      std::fill(std::begin(b.cellMv), std::end(b.cellMv), 3700);
      std::fill(std::begin(b.tempDeciK), std::end(b.tempDeciK), 2982);
    }
    monitor.start();
    publisher.start();
  }
};

// The instants at which each message instance (id, board, frame index) completed on the wire.
std::map<std::tuple<uint32_t, int, int>, std::vector<double>> instances(const bsp::host::SimCan& can) {
  std::map<std::tuple<uint32_t, int, int>, std::vector<double>> out;
  for (const auto& s : can.sent()) {
    const auto& f = s.frame;
    const bool perBoard =
        f.id == bms::CellVoltages::kId || f.id == bms::Temperatures::kId || f.id == bms::BalancingStatus::kId;
    out[{f.id, perBoard ? f.data[0] : 0, perBoard ? (f.data[1] & 0xF) : 0}].push_back(s.timeUs / 1000.0);
  }
  return out;
}

TEST(CanBudget, EveryNativeMessageGoesOutAtItsStatedPeriodUpTo64Boards) {
  for (int n : {1, 2, 16, 40, 63, 64}) {
    Rig r(n, app::CanLayout::Native);
    r.h.runFor(fw::ms(4050));
    const auto got = instances(r.can);
    const std::map<uint32_t, double> period = {
        {bms::PackSummary::kId, bms::PackSummary::kCycleMs},
        {bms::CellExtremes::kId, bms::CellExtremes::kCycleMs},
        {bms::TemperatureExtremes::kId, bms::TemperatureExtremes::kCycleMs},
        {bms::StateOfCharge::kId, bms::StateOfCharge::kCycleMs},
        {bms::CellVoltages::kId, bms::CellVoltages::kCycleMs},
        {bms::Temperatures::kId, bms::Temperatures::kCycleMs},
        {bms::BalancingStatus::kId, bms::BalancingStatus::kCycleMs}};
    // Every instance: each board's six cell frames, its temperature frame and its balancing frame, the
    // extremes and the state of charge.
    EXPECT_EQ(got.size(), 4u + n * 8u) << n << " boards";
    for (const auto& [key, times] : got) {
      const auto [id, board, frame] = key;
      const double p = period.at(id);
      EXPECT_GE(times.size(), static_cast<size_t>(4000 / p) - 1)
          << n << " boards, id " << id << " board " << board << " frame " << frame;
      for (size_t i = 1; i < times.size(); ++i) {
        // Queued behind at most a full TX queue of slow frames: a few ms of jitter, never a missed period.
        EXPECT_LE(times[i] - times[i - 1], p + 5.0) << n << " boards, id " << id << " board " << board;
      }
    }
    EXPECT_EQ(r.publisher.stats().abandoned, 0u) << n << " boards";
  }
}

// A frame is built only when the controller's queue has room for it: once the queue refused one, the
// publisher counts the frames that left against the ones it queued (it is the only sender) and waits for the
// next to leave instead of filling a frame the queue refuses again. Before, every frame of a 64-board slow
// cycle was filled twice, once into the full queue.
TEST(CanPublisher, AFullQueueGetsNoFrameBuiltUntilOneHasLeft) {
  Rig r(64, app::CanLayout::Native);
  r.h.runFor(fw::ms(2050));
  const app::PublishStats& st = r.publisher.stats();
  EXPECT_GT(st.frames, 1000u);  // two slow cycles of 64 boards went out
  EXPECT_EQ(st.frames, r.can.sent().size());
  EXPECT_LE(st.refused, 1u) << "only the refusal that starts the count";
  EXPECT_EQ(st.abandoned, 0u);
}

TEST(CanBudget, EveryScanGetsACompleteTiSetUpTo64Boards) {
  for (int n : {1, 2, 16, 64}) {
    Rig r(n, app::CanLayout::Ti);
    r.h.runFor(fw::ms(1100));
    const auto& sent = r.can.sent();
    ASSERT_EQ(sent.size(), 10u * 4 * n) << n << " boards: one whole set per scan";
    // Sets follow the scans: each set's first frame after its scan (every 100 ms), its last before the next.
    for (size_t k = 0; k < 10; ++k) {
      const double first = sent[k * 4 * n].timeUs / 1000.0, last = sent[(k + 1) * 4 * n - 1].timeUs / 1000.0;
      EXPECT_GT(first, 100.0 * (k + 1)) << n << " boards, set " << k;
      EXPECT_LT(last, 100.0 * (k + 2)) << n << " boards, set " << k;
    }
  }
}

// A bus-off drops the summary of the cycle it hits, whether the controller lost the frame (bus-off while it
// was queued) or refused it (the tick came while the bus was off, as on the twin): either way
// PackSummary.Counter skips the one that never went out (bms.yaml: a gap means a lost frame). The tick during
// the bus-off once began no cycle, and the receiver saw no gap.
TEST(CanBudget, ASummaryLostToABusOffLeavesACounterGap) {
  for (const uint32_t busOffUs : {299900u, 300100u}) {  // just before the 300 ms tick, and while it is queued
    Rig r(2, app::CanLayout::Native);
    r.h.runFor(fw::us(busOffUs));
    r.can.injectBusOff();
    r.h.runFor(fw::us(700000 - busOffUs));
    std::vector<std::pair<double, int>> summaries;
    for (const auto& s : r.can.sent()) {
      if (s.frame.id == bms::PackSummary::kId)
        summaries.emplace_back(s.timeUs / 1000.0, bms::PackSummary::unpack(s.frame).counter);
    }
    ASSERT_GE(summaries.size(), 5u);
    int gaps = 0;
    for (size_t i = 1; i < summaries.size(); ++i) {
      const int step = (summaries[i].second - summaries[i - 1].second) & 0xF;
      const double slots = (summaries[i].first - summaries[i - 1].first) / 100.0;
      EXPECT_NEAR(step, slots, 0.1) << "bus-off at " << busOffUs << " us: the counter steps by " << step
                                    << " across " << slots << " periods at " << summaries[i].first << " ms";
      gaps += step - 1;
    }
    EXPECT_EQ(gaps, 1) << "bus-off at " << busOffUs << " us: exactly the 300 ms summary is missing";
  }
}

// The scheduler never preempts a run, so a publisher run that queued a whole cycle (8 frames, about 0.5 ms
// of CPU on the G3507) held up every higher task made ready meanwhile: on the twin the FET-off command's
// echo poll waited for it (ALERT to the command complete 1 935 us, budget 2 000). A run queues one frame:
// here the bus makes a higher task ready with every frame it takes, and that task runs before the next one.
class Urgent final : public fw::sched::Task {
 public:
  static constexpr fw::sched::TaskId kId = 2;
  explicit Urgent(fw::sched::Scheduler& s) : scheduler_(s) { s.addTask(kId, *this); }
  void run(fw::sched::EventMask) override { ++runs; }
  void post() { scheduler_.post(kId, 1); }
  uint32_t runs = 0;

 private:
  fw::sched::Scheduler& scheduler_;
};

class BusThatWakesATask final : public fw::hal::CanBus {
 public:
  BusThatWakesATask(fw::hal::CanBus& bus, Urgent& urgent) : bus_(bus), urgent_(urgent) {}
  // Frames the publisher queued while `urgent` was ready and had not run yet.
  uint32_t queuedAhead = 0;
  uint32_t accepted = 0;

 private:
  fw::Status doSend(const fw::hal::CanFrame& frame) override {
    if (urgent_.runs != runsAtLastFrame_) pending_ = false;
    if (pending_) ++queuedAhead;
    const fw::Status s = bus_.send(frame);
    if (s == fw::Status::Ok) {
      ++accepted;
      pending_ = true;
      runsAtLastFrame_ = urgent_.runs;
      urgent_.post();
    }
    return s;
  }
  bool doReceive(fw::hal::CanFrame& frame) override { return bus_.receive(frame); }
  void doOnEvent(const fw::hal::Notify& notify) override { bus_.onEvent(notify); }
  void doOnReceive(const fw::hal::Notify& notify) override { bus_.onReceive(notify); }
  fw::hal::CanState doState() const override { return bus_.state(); }
  fw::Status doRecover() override { return bus_.recover(); }
  fw::hal::CanCounters doCounters() const override { return bus_.counters(); }

  fw::hal::CanBus& bus_;
  Urgent& urgent_;
  bool pending_ = false;
  uint32_t runsAtLastFrame_ = 0;
};

TEST(CanPublisher, AHigherTaskMadeReadyDuringACycleWaitsForOneFrameAtMost) {
  bsp::host::Harness h;
  bsp::host::SimCan can{h.clock, h.irq, bms::kBitrate, 8};
  Urgent urgent{h.sched};
  BusThatWakesATask bus{can, urgent};
  std::vector<app::BoardSample> boards(4);
  app::PackView view;
  app::PublishStatus status;
  app::FramePlan plan{view, status, fw::ms(300)};
  view.boards = boards;
  view.cellsPerBoard = 16;
  view.tempsPerBoard = 2;
  app::CanPublisher publisher(h.sched, 0, bus, plan, app::CanLayout::Native, fw::ms(100), 10);
  publisher.start();
  h.runFor(
      fw::ms(1050));  // a slow cycle (1 s): 4 boards' cells and temperatures, more than the 8-frame queue
  EXPECT_GT(bus.accepted, 30u);
  EXPECT_EQ(bus.queuedAhead, 0u) << "frames queued by one run while a higher task waited";
  EXPECT_EQ(urgent.runs, bus.accepted);
}

}  // namespace
