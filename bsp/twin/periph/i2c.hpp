// I2c: the MSPM0 I2C controller (I2C0 0x400F0000, I2C1 0x400F2000; tsv base rows), wired to emulated
// targets (bsp::host::I2cTarget: the BQ769x2/BQ7690x and BQ4050 emulators). Registers from mspm0-sdk
// hw_i2c.h: CLKDIV 0x1000, CLKSEL 0x1004, GFCTL 0x1200, TIMEOUT_CTL 0x1204, TIMEOUT_CNT 0x1208, MSA 0x1210,
// MCTR 0x1214, MSR 0x1218, MRXDATA 0x121C, MTXDATA 0x1220, MTPR 0x1224, MCR 0x1228, MBMON 0x1234,
// MFIFOCTL 0x1238, MFIFOSR 0x123C, CONTROLLER_I2CPECCTL 0x1240, CONTROLLER_PECSR 0x1244.
//
// Wire timing (tsv note "I2C SCL formula"): SCL period = (1 + MTPR.TPR) x 10 functional clocks, the
// functional clock being BUSCLK / (CLKDIV.RATIO + 1). START, repeated START and STOP take one SCL period;
// a byte nine (eight bits and the acknowledge) plus whatever the target stretches SCL.
//
// Controller bursts (hw_i2c.h MCTR/MSR descriptions; TI's DL_I2C_startControllerTransfer): an MCTR write
// with BURSTRUN starts a burst of MBLEN bytes to MSA's address, opening with START, or with a repeated START
// when the previous burst ended without STOP (the controller kept the bus); STOP ends it when MCTR.STOP is
// set. A transmit burst takes its bytes from the 8-entry TX FIFO, a receive burst fills the 8-entry RX FIFO,
// acknowledging every byte except the last unless MCTR.ACK; a read burst with STOP must NACK its last byte
// (rules.hpp I2C-READ-NACK: MCTR.ACK with STOP stops the run, UM10204 3.1.6). The controller holds SCL low
// while it waits for the FIFO (empty on transmit, full on receive). A NACK of the address or a data byte sets
// MSR.ADRACK / DATACK and MNACK, and the controller sends STOP by itself. Interrupts: MRXDONE/MTXDONE at the
// end of a burst, MSTART, MSTOP, MNACK; MTXFIFOTRG "when Transmit FIFO contains <= defined bytes" and
// MRXFIFOTRG "when RX FIFO contains >= defined bytes" (hw_i2c.h RIS descriptions), evaluated at every FIFO
// change.
//
// A burst that ends without STOP keeps the bus and holds SCL low (the clock-low timeout runs) until the next
// MCTR write. With START that write opens a repeated START; without START it continues a receive whose last
// byte was acknowledged (MCTR.ACK) with MBLEN more bytes, no address (SLAU846A controller transfer table: a
// burst without START goes on with DATA x n). That is how TI's SMBus library reads a block read's count byte
// and then its payload (mspm0-sdk source/ti/smbus smbus_nwk.c SMBus_NWK_startRxTransfer /
// SMBus_NWK_startRxBlockPayloadTransfer: MBLEN 1 with ACK and no STOP, then the rest without START). The
// controller ACK override (MCTR.MACKOEN) is refused: no TI example or library uses it and no TRM text
// describes it beyond hw_i2c.h's field (bsp/mspm0/README.md, open questions). A continuation after a
// transmit burst or after a NACKed byte stops the run (not modelled).
//
// Set-up rules that stop the run: TIMEOUT_CTL written while MCR.ACTIVE is set (SLAU846B 20.2 / SLAU847D
// 21.2 "clock low timeout": configured during initialisation, not in the active state); GFCTL.AGFEN without
// GFCTL.CHAIN ("When 0, chaining is disabled and only digital filter output is available to IP logic",
// hw_i2c.h GFCTL.CHAIN: the analog filter would do nothing).
//
// Rules that stop the run (the part would lose data silently): a write to MTXDATA with the TX FIFO full
// ("the model drops and flags a write to a full FIFO"); a burst while MCR.ACTIVE is clear; a target that
// stretches SCL on any byte (address, written or read) with MCR.CLKSTRETCH clear (rules.hpp I2C-CLKSTRETCH).
// MFIFOCTL.TXFLUSH/RXFLUSH (rules.hpp I2C-FLUSH): "Setting this bit will Flush the TX FIFO. Before clearing
// this bit to stop Flush the TXFIFOCNT should be checked to be 8 and indicating that the Flush has completed"
// and MFIFOSR.TXFLUSH "When this bit is set a Flush operation for the TX FIFO is active. Clear the TXFLUSH
// bit in the control register to stop" (hw_i2c.h; the same for RX with RXFIFOCNT = 0): a flush empties its
// FIFO one functional clock after it is set and goes on while the bit stays set, so a byte written to MTXDATA
// or a burst started meanwhile is lost (stop); clearing the bit before an MFIFOSR read has shown the FIFO
// flushed stops the run too (DL_I2C_flushControllerTXFIFO polls the same way).
//
// Wire agreement (rules.hpp): at every START the SCL the settings give, f_func / ((1 + TPR) x 10), must lie
// in the addressed device's range (setTargetRange: the board's device's data sheet) and within the
// controller's own limits (TPR 1..127, hw_i2c.h MTPR; at most 1 MHz, Fast-mode Plus); SDA and SCL need INENA
// (PIN-INENA).
//
// Lines held by a device (the board drives the pin low, bms-sim's stuck-scl / stuck-sda): a START with SCL
// low waits for it, with the clock-low timeout running; a START with SDA low loses arbitration (MARBLOST; the
// controller cannot drive SDA high, UM10204 3.1.8).
//
// Clock-low timeout A (SLAU846B 20.2 / SLAU847D 21.2, "clock low timeout"): TCNTLA is the upper 8 bits of
// a 12-bit counter, "each count is equal to a timeout period of (1 + TPR) x 12 of functional clocks",
// counting while SCL is held low continuously and reloaded when it goes high; at zero TIMEOUTA is set and the
// controller stops where it is until it is reset. hw_i2c.h describes the count as "520 times the timeout
// period of functional clock" instead: README, open questions. The twin follows the TRM's worked example.
//
// SMBus PEC (CONTROLLER_I2CPECCTL: PECCNT 8:0, PECEN 12): CRC-8 (x^8 + x^2 + x + 1) over every byte on the
// wire; the PECCNT-th data byte counted is the PEC: sent in place of the FIFO's byte, or checked after its
// last bit on receive (MPEC_RX_ERR, PECSR.PECSTS_ERROR on a mismatch). The CRC and the byte count restart
// when the controller leaves IDLE (a START after STOP or timeout); a write to CONTROLLER_I2CPECCTL clears
// the byte count only, so PECCNT can be set mid-transaction (hw_i2c.h PECCNT and PECEN descriptions; TI's
// SMBus library sets PECCNT = N + 1 after a block read's count byte). PECCNT = 0 counts no byte.
//
// Bus recovery by GPIO (the firmware takes SDA/SCL as GPIOs, clocks SCL and makes a STOP): each target is
// told onBusRecovery() when a STOP (SDA rising while SCL is high) appears on GPIO-driven lines.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "periph/peripheral.hpp"
#include "periph/pins.hpp"
#include "sim/i2c_target.hpp"
#include "timeline.hpp"

