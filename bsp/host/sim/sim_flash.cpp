// The host flash model: contract checks of hal/flash.hpp and the torn states a power cut can leave.
#include "sim/sim_flash.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>

namespace bsp::host {

SimFlash::SimFlash(uint32_t sectors, uint64_t seed)
    : SimFlashImage{std::vector<uint8_t>(sectors * kSectorBytes, kErased)},
      FlashStorage(image_.data(), sectors),
      sectors_(sectors),
      sectorErases_(sectors, 0),
      rng_(seed | 1) {}

uint64_t SimFlash::random() {
  // xorshift64: reproducible and good enough to pick torn bits.
  rng_ ^= rng_ << 13;
  rng_ ^= rng_ >> 7;
  rng_ ^= rng_ << 17;
  return rng_;
}

void SimFlash::cutAtProgram(uint32_t n, Tear tear) {
  cutProgram_ = n;
  tear_ = tear;
}

void SimFlash::cutAtErase(uint32_t n) {
  cutErase_ = n;
}

void SimFlash::powerOn() {
  powerLost_ = false;
  cutProgram_ = kNever;
  cutErase_ = kNever;
}

fw::Status SimFlash::doErase(uint32_t sector) {
  if (powerLost_) return fw::Status::Aborted;
  if (sector >= sectors_) return fw::Status::InvalidArgument;
  if (failNext_ != fw::Status::Ok && failSkip_-- == 0) {
    const fw::Status s = failNext_;
    failNext_ = fw::Status::Ok;
    return s;
  }
  uint8_t* base = image_.data() + sector * kSectorBytes;
  if (cutErase_ == 0) {
    // A cut erase: each word either got erased or only some of its bits went to 1.
    powerLost_ = true;
    for (uint32_t w = 0; w < kSectorBytes; w += kWordBytes) {
      const uint64_t r = random();
      for (uint32_t i = 0; i < kWordBytes; ++i)
        base[w + i] = (r & 1) ? kErased : static_cast<uint8_t>(base[w + i] | (r >> (8 * i + 1)));
    }
    ++sectorErases_[sector];
    return fw::Status::Aborted;
  }
  if (cutErase_ != kNever) --cutErase_;
  for (uint32_t i = 0; i < kSectorBytes; ++i)
    base[i] = kErased;
  ++erases_;
  ++sectorErases_[sector];
  return fw::Status::Ok;
}

fw::Status SimFlash::doProgram(uint32_t offset, std::span<const uint8_t, kWordBytes> word) {
  if (powerLost_) return fw::Status::Aborted;
  if (offset % kWordBytes != 0 || offset + kWordBytes > image_.size()) return fw::Status::InvalidArgument;
  uint8_t* target = image_.data() + offset;
  for (uint32_t i = 0; i < kWordBytes; ++i)
    if (target[i] != kErased) return fw::Status::InvalidArgument;
  if (failNext_ != fw::Status::Ok && failSkip_-- == 0) {
    const fw::Status s = failNext_;
    failNext_ = fw::Status::Ok;
    return s;
  }
  if (cutProgram_ == 0) {
    powerLost_ = true;
    const uint64_t r = random();
    for (uint32_t i = 0; i < kWordBytes; ++i) {
      const uint8_t bits = static_cast<uint8_t>(r >> (8 * i));
      switch (tear_) {
        case Tear::Erased:
          break;
        case Tear::Partial:
          target[i] = static_cast<uint8_t>(word[i] | bits);
          break;
        case Tear::Random:
          target[i] = bits;
          break;
        case Tear::Complete:
          target[i] = word[i];
          break;
      }
    }
    return fw::Status::Aborted;
  }
  if (cutProgram_ != kNever) --cutProgram_;
  for (uint32_t i = 0; i < kWordBytes; ++i)
    target[i] = word[i];
  ++programs_;
  return fw::Status::Ok;
}

bool SimFlash::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::vector<uint8_t> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.size() != image_.size()) return false;
  std::copy(data.begin(), data.end(), image_.begin());  // in place: FlashStorage reads at its address
  return true;
}

bool SimFlash::save(const std::string& path) const {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(image_.data()), static_cast<std::streamsize>(image_.size()));
  return static_cast<bool>(out);
}

}  // namespace bsp::host
