// Bq76952Responder: a BQ76952 on an I2C bus for the application benchmark under QEMU (app_cycle_bench.cpp).
//
// The host emulator (bsp/host/emul) uses the heap and std containers; this one is a fixed-size register image
// small enough for the 16 KiB target, deterministic, and answers at once (no subcommand latency):
//   - the 128-byte direct-command space, read and written with auto-increment (0x14..0x33 cells at 3.7 V,
//     stack, pack and LD at 59.2 V, current 0, temperatures 25 degC, FET Status CHG and DSG on);
//   - Alarm Status 0x62 is latched and cleared by writing 1s (SLUUBY2B chapter 12, Alarm Status; SLAAEB3A
//     3.3: "clear those latched bits by writing the 0x62 with a 1");
//   - the subcommand window 0x3E..0x61 (SLUUBY2B 13.1): a 2-byte write of 0x3E runs the subcommand and leaves
//     its result in 0x40.., the checksum in 0x60 and the length in 0x61; a write with data followed by the
//     0x60/0x61 commit writes data memory (0x9180..0x937F), taken only with the right checksum and length
//     (SLUUBY2B 13.1) and only in CONFIG_UPDATE (SLUAA11B section 3: SET_CFGUPDATE before the writes);
//   - DEVICE_NUMBER 0x7695, FW_VERSION, MANUFACTURINGSTATUS with FET_EN (bit 4), FET_ENABLE toggling it,
//     SET_CFGUPDATE / EXIT_CFGUPDATE setting and clearing Battery Status[CFGUPDATE] (bit 0), and any other
//     code accepted as a command without data.
// No CRC mode (the L1306 image's configuration has it off). Every transaction ends Ok.
//
// start() keeps the list; the owner completes it (complete(), from its interrupt handler) at dueAt(), so the
// firmware sees the bus finish after its wire time, as on the board.
#pragma once

#include <cstdint>
#include <span>

#include "hal/clock.hpp"
#include "hal/i2c_bus.hpp"

namespace qbench {

class Bq76952Responder final : public fw::hal::I2cBus {
 public:
  explicit Bq76952Responder(const fw::hal::Clock& clock);

  // Thread or ISR context: runs the pending list against the register image and calls its `done`.
  void complete();
  bool pending() const { return pending_; }
  // When the pending list has left the wire: its start plus 9 bit times per byte at 400 kHz (start, stop and
  // repeated start included).
  uint32_t dueAt() const { return dueAt_; }
  uint32_t transactions() const { return transactions_; }

 private:
  fw::Status doStart(std::span<fw::hal::I2cTransaction> list, const fw::hal::Notify& done) override;
  fw::Status doRecover() override { return fw::Status::Ok; }
  uint32_t doBitRate() const override { return 400000; }

  void write(uint8_t cmd, std::span<const uint8_t> bytes);
  void runSubcommand(uint16_t code);
  void commitWrite();
  uint8_t dm(uint16_t address) const;

  uint8_t regs_[128];  // direct commands 0x00..0x7F
  uint8_t dm_[0x200];  // data memory 0x9180..0x937F
  bool cfgUpdate_ = false;
  bool fetEn_ = false;
  bool pending_ = false;
  const fw::hal::Clock& clock_;
  uint32_t dueAt_ = 0;
  uint32_t transactions_ = 0;
  std::span<fw::hal::I2cTransaction> list_;
  fw::hal::Notify done_;
};

}  // namespace qbench
