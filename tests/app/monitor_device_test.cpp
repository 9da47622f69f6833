// MonitorDevice (app/monitors/monitor_task.hpp): a device that keeps the contract satisfies it, and a device
// that lacks a hook, or gives one another type, fails the part that names that hook. The real devices are
// held to it where MonitorTask<Device> is built (every application and image).
#include <gtest/gtest.h>

#include "app/monitors/monitor_task.hpp"

namespace fw::app {
namespace {

struct FakeDriver {
  bool busy() const { return false; }
  Status result() const { return Status::Ok; }
  drivers::Progress onEvent(sched::EventMask) { return drivers::Progress::Done; }
};

// Every hook, protected as in the real devices.
class GoodDevice : public MonitorBase {
 public:
  GoodDevice(sched::Scheduler& scheduler, PackView& view) : scheduler_(scheduler), view_(view) {}

 protected:
  static constexpr bool kCommands = false;
  static constexpr bool kFaultLineToo = false;
  static constexpr sched::EventMask kPublisherScanDone = 0;
  Duration scanPeriod() const { return ms(100); }
  Duration firstDataBound() const { return ms(200); }
  static constexpr sched::EventMask driverEvents() { return 1; }
  Status startSetup() { return Status::Ok; }
  void setupFinished(Status) {}
  Status startScan() { return Status::Ok; }
  ScanVerdict scanFinished(Status, Instant) { return {}; }
  void afterSummarize() {}
  void recover() {}

  struct Records {
    ScanStats stats;
    sched::Timer scanTimer;
  };
  sched::Scheduler& scheduler_;
  PackView& view_;
  Zeroed<Records> records_;
  FakeDriver driver_;
};

// Without recover().
class NoRecover : public GoodDevice {
 protected:
  void recover() = delete;
};
// startScan() that answers bool instead of a Status.
class BoolScan : public GoodDevice {
 protected:
  bool startScan() { return true; }
};
// kCommands without the command hooks.
class CommandsWithoutHooks : public GoodDevice {
 protected:
  static constexpr bool kCommands = true;
};
// kFaultLineToo without faultLine().
class FaultLineWithoutHook : public GoodDevice {
 protected:
  static constexpr bool kFaultLineToo = true;
};
// kBalancing without balanceCheck(), and with it.
class BalancingWithoutHook : public GoodDevice {
 protected:
  static constexpr bool kBalancing = true;
};
class BalancingWithHook : public BalancingWithoutHook {
 protected:
  void balanceCheck() {}
};
// Not a MonitorBase: the loop's own state is missing.
struct NotABase {};

TEST(MonitorDevice, ADeviceWithEveryHookSatisfiesIt) {
  static_assert(MonitorDevice<GoodDevice>);
  static_assert(MonitorDevice<BalancingWithHook>);
  static_assert(sizeof(MonitorTask<GoodDevice>) > 0);
}

TEST(MonitorDevice, AMissingOrMistypedHookFailsThePartThatNamesIt) {
  static_assert(!MonitorDevice<NoRecover> && !DeviceHooks<NoRecover>::setupScanHooks());
  static_assert(!MonitorDevice<BoolScan> && !DeviceHooks<BoolScan>::setupScanHooks());
  static_assert(!MonitorDevice<CommandsWithoutHooks> && !DeviceHooks<CommandsWithoutHooks>::commandHooks());
  static_assert(!MonitorDevice<FaultLineWithoutHook> && !DeviceHooks<FaultLineWithoutHook>::faultLineHook());
  static_assert(!MonitorDevice<BalancingWithoutHook> && !DeviceHooks<BalancingWithoutHook>::balancingHook());
  static_assert(!MonitorDevice<NotABase>);
  // The other parts of each still hold: only the named one fails.
  static_assert(DeviceHooks<NoRecover>::fieldHooks() && DeviceHooks<NoRecover>::constantHooks());
  static_assert(DeviceHooks<CommandsWithoutHooks>::setupScanHooks());
}

}  // namespace
}  // namespace fw::app
