// Fuzz target: the BQ4050 gauge driver (firmware/drivers/bq4050/gauge.*), driven through its public
// operations over the host BSP's simulated SMBus (100 kHz, 25 ms stretch limit as on the board), against a
// device that answers any bytes (NACKs and long stretches when the input's first byte allows them).
// Properties checked besides the sanitizers: every started operation reports Done exactly once within 60 s
// of virtual time and the driver is idle again within 5 s after that (a bus transaction that outlived the
// driver's guard completes); a block read never reports more bytes than its buffer holds.
#include <cstdint>
#include <span>

#include "drivers/bq4050/gauge.hpp"
#include "fuzz_i2c_target.hpp"

namespace {

namespace bq = fw::drivers::bq4050;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bms_fuzz::Input in(data, size);
  const uint8_t flags = in.byte();
  bms_fuzz::Bench bench(in, flags, bq::kAddress, bsp::host::SimI2cConfig{100000, fw::ms(25), fw::us(4)});
  bq::GaugeConfig config;
  config.pec = static_cast<bq::PecMode>(((flags >> 2) & 3) % 3);
  config.cells = static_cast<uint8_t>(1 + ((flags >> 4) & 3));
  config.retries = static_cast<uint8_t>((flags >> 6) & 3);
  bq::Gauge gauge(bench.bus, bench.harness.clock, bench.context(), config);
  bms_fuzz::DriverTask<bq::Gauge> task(gauge);
  bench.harness.sched.addTask(bms_fuzz::Bench::kTask, task);

  bq::Measurement m;
  bq::DeviceInfo info;
  bq::FetState fets;
  uint16_t word = 0;
  uint8_t block[bq::kMaxBlock] = {};
  uint8_t length = 0;
  for (int op = 0; op < 3 && !in.empty(); ++op) {
    const uint8_t what = in.byte() % 10;
    const uint8_t cmd = in.byte();
    const uint16_t sub = in.word();
    const size_t room = in.byte() % (sizeof block + 1);  // a buffer of any size up to 32
    const std::span<uint8_t> out(block, room);
    length = 0;
    fw::Status started = fw::Status::InvalidArgument;
    switch (what) {
      case 0:
        started = gauge.startProbe(info);
        break;
      case 1:
        started = gauge.startScan(m);
        break;
      case 2:
        started = gauge.startReadWord(cmd, word);
        break;
      case 3:
        started = gauge.startWriteWord(cmd, sub);
        break;
      case 4:
        started = gauge.startReadBlock(cmd, out, length);
        break;
      case 5:
        started = gauge.startWriteBlock(cmd, std::span<const uint8_t>(block, room));
        break;
      case 6:
        started = gauge.startReadMac(sub, out, length);
        break;
      case 7:
        started = gauge.startReadMacData(sub, out, length);
        break;
      case 8:
        started = gauge.startSendMac(sub);
        break;
      default:
        started = gauge.startFetControl(
            bq::FetRequest::manual((cmd & 1) != 0, (cmd & 2) != 0, (cmd & 4) != 0), fets);
        break;
    }
    if (started != fw::Status::Ok) continue;
    bench.finish(gauge, task, fw::s(60), fw::s(5));
    if ((what == 4 || what == 6 || what == 7) && gauge.result() == fw::Status::Ok && length > room)
      __builtin_trap();
  }
  return 0;
}
