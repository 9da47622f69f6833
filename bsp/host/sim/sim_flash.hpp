// SimFlash: a host FlashStorage in RAM for tests and the host simulator, with a power-cut injector.
//
// Contract
// - Enforces hal/flash.hpp: erased bytes read 0xFF; program() into a word that is not all 0xFF, or at an
//   offset outside the region or not word-aligned, returns InvalidArgument and changes nothing.
// - Power cut: cutAtProgram(n) makes the n-th program call from now (0-based) the one during which power
//   fails: that word is left torn (see Tear) and it and every later call return Aborted until powerOn().
//   cutAtErase(n) does the same for the n-th erase: the sector is left partly erased (each word either
//   erased, or its old value with random bits set, as a cut erase can leave it).
// - failNext(status, skip) makes the program or erase after the next `skip` ones return `status` (Timeout or
//   VerifyFailed) without changing the flash, as a controller that did not report completion would.
// - Counts of programs and erases (per sector) for wear tests; load()/save() of the image to a file.
// - Randomness from a seeded generator: every run is reproducible.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hal/flash.hpp"

namespace bsp::host {

// The image is a base, built before FlashStorage, which is given its address (base-from-member).
struct SimFlashImage {
  std::vector<uint8_t> image_;
};

class SimFlash final : private SimFlashImage, public fw::hal::FlashStorage {
 public:
  // How the word being programmed reads after the cut.
  enum class Tear : uint8_t {
    Erased,    // nothing took
    Partial,   // some of the word's programmed (0) bits took, the others still read 1
    Random,    // any value
    Complete,  // it took entirely
  };

  explicit SimFlash(uint32_t sectors, uint64_t seed = 1);

  void cutAtProgram(uint32_t n, Tear tear);
  void cutAtErase(uint32_t n);
  void powerOn();
  bool powerLost() const { return powerLost_; }
  void failNext(fw::Status status, uint32_t skip = 0) {
    failNext_ = status;
    failSkip_ = skip;
  }

  uint32_t programCount() const { return programs_; }
  uint32_t eraseCount() const { return erases_; }
  uint32_t eraseCount(uint32_t sector) const { return sectorErases_.at(sector); }
  std::span<uint8_t> image() { return image_; }

  bool load(const std::string& path);
  bool save(const std::string& path) const;

 private:
  fw::Status doErase(uint32_t sector) override;
  fw::Status doProgram(uint32_t offset, std::span<const uint8_t, kWordBytes> word) override;
  uint64_t random();

  static constexpr uint32_t kNever = 0xFFFFFFFF;
  uint32_t sectors_;
  std::vector<uint32_t> sectorErases_;
  uint64_t rng_;
  uint32_t programs_ = 0;
  uint32_t erases_ = 0;
  uint32_t cutProgram_ = kNever;
  uint32_t cutErase_ = kNever;
  Tear tear_ = Tear::Partial;
  bool powerLost_ = false;
  fw::Status failNext_ = fw::Status::Ok;
  uint32_t failSkip_ = 0;
};

}  // namespace bsp::host
