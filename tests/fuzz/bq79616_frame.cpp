// Fuzz target: the BQ79616 frame codec (firmware/drivers/bq79616/frame.*). The input names a read (register,
// register count) and then holds the bytes the device answered; parseResponse() must accept them only as a
// whole, intact frame for that read. The encoders get arbitrary arguments: they either refuse (0) or write a
// frame that fits the protocol's limits, and a read frame they write is one the frame's own CRC covers.
// Properties checked besides the sanitizers: an accepted frame's data lies inside the input and has the
// count asked for; encoded frames are at most kMaxCommandBytes long and end in a CRC that checks.
#include <cstdint>
#include <span>

#include "core/crc.hpp"
#include "drivers/bq79616/frame.hpp"
#include "fuzz_input.hpp"

namespace {

namespace drv = fw::drivers::bq79616;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bms_fuzz::Input in(data, size);
  const uint16_t reg = in.word();
  const size_t count = in.byte();  // 0 and > 128 included: parseResponse() must cope
  const uint8_t typeByte = in.byte();
  const uint8_t device = in.byte();
  uint8_t writeData[drv::kMaxWriteBytes + 1] = {};
  for (uint8_t& b : writeData)
    b = in.byte();
  const std::span<const uint8_t> response(in.rest(), in.restSize());

  drv::ResponseFrame frame{};
  if (drv::parseResponse(response, reg, count, frame) == fw::Status::Ok) {
    const bool inside = frame.data.data() >= response.data() &&
                        frame.data.data() + frame.data.size() <= response.data() + response.size();
    if (!inside || frame.data.size() != count || frame.reg != reg) __builtin_trap();
  }

  const auto type = static_cast<drv::RequestType>(typeByte % 8);
  uint8_t out[drv::kMaxCommandBytes + 4];
  const size_t n =
      typeByte & 0x80
          ? drv::encodeRead(type, device, reg, count, out)
          : drv::encodeWrite(type, device, reg, std::span<const uint8_t>(writeData, typeByte % 10), out);
  if (n > drv::kMaxCommandBytes) __builtin_trap();
  if (n != 0 && fw::crc::crc16(out, n) != 0) __builtin_trap();
  return 0;
}
