// Fuzz target: the command path (firmware/app/command): random SLCAN text through the adapter and random
// CAN frames through the handler, with protection, the limit settings and the chip identity of a host board
// behind them (the scheduler runs protection after each frame, as on the images).
// Input: a flags byte (bit 0: SLCAN text, else frames; bit 1: give each frame its right CRC, so the checks
// past the CRC are reached), then the text, or per frame: identifier (2 bytes, 11 bits), DLC (0..15, above 8
// refused as on the wire), 8 data bytes.
// Properties besides the sanitizers: every answer is at most three standard 8-byte frames at 0x580..0x584,
// CommandAck first; an SLCAN answer is CR, BEL, z/Z + CR, or a V/N/F answer; a frame that was not accepted
// changes nothing (the limits, the paths held off, bootloader entry; a bootloader entry taken up is valid
// before it is answered); the limits never leave their ranges and
// each clear value stays on its trip value's safe side.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "app/command/e2e.hpp"
#include "app/command/handler.hpp"
#include "app/command/settings.hpp"
#include "app/command/slcan_adapter.hpp"
#include "app/protection/default_limits.hpp"
#include "app/protection/protection_task.hpp"
#include "fuzz_input.hpp"
#include "sim/harness.hpp"
#include "sim/peripherals.hpp"

namespace {

using namespace fw::app;
using namespace fw::app::command;

void check(bool ok) {
  if (!ok) std::abort();
}

// Stands in for the command task (the handler's bootloader timer posts to it); the handler is driven
// directly.
struct IdleTask final : fw::sched::Task {
  void run(fw::sched::EventMask) override {}
};

struct Rig {
  bsp::host::Harness h;
  IdleTask commandTask;
  bsp::host::SimDigitalOut pin{h.clock, true};
  bsp::host::SimSystem system{h.clock};
  fw::Zeroed<PackView> view;
  fw::Zeroed<PublishStatus> status;
  FaultPinActuator actuator{pin, true};
  LimitSettings settings{kDefaultLimits};
  ProtectionTask protection{h.sched, kProtectionTask, settings.limits(), *view,
                            *status, actuator,        fw::ms(100)};
  CommandHandler handler{{h.sched, protection, settings, system, 1}};
  SlcanAdapter adapter;

  Rig() {
    protection.setLimitUpdate(settings);
    protection.start();
    h.sched.addTask(kCommandTask, commandTask);
  }

  void limitsHold() const {
    for (uint8_t id = 0; id < kSettingCount; id += 2) {
      const SettingSpec trip = settings.spec(id), clear = settings.spec(static_cast<uint8_t>(id + 1));
      const int32_t t = settings.read(id), c = settings.read(static_cast<uint8_t>(id + 1));
      check(t >= trip.min && t <= trip.max && c >= clear.min && c <= clear.max);
      check((trip.rule & 1U) == 0 ? c <= t : c >= t);
    }
  }

  void frame(const fw::hal::CanFrame& f) {
    const uint32_t accepted = handler.stats().accepted;
    ProtectionConfig before;
    std::memcpy(&before, &settings.limits(), sizeof before);
    const uint8_t off = handler.hostOff();
    const auto boot = handler.boot();
    Replies r{};
    handler.handle(f, r);
    check(r.count <= Replies::kMax);
    for (uint8_t k = 0; k < r.count; ++k) {
      check(r.frame[k].id >= 0x580 && r.frame[k].id <= 0x584 && r.frame[k].dlc == 8 && !r.frame[k].extended);
      check((k == 0) == (r.frame[k].id == 0x580));
    }
    h.sched.post(kProtectionTask, ProtectionTask::kNewData);  // a scan boundary: waiting writes apply
    h.runUntilIdle();
    limitsHold();
    // A bootloader entry taken up is answered later (once the paths are off): valid, though not yet counted.
    const bool entering = boot == CommandHandler::Boot::Idle && handler.boot() != boot;
    if (handler.stats().accepted == accepted && !entering) {
      check(std::memcmp(&before, &settings.limits(), sizeof before) == 0);
      check(handler.hostOff() == off && handler.boot() == boot);
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bms_fuzz::Input in(data, size);
  const uint8_t flags = in.byte();
  Rig rig;
  if (flags & 1) {
    while (!in.empty()) {
      const uint8_t b = in.byte();
      if (!rig.adapter.take(b)) continue;
      SlcanAdapter::Line line;
      rig.adapter.answer({0x1306, false}, line);
      check(line.answerLength >= 1 && line.answerLength <= SlcanAdapter::kMaxAnswer);
      const uint8_t a = line.answer[0];
      check(a == '\r' || a == 0x07 || a == 'z' || a == 'Z' || a == 'V' || a == 'N' || a == 'F');
      check(line.hasFrame == (a == 'z' || a == 'Z'));
      if (line.hasFrame) rig.frame(line.frame);
    }
    return 0;
  }
  for (int n = 0; n < 64 && !in.empty(); ++n) {
    fw::hal::CanFrame f{};
    f.id = in.word() & 0x7FFU;
    f.dlc = static_cast<uint8_t>(in.byte() & 0x0F);
    for (uint8_t& b : f.data)
      b = in.byte();
    if (f.dlc > 8) continue;  // not a classic CAN frame: the controller takes none
    if (flags & 2) f.data[0] = frameCrc(f.id, f.data.data(), f.dlc);
    rig.frame(f);
  }
  return 0;
}
