// Fuzz target: the BQ769x2/BQ7690x link (firmware/drivers/bq769x2/link.*), driven through its public
// operations over the host BSP's simulated I2C bus, against a device that answers any bytes (including
// NACKs and clock stretches past the bus limit, when the input's first byte allows them).
// Properties checked besides the sanitizers: every started operation reports Done exactly once, within 10 s
// of virtual time (no wait without a bound), and leaves the link idle.
#include <cstdint>
#include <span>

#include "drivers/bq769x2/link.hpp"
#include "fuzz_i2c_target.hpp"

namespace {

namespace drv = fw::drivers::bq769x2;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bms_fuzz::Input in(data, size);
  const uint8_t flags = in.byte();
  bms_fuzz::Bench bench(in, flags, drv::kDefaultAddress);
  drv::LinkConfig config;
  config.crc = (flags & 4) != 0;
  config.retries = static_cast<uint8_t>((flags >> 3) & 3);
  config.maxPolls = static_cast<uint8_t>(1 + ((flags >> 5) & 7));
  drv::Link link(bench.bus, bench.context(), config);
  bms_fuzz::DriverTask<drv::Link> task(link);
  bench.harness.sched.addTask(bms_fuzz::Bench::kTask, task);

  for (int op = 0; op < 4 && !in.empty(); ++op) {
    const uint8_t what = in.byte() % 5;
    uint8_t bytes[drv::kMaxWriteData + 2] = {};
    const uint8_t n = in.byte();  // any length: the link refuses the ones it cannot send
    for (uint8_t& b : bytes)
      b = in.byte();
    const std::span<const uint8_t> payload(bytes, n < sizeof bytes ? n : sizeof bytes);
    fw::Status started = fw::Status::InvalidArgument;
    switch (what) {
      case 0:
        started = link.startRead(in.byte(), n, static_cast<uint8_t>(in.byte() % 64), fw::us(in.byte()));
        break;
      case 1:
        started = link.startWrite(in.byte(), payload);
        break;
      case 2:
        started = link.startSubcommand(in.word(), in.flag());
        break;
      case 3:
        started = link.startSubcommandRead(in.word(), n);
        break;
      default:
        started = link.startSubcommandWrite(in.word(), payload);
        break;
    }
    if (started != fw::Status::Ok) continue;
    bench.finish(link, task, fw::s(10));
    if (link.result() == fw::Status::Ok && what == 3) {
      // A validated result: its bytes are readable and the reported length is a buffer length.
      unsigned sum = 0;
      for (uint8_t i = 0; i < n; ++i)
        sum += link.data()[i];
      if (link.reported() > drv::kBufferBytes) __builtin_trap();
      (void)sum;
    }
  }
  return 0;
}
