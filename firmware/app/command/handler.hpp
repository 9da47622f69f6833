// CommandHandler: checks a received command frame and acts on it (firmware/app/can/bms.yaml, "Commands").
//
// Checks, in order, each refusal answered with CommandAck and counted (rejected(), and per reason):
//   1. the identifier is a command (else it is not one of ours: counted as filtered, no answer; on CAN the
//      MCAN's filter already keeps such frames out);
//   2. the target is this node or 255 (else counted as for another node, no answer);
//   3. the DLC is the message's (wrong_length); 4. the CRC (bad_crc); 5. the alive counter is not a repeat
//      (repeated_counter; the counter is taken once the frame passed 3 and 4);
//   6. the values: a setting id or mode out of range, a write outside its range (out_of_range) or crossing
//      its trip/clear partner (inconsistent); bootloader entry without the key, this node's number and the
//      chip's TraceId (wrong_key); ClearFaults while a latched fault's condition is still there
//      (condition_present: nothing of that fault changes); StorageMode enter while a fault is active
//      (fault_active) or the current is above the pack's rest threshold (not_at_rest), or on an image
//      without storage (unsupported).
// A refused frame changes nothing but the counters and the counter window.
//
// Safety rules (README.md in this folder; tests/app/command_*_test.cpp):
// - No command turns a path on: PathRequest and bootloader entry only add paths to hold off
//   (ProtectionTask::requestOff); what protection holds off stays off.
// - No limit passes its hard bound (LimitSettings), and a write takes effect at a scan boundary, whole.
// - ClearFaults clears the latched faults whose condition is gone (ProtectionTask::clearLatched); it clears
//   nothing else, and while a latched fault's condition is still there it is answered condition_present
//   (that fault stays latched).
// - Bootloader entry: protection first holds both paths off; once the actuator has confirmed them off
//   (within kBootTimeout) the answer is accepted and, once it has left, the MCU restarts into its ROM
//   bootloader. If they are not confirmed off in time the request is answered paths_not_off and the paths
//   are released to what they were. Meanwhile every other command is answered busy.
// Thread mode only (the command task).
#pragma once

#include <cstdint>

#include "app/balancing/balancing_policy.hpp"
#include "app/command/e2e.hpp"
#include "app/command/result.hpp"
#include "app/command/settings.hpp"
#include "app/monitors/storage_mode.hpp"
#include "app/protection/protection_task.hpp"
#include "app/tasks.hpp"
#include "can/bms.hpp"
#include "core/time.hpp"
#include "core/zeroed.hpp"
#include "hal/can_bus.hpp"
#include "hal/system.hpp"
#include "sched/scheduler.hpp"

namespace fw::app::command {

inline constexpr uint8_t kCommandCount = static_cast<uint8_t>(can::bms::kReceivedIds.size());
inline constexpr uint8_t kBroadcast = 255;
inline constexpr uint8_t kBootloaderKey = 0xA5;

// Up to three answer frames: CommandAck in frame[0], then a command's data (Identify, SettingRead).
// The count first: Thumb's byte stores reach it without an address computation.
struct Replies {
  static constexpr uint8_t kMax = 3;
  uint8_t count;
  hal::CanFrame frame[kMax];
};

struct CommandStats {
  uint32_t frames;                     // command frames handed in
  uint32_t accepted;                   // taken and acted on
  uint32_t filtered;                   // not a command identifier (SLCAN: the software filter)
  uint32_t otherTarget;                // for another node
  uint16_t rejected;                   // refused (saturates; also in every CommandAck)
  uint16_t rejectedFor[kResultCount];  // by reason (index: Result)
};

class CommandHandler {
 public:
  static constexpr Duration kBootTimeout = ms(1000);
  static constexpr Duration kPoll = ms(10);  // bootloader entry: how often the command task checks

  struct Context {
    sched::Scheduler& scheduler;
    ProtectionTask& protection;
    LimitSettings& settings;
    hal::SystemControl& system;
    uint8_t node;
  };
  explicit CommandHandler(const Context& context) : ctx_(context) {}
  // The balancing policy BalancingMode sets, and the pack it checks a board and mask against; set once at
  // start-up by the images that balance. Without it BalancingMode is answered Unsupported.
  void setBalancing(BalancingPolicy& policy, const PackView& pack) {
    balancing_ = &policy;
    pack_ = &pack;
  }
  // The monitor's pack-storage mode StorageMode asks (storage_mode.hpp); without it StorageMode is answered
  // Unsupported.
  void setStorage([[maybe_unused]] StorageState& storage) {
#if FW_STORAGE != 0
    storage_ = &storage;
#endif
  }

  // Checks and acts on one received frame; the answers go to `out` (none for a frame not addressed here, or
  // while bootloader entry waits for the paths: poll() answers it).
  void handle(const hal::CanFrame& frame, Replies& out);
  // Bootloader entry: Idle, then WaitingForPaths until poll() answers (Answered once accepted, Idle again
  // when refused), then answerSent() restarts the MCU.
  enum class Boot : uint8_t { Idle, WaitingForPaths, Answered };
  Boot boot() const {
    return state_->boot;
  }
  // While WaitingForPaths: answers into `out` once the paths are confirmed off or the time is up.
  void poll(Replies& out);
  // While Answered, once the accepted answer has left: restarts into the bootloader.
  void answerSent();

  const CommandStats& stats() const {
    return state_->stats;
  }
  uint8_t hostOff() const {
    return state_->hostRequest;
  }
  sched::Scheduler& scheduler() const {
    return ctx_.scheduler;
  }

 private:
  Result act(const hal::CanFrame& f, Replies& out);
  void ack(Replies& out, uint32_t id, uint8_t counter, Result result);
  void applyHostOff();

  // The bytes first: Thumb's byte loads and stores reach 31 bytes past their base, word ones 124.
  struct State {
    uint8_t hostRequest;  // Action bits PathRequest holds off
    Boot boot;
    uint8_t bootCounter;
    CounterWindow<kCommandCount> counters;
    CommandStats stats;
    Instant bootDeadline;
    sched::Timer bootTimer;  // posts command_event::kTimer every kPoll while entering
  };
  Context ctx_;
  BalancingPolicy* balancing_ = nullptr;
  const PackView* pack_ = nullptr;
#if FW_STORAGE != 0
  StorageState* storage_ = nullptr;
#endif
  Zeroed<State> state_;
};

}  // namespace fw::app::command
