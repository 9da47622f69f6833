// Instructions per 100 ms cycle of the lp-mspm0l1306-bq76952 application on ARMv6-M under QEMU.
//
// What runs is the image's own code: its main() (bsp/mspm0/images/common/main.cpp), its appInit()
// (images/<preset>/app_init.cpp) and every firmware source they use, compiled with the image's definitions
// (tests/qemu/CMakeLists.txt). Only the board is replaced, by stand-ins that behave like the LaunchPad's
// peripherals seen from the firmware:
//   clock     virtual microseconds; the scheduler's wake-up request is the alarm
//   I2C0      a BQ76952 (bq76952_responder.hpp) whose list completes after its 400 kHz wire time
//   UART0     SLCAN output whose write completes after its 115 200 Bd wire time
//   ALERT     an edge input that never fires (no fault in this run)
//   watchdog  counts feeds
// Time advances only when the scheduler goes idle: the idle probe (FW_SCHED_IDLE_PROBE, called with
// interrupts masked right before WFI) moves virtual time to the earliest pending completion or alarm and
// pends that stand-in's interrupt, so the WFI returns at once and its handler runs: no instruction is spent
// sleeping, and SysTick (insn_counter.hpp) counts exactly the instructions executed.
//
// The count starts at the 1 s boundary (start-up over) and covers kCycles scan periods. It includes the
// stand-ins' own instructions (a byte copy per transferred byte, a few per completion): a few hundred per
// cycle, the same before and after a firmware change. Output: REPORT app.<image>.insns_per_cycle, and the
// I2C transactions and SLCAN bytes per cycle that show the cycle did its work.
#include <cstdint>

#include "board.hpp"
#include "bq76952_responder.hpp"
#include "common/startup_info.hpp"
#include "core/time.hpp"
#include "insn_counter.hpp"
#include "qtest.hpp"
#include "scs.hpp"
#include "semihosting.hpp"

namespace {

constexpr unsigned kIrqClock = 20, kIrqI2c = 21, kIrqSerial = 22;
constexpr fw::Duration kCycle = fw::ms(100);
constexpr uint32_t kWarmupCycles = 10;
constexpr uint32_t kCycles = 100;

class VirtualClock final : public fw::hal::Clock {
 public:
  uint32_t t = 0;
  uint32_t alarm = 0;
  bool alarmSet = false;

 private:
  fw::Instant doNow() const override { return fw::Instant{t}; }
  void doWakeAt(fw::Instant deadline) override {
    alarm = deadline.us;
    alarmSet = true;
  }

 public:
  void fire() { wakeFired(); }  // the alarm's handler
};

// The back-channel both ways; nothing arrives from the PC in the benchmark (no commands).
class SerialStandIn final : public fw::hal::SerialPort {
 public:
  explicit SerialStandIn(const VirtualClock& clock) : clock_(clock) {}
  bool pending = false;
  uint32_t dueAt = 0;
  uint32_t bytes = 0;
  fw::hal::Notify done;

 private:
  fw::Status doWrite(std::span<const uint8_t> data, const fw::hal::Notify& notify) override {
    if (pending) return fw::Status::Busy;
    if (data.empty()) return fw::Status::InvalidArgument;
    bytes += static_cast<uint32_t>(data.size());
    dueAt = clock_.t + static_cast<uint32_t>(data.size()) * 87;  // 10 bits at 115 200 Bd
    done = notify;
    pending = true;
    return fw::Status::Ok;
  }
  bool doRead(uint8_t&) override { return false; }
  void doOnReceive(const fw::hal::Notify&) override {}
  uint32_t doLost() const override { return 0; }
  const VirtualClock& clock_;
};

class SystemStandIn final : public fw::hal::SystemControl {
  fw::hal::ChipIdentity doIdentity() const override { return {0x13060001, 0xBB82, 0}; }
  void doEnterBootloader() override {}
};

class AlertStandIn final : public fw::hal::EdgeInput {
  void doEnable(const fw::hal::Notify&) override {}
  void doDisable() override {}
  bool doLevel() const override { return true; }  // released (pulled up)
};

class WatchdogStandIn final : public fw::hal::Watchdog {
 public:
  uint32_t feeds = 0;

