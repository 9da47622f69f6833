// Fault and assert handling with module ids (design by contract, in the manner of QP's numbered asserts).
//
// Contract
// - FW_ASSERT(cond) is for programming errors only (a broken precondition, an impossible state), never for
//   conditions the outside world can cause: a NACK, a bad CRC or a full queue is a Status, not an assert.
// - Each source file names its module once with FW_MODULE(Module::X); a failed assert calls
//   fw::onFault(module, line), which the BSP implements: on MSPM0 it records (module, line) in a
//   no-init RAM word and resets; under QEMU it prints and exits with a failure code; on the host it reports
//   and aborts (so gtest death tests can see it).
// - onFault never returns. Safe to call from an ISR.
#pragma once

#include <cstdint>

namespace fw {

enum class Module : uint8_t {
  Core = 1,
  Sched = 2,
  Hal = 3,
  DriverBq769x2 = 10,
  DriverBq79616 = 11,
  DriverBq4050 = 12,
  App = 20,
  Protection = 21,
  Publish = 22,
  Bsp = 30,
  BspI2c = 31,
  BspUart = 32,
  BspCan = 33,
  Test = 99,
};

// Implemented by the BSP. `line` identifies the check within its module.
[[noreturn]] void onFault(Module module, uint16_t line);

}  // namespace fw

#define FW_ASSERT_MODULE(module, cond)                                     \
  do {                                                                     \
    if (!(cond)) ::fw::onFault((module), static_cast<uint16_t>(__LINE__)); \
  } while (0)

// Declares the module of the current .cpp file; FW_ASSERT then uses it.
#define FW_MODULE(module) [[maybe_unused]] static constexpr ::fw::Module kFwThisModule = (module)
#define FW_ASSERT(cond) FW_ASSERT_MODULE(kFwThisModule, cond)
