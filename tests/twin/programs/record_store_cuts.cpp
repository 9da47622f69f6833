// The record store (firmware/app/store/record_store.cpp) on the FLASHCTL driver (bsp/mspm0/flashctl.cpp),
// built for the MSPM0 with the product's start-up and linker script, for the power-cut sweep of
// flashctl_test.cpp (issue 30: a cut at every instruction of a record write).
//
// Each boot: restore the store and report what it holds (kFound, one word per type: the value of the
// newest record, 0 none; kBad counts records whose payload is not the one written for their value), then
// write two records, the first of which the test sweeps (kSweeping is kMark + 1 around it), then kPhase is
// kMark + 2.
// The records cycle through kTypes types; record v carries v in its first word and a payload of
// 8 + 8 * (v % 8) bytes, each byte following from v, so a record read back is either exactly one that was
// written or counted in kBad. kCommitted holds, per type, the value of the last write that returned Ok;
// kInFlight the value being written (0 none): a cut between the two leaves either in the flash.
#include <cstdint>
#include <span>

#include "app/store/record_store.hpp"
#include "bare_program.hpp"
#include "flashctl.hpp"

extern "C" {
extern const uint8_t __record_store_start__[], __record_store_end__[];
}

constexpr uint8_t kTypes = 3;
// kPhase and kSweeping hold kMark + n: SRAM holds a pattern until the start-up zeroes .bss, and after a
// power cut, so a plain 1 or 2 could be read before the program wrote it.
constexpr uint32_t kMark = 0xC0DE0000;
volatile uint32_t kPhase;  // kMark + 1: restored (kRestore, kFound, kBad set); kMark + 2: both writes done
volatile uint32_t kRestore;
volatile uint32_t kFound[kTypes];
volatile uint32_t kBad;
volatile uint32_t kSweeping;
volatile uint32_t kCommitted[kTypes];
volatile uint32_t kInFlight[kTypes];
volatile uint32_t kWrites[2];  // the two writes' results (fw::Status values)

namespace {

using fw::app::store::RecordStore;

uint32_t lengthOf(uint32_t value) {
  return 8 + 8 * (value % 8);
}

void fill(uint32_t value, uint8_t* payload) {
  for (uint32_t i = 0; i < lengthOf(value); ++i)
    payload[i] = static_cast<uint8_t>(i < 4 ? value >> (8 * i) : value * 7 + i);
}

// The value of the record read, or 0 and kBad counted when its bytes are not the ones written for it.
uint32_t valueOf(const uint8_t* payload, uint32_t length) {
  const uint32_t value =
      payload[0] | payload[1] << 8 | payload[2] << 16 | static_cast<uint32_t>(payload[3]) << 24;
  uint8_t expect[RecordStore::kMaxPayload];
  fill(value, expect);
  bool same = length == lengthOf(value);
  for (uint32_t i = 0; same && i < length; ++i)
    same = payload[i] == expect[i];
  if (!same) kBad = kBad + 1;
  return same ? value : 0;
}

fw::Status writeOne(RecordStore& store, uint32_t value) {
  const uint8_t type = static_cast<uint8_t>(value % kTypes);
  uint8_t payload[RecordStore::kMaxPayload];
  fill(value, payload);
  const std::span<const uint8_t> bytes(payload, lengthOf(value));
  kInFlight[type] = value;
  fw::Status status = store.write(type, bytes);
  if (status == fw::Status::Busy) {  // a compaction is due and no sector is erased: erase one, then write
    status = store.eraseStep();
    if (status == fw::Status::Ok) status = store.write(type, bytes);
  }
  if (status == fw::Status::Ok) kCommitted[type] = value;
  kInFlight[type] = 0;
  return status;
}

}  // namespace

int main() {
  const auto start = reinterpret_cast<uintptr_t>(__record_store_start__);
  const auto sectors = static_cast<uint32_t>(__record_store_end__ - __record_store_start__) / 1024;
  bsp::mspm0::FlashctlStorage flash(
      {0x400CD000, static_cast<uint32_t>(start), __record_store_start__, sectors, FLASH_ECC != 0, 32});
  RecordStore store(flash);
  kRestore = static_cast<uint32_t>(store.restore());
  uint32_t newest = 0;
  for (uint8_t type = 0; type < kTypes; ++type) {
    uint8_t payload[RecordStore::kMaxPayload];
    uint32_t length = 0;
    kFound[type] = store.read(type, payload, length) == fw::Status::Ok ? valueOf(payload, length) : 0;
    kCommitted[type] = kFound[type];
    if (kFound[type] > newest) newest = kFound[type];
  }
  kPhase = kMark + 1;
  kSweeping = kMark + 1;
  kWrites[0] = static_cast<uint32_t>(writeOne(store, newest + 1));
  kSweeping = kMark;
  kWrites[1] = static_cast<uint32_t>(writeOne(store, newest + 2));
  kPhase = kMark + 2;
  for (;;) {
  }
}