namespace twin {

struct I2cWireLog {
  uint64_t startCycle = 0, endCycle = 0;
  bool failed = false;
  std::string text;  // bmsctl trace format: "S 10 14 Sr 11 [68 33] P"
};

class I2c final : public Peripheral {
 public:
  static constexpr uint32_t kMrxDone = 1U << 0, kMtxDone = 1U << 1, kMrxFifoTrg = 1U << 2,
                            kMtxFifoTrg = 1U << 3;
  static constexpr uint32_t kMrxFifoFull = 1U << 4, kMtxEmpty = 1U << 5, kMnack = 1U << 7, kMstart = 1U << 8;
  static constexpr uint32_t kMstop = 1U << 9, kMarbLost = 1U << 10, kMpecRxErr = 1U << 13,
                            kTimeoutA = 1U << 14;

  I2c(Machine& machine, const char* name, Pins& pins);
  // The board: which pins carry SDA and SCL with which PF, and who is on the bus.
  void setPins(int sdaPincm, uint32_t sdaPf, int sclPincm, uint32_t sclPf);
  void attach(uint8_t address7, bsp::host::I2cTarget& target) { targets_[address7] = &target; }
  void detach(uint8_t address7) { targets_.erase(address7); }  // the device left the bus (NACKs from now)
  // The SCL range the device at `address7` accepts (its data sheet, named in `source`).
  struct TargetRange {
    std::string device;
    uint32_t minHz = 0, maxHz = 0;
    std::string source;
    // Non-empty when the device's documents say it may stretch SCL (the source): every transaction to it then
    // needs MCR.CLKSTRETCH (rules.hpp I2C-CLKSTRETCH), whether or not this run's device stretches.
    std::string stretchSource = {};
  };
  void setTargetRange(uint8_t address7, TargetRange range) { ranges_[address7] = std::move(range); }
  uint32_t sclHz() const;

