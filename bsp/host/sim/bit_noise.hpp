// BitNoise: noise on a UART line (bms-sim's `uart-noise <ppm>` step): each bit of an 8N1 frame - start bit,
// eight data bits, stop bit - is flipped with probability ppm / 1 000 000, independently, from a fixed-seed
// generator so every run of a scenario sees the same errors. What the receiver then samples:
//   a data bit flipped   the byte arrives with that bit wrong;
//   the stop bit flipped the byte arrives with a framing error (its stop bit reads 0);
//   the start bit flipped the receiver sees no start edge there: it synchronises on the first falling edge of
//                        the data instead; modelled as a framing error on that byte (the frame is lost).
// 0 ppm is a clean line.
#pragma once

#include <cstdint>

namespace bsp::host {

class BitNoise {
 public:
  void setPpm(uint32_t ppm) { ppm_ = ppm > 1000000 ? 1000000 : ppm; }
  uint32_t ppm() const { return ppm_; }

  // The byte as the receiver takes it; framingError is set (never cleared) when the frame is lost.
  uint8_t pass(uint8_t byte, bool& framingError) {
    if (ppm_ == 0) return byte;
    for (int bit = 0; bit < 10; ++bit) {
      if (next() % 1000000 >= ppm_) continue;
      ++flipped_;
      if (bit == 0 || bit == 9) {
        framingError = true;
      } else {
        byte = static_cast<uint8_t>(byte ^ (1U << (bit - 1)));
      }
    }
    return byte;
  }
  uint64_t flipped() const { return flipped_; }

 private:
  uint64_t next() {  // xorshift64* (Marsaglia 2003, Vigna 2014)
    state_ ^= state_ >> 12;
    state_ ^= state_ << 25;
    state_ ^= state_ >> 27;
    return (state_ * 0x2545F4914F6CDD1DULL) >> 16;
  }

  uint32_t ppm_ = 0;
  uint64_t state_ = 0x9E3779B97F4A7C15ULL;
  uint64_t flipped_ = 0;
};

}  // namespace bsp::host