 private:
  void doFeed() override { ++feeds; }
};
WatchdogStandIn gWatchdog;

VirtualClock gClock;
qbench::Bq76952Responder gI2c(gClock);
SerialStandIn gSerial(gClock);
AlertStandIn gAlert;
SystemStandIn gSystem;
image::Board gBoard{gClock, gWatchdog, gI2c, gAlert, gSerial, gSystem};

// The measurement, advanced at each cycle boundary the virtual time reaches.
struct Meter {
  qbench::InsnCounter counter;
  uint32_t boundary = kCycle.us;
  uint32_t cycle = 0;
  uint64_t startCounts = 0;
  uint32_t startTransactions = 0, startBytes = 0, startFeeds = 0;

  uint32_t feeds() const { return gWatchdog.feeds; }

  // Every instruction of the cycles before `boundary` has run.
  void onBoundary() {
    ++cycle;
    const uint64_t counts = counter.read();
    if (cycle == kWarmupCycles) {
      startCounts = counts;
      startTransactions = gI2c.transactions();
      startBytes = gSerial.bytes;
      startFeeds = feeds();
    } else if (cycle == kWarmupCycles + kCycles) {
      finish(counts);
    }
  }

  [[noreturn]] void finish(uint64_t counts) {
    const uint32_t transactions = gI2c.transactions() - startTransactions;
    const uint32_t bytes = gSerial.bytes - startBytes;
    // The cycles did the application's work: a scan (4 block reads) and SLCAN output every period, and the
    // watchdog fed (every 250 ms).
    QCHECK(transactions >= 4 * kCycles);
    QCHECK(bytes >= kCycles * 10);
    QCHECK(feeds() - startFeeds >= kCycles / 3);
    qbench::reportCenti("app." BENCH_IMAGE ".insns_per_cycle",
                        qbench::InsnCounter::centiInsnPer(counts - startCounts, kCycles));
    qbench::reportCenti("app." BENCH_IMAGE ".i2c_transactions_per_cycle", transactions * 100 / kCycles);
    qbench::reportCenti("app." BENCH_IMAGE ".slcan_bytes_per_cycle", bytes * 100 / kCycles);
    bsp::qemu::exit(qtest::finish("qemu_app_cycle_bench"));
  }
};
Meter gMeter;

}  // namespace

namespace image {
Board& board() {
  return gBoard;
}
void bringUp() {
  for (unsigned irq : {kIrqClock, kIrqI2c, kIrqSerial})
    bsp::scs::nvicEnable(irq);
  gMeter.counter.start();
}
fw::app::StartupInfo startupInfo(uint8_t) {
  return {};  // the stand-in board has no reset cause to report
}
}  // namespace image

// The scheduler is idle with interrupts masked: advance virtual time to the next event and pend its
// interrupt (no event at all would be a hang: fail).
extern "C" void fw_sched_idle_probe() {
  unsigned irq = kIrqClock;
  uint32_t next = 0;
  bool any = false;
  auto consider = [&](bool pending, uint32_t at, unsigned line) {
    if (pending && (!any || fw::isBefore(fw::Instant{at}, fw::Instant{next}))) {
      next = at, irq = line, any = true;
    }
  };
  consider(gI2c.pending(), gI2c.dueAt(), kIrqI2c);
  consider(gSerial.pending, gSerial.dueAt, kIrqSerial);
  consider(gClock.alarmSet, gClock.alarm, kIrqClock);
  if (!any) {
    QCHECK(any);
    bsp::qemu::exit(qtest::finish("qemu_app_cycle_bench"));
  }
  while (!fw::isBefore(fw::Instant{next}, fw::Instant{gMeter.boundary})) {
    gMeter.onBoundary();
    gMeter.boundary += kCycle.us;
  }
  if (fw::isBefore(fw::Instant{gClock.t}, fw::Instant{next})) gClock.t = next;
  if (irq == kIrqClock) gClock.alarmSet = false;
  bsp::scs::nvicSetPending(irq);
}

extern "C" void Irq20_Handler() {  // the alarm: the scheduler's loop finds the due timers
  gClock.fire();
}
extern "C" void Irq21_Handler() {
  gI2c.complete();
}
extern "C" void Irq22_Handler() {
  gSerial.pending = false;
  gSerial.done();
}