  // Each transaction (START .. STOP) as it completes.
  void onTransaction(std::function<void(const I2cWireLog&)> sink) { sink_ = std::move(sink); }
  uint64_t transactions() const { return transactions_; }
  uint64_t busCycles() const { return busCycles_; }
  // A controller transfer is on the bus (START sent, STOP not yet): its bit timing needs the functional
  // clock it was configured for (the power-mode rule, rules.hpp SLEEP-EVENT-LOST).
  bool transferInFlight() const { return phase_ != Phase::Idle && phase_ != Phase::TimedOut; }
  // A fault for the tests of a driver's bounded flush wait: from now on a flush never completes (MFIFOSR
  // never shows it done); a GPRCM reset still empties the FIFOs.
  void holdFlush() { flushStuck_ = true; }

 private:
  enum class Phase : uint8_t { Idle, Start, Address, Data, WaitFifo, Stop, TimedOut };

  bool readRegister(uint32_t offset, uint32_t& value) override;
  bool writeRegister(uint32_t offset, uint32_t value) override;
  void resetRegisters() override;

  uint64_t bitCycles() const;
  uint64_t timeoutCycles() const;  // 0: timeout A disabled
  bool routed() const;
  void startBurst();
  void step();
  void nextByte();
  void byteDone();
  void finishBurst();
  void sendStop();
  void holdSclLow(uint64_t from);  // the timeout counter runs from `from`
  void releaseScl() { timeout_.cancel(); }
  void onTimeout();
  void txChanged();
  void rxChanged();
  void pecAdd(uint8_t byte);
  void log(const std::string& token);
  void endTransaction(bool failed);
  void watchRecovery(bool sdaChanged);
  bool checkStretch(uint64_t stretchCycles, const char* byte);
  void checkWire(uint8_t address7);

  Pins& pins_;
  TimedEvent step_, timeout_, flush_;
  std::map<uint8_t, bsp::host::I2cTarget*> targets_;
  std::map<uint8_t, TargetRange> ranges_;
  bool flushSeenDone_ = true;
  bool flushStuck_ = false;  // since a flush bit was set, MFIFOSR has shown the flush complete
  std::function<void(const I2cWireLog&)> sink_;
  int sdaPincm_ = 0, sclPincm_ = 0;
  uint32_t sdaPf_ = 0, sclPf_ = 0;

  ClockRegs clock_{0x1004};
  uint32_t gfctl_ = 0, timeoutCtl_ = 0, msa_ = 0, mctr_ = 0, mtpr_ = 0, mcr_ = 0;
  uint32_t mfifoctl_ = 0, pecctl_ = 0, pecsr_ = 0;
  bool adrNack_ = false, dataNack_ = false, err_ = false;
  std::deque<uint8_t> tx_, rx_;

  Phase phase_ = Phase::Idle;
  bool busOwned_ = false;  // START sent, no STOP yet (a following burst opens with a repeated START)
  bsp::host::I2cTarget* target_ = nullptr;
  bool read_ = false, stopAfter_ = false, ackLast_ = false;
  // The RX FIFO holds bytes of a read that ended with STOP, no NACK, no error: the transfer's data
  // (I2C-RX-UNREAD).
  bool rxDelivered_ = false;
  uint32_t remaining_ = 0;
  uint8_t byte_ = 0;
  bool byteAck_ = true;
  bool pecFail_ = false;  // the byte being received is a PEC byte that does not match
  uint32_t pecDataBytes_ = 0;
  uint8_t crc_ = 0;

  I2cWireLog current_;
  bool readOpen_ = false;  // a "[" is open in the log text
  uint64_t transactions_ = 0, busCycles_ = 0;
  // GPIO bus recovery watch
  bool sawGpioClock_ = false;
};

}  // namespace twin
