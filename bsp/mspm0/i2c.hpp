// I2cController: fw::hal::I2cBus on an MSPM0 I2C controller, interrupt driven.
//
// Every transaction runs as at most two controller bursts: the write bytes (START, address+W, data) and,
// when there are bytes to read, a second burst that the controller opens with a repeated START
// (address+R, data, NACK on the last byte, STOP). Each transaction starts with both FIFOs flushed (bounded
// wait for the flush to finish). The ISR refills the 8-byte TX FIFO with as many bytes as it has free
// entries and drains the RX FIFO at 7 bytes, moves to the next transaction of the list, and ends the list: a
// write alone costs one interrupt (its STOP), a write-read two and one more per 7 bytes read.
//
// Why no DMA for I2C: at 400 kHz a byte takes 22.5 us, so an ISR that moves 7 bytes every 157 us costs
// about 1 % of the CPU during a 32-byte block and tolerates 22.5 us of interrupt latency before the
// controller simply stretches SCL (no data can be lost). A DMA path would add ~250 B of code and a DMA
// channel to the 8 KiB L1306 image for no measurable gain; the BQ769x2 reads are at most 32 bytes.
//
// Contract (see hal/i2c_bus.hpp; the statuses here are exactly those)
// - start(): Ok, Busy, or InvalidArgument (empty list; a transaction with nothing to write or read; a
//   7-bit address above 0x7F; more than 255 bytes to read or 4094 to write; PEC or blockRead in a
//   build without them; more than one transaction in a build without lists).
// - Length: blockRead only, the count byte was 0 or larger than the buffer after it (NACKed, STOP).
// - Nack: the address was not acknowledged (MSR.ADRACK); DataNack: a written byte was not (MSR.DATACK). The
//   controller sends STOP itself after a NACK ("If there is a NACK response from the target,
//   the controller will automatically send out a stop", SLAU846A I2C controller transfer table).
// - Timeout: SCL was held low longer than the configured stretch limit (hardware timeout A). The driver then
//   resets the controller, clocks SCL up to 9 times as a GPIO until SDA is released, sends a STOP and
//   re-initialises; Timeout means the bus is free again, BusStuck that it is not. The same recovery runs
//   before a transaction when SDA is found low on an idle bus.
// - ArbitrationLost: another controller won the bus (the hardware has released it).
// - Pec: with `pec` set, the hardware PEC check of the received PEC byte failed (MPEC_RX_ERR).
// - SMBus block read (blockRead, in builds with PEC), TI's SMBus library's sequence: the count byte is read
//   alone and ACKed without STOP (the controller keeps the bus and raises RXDONE); the ISR reads the count
//   and continues the receive without a new START for the N data bytes (and the PEC), the last NACKed,
//   then STOP. A count of 0 or one that does not fit the buffer ends with one more byte NACKed and STOP:
//   Length, readCount 1.
// - Hardware PEC: PECCNT counts every data byte of the transaction (not the address bytes, which the CRC
//   still covers) through the repeated START, up to and including the PEC byte; a write appends a dummy
//   byte that the hardware replaces with the PEC (i2c_v1 CONTROLLER_I2CPECCTL description).
// - recover(): task context, only while idle; Ok or BusStuck (or Busy). Takes about 100 us.
// - onInterrupt(): body of I2Cx_IRQHandler: MIS -> ICLR -> act -> return; `done` runs from here.
#pragma once

#include <cstdint>
#include <span>

#include "hal/i2c_bus.hpp"
#include "i2c_timing.hpp"
#include "mspm0/config.hpp"
#include "pin.hpp"
#include "regs/i2c.hpp"

// SMBus PEC and block reads (BSP_I2C_PEC) and transaction lists longer than one (BSP_I2C_LISTS) are options
// (mspm0/config.hpp): without them a transaction asking for PEC or a block read, or a longer list, is
// refused with InvalidArgument.

namespace bsp::mspm0 {

inline constexpr bool kI2cPec = BSP_I2C_PEC != 0;
inline constexpr bool kI2cLists = BSP_I2C_LISTS != 0;

class I2cController final : public fw::hal::I2cBus {
 public:
  struct Config {
    uintptr_t base = 0;
    uint8_t irq = 0;
    PinFunction sda{};
    PinFunction scl{};
    uint32_t bitRate = 100000;
    I2cTiming timing{};
  };

  constexpr explicit I2cController(const Config& config) : config_(config) {}

  // Powers the controller, muxes the pins, programs timing and timeout, enables the IRQ. Thread mode.
  void init();
  void onInterrupt();

 private:
  enum class Phase : uint8_t { Idle, Write, Read, BlockCount, BlockData };

  fw::Status doStart(std::span<fw::hal::I2cTransaction> list, const fw::hal::Notify& done) override;
  fw::Status doRecover() override;
  uint32_t doBitRate() const override { return config_.bitRate; }

  void configure();
  bool recoverBus();
  void startTransaction();
  void beginRead();
  void blockCount();
  void flushFifos();
  void fillTx();
  void drainRx();
  void complete(fw::Status status);
  inline void finish();
  // The transaction in progress (the list's only one in a build without lists).
  fw::hal::I2cTransaction& current() const { return list_[kI2cLists ? index_ : 0]; }

  // Byte-sized state first: Thumb-1 byte loads and stores reach only 31 bytes past the object address.
  volatile Phase phase_ = Phase::Idle;
  volatile bool busy_ = false;
  bool stuck_ = false;  // recovery before a transaction failed: complete it as BusStuck in the ISR
  bool txPecDummy_ = false;
  uint8_t index_ = 0;                   // transaction in progress
  fw::Status result_ = fw::Status::Ok;  // first problem seen in this transaction
  uint16_t txLeft_ = 0;                 // write bytes not yet in the FIFO
  uint16_t rxLeft_ = 0;                 // read bytes not yet stored
  const uint8_t* tx_ = nullptr;
  uint8_t* rx_ = nullptr;
  std::span<fw::hal::I2cTransaction> list_{};
  fw::hal::Notify done_{};
  Config config_;
};

}  // namespace bsp::mspm0
