// SimI2cBus: the host's I2C/SMBus controller (implements fw::hal::I2cBus) wired to emulated targets.
//
// Timing model (so bus-time figures are real): one bit time T = 1/bitRate. START, repeated START and STOP
// take one T each; every byte takes 9 T (8 data + ACK) plus any clock stretch by the target; a transaction is
// followed by the bus-free time tBUF (4.7 us at 100 kHz, 1.3 us at 400 kHz) and the controller's restart
// latency between the transactions of a list (config.restartGap, the ISR/DMA reload time on the MCU).
// A stretch longer than config.stretchLimit ends the transaction with Timeout after stretchLimit, followed by
// the 9-clock recovery and STOP.
//
// Every transaction is logged in the format of `bmsctl trace` (README "Host tools"):
//   S 10 14 Sr 11 [68 33 0B 31] P
// address bytes in their 8-bit form, target-driven bytes in [ ], and, where a transaction failed, the token
// NACK (after the refused byte) or TIMEOUT. With pec set the PEC byte appears on the wire like any other.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "hal/i2c_bus.hpp"
#include "sim/i2c_target.hpp"

namespace bsp::host {

class SimClock;
class SimIrq;

struct SimI2cConfig {
  uint32_t bitRate = 400000;
  fw::Duration stretchLimit = fw::ms(20);  // MSPM0 I2C TIMEOUT_CTL setting used by the BSP
  fw::Duration restartGap = fw::us(4);     // controller reload between transactions of one list
};

struct I2cWireRecord {
  uint64_t startUs = 0;
  uint64_t endUs = 0;
  fw::Status status = fw::Status::Ok;
  std::string text;
};

class SimI2cBus final : public fw::hal::I2cBus {
 public:
  SimI2cBus(SimClock& clock, SimIrq& irq, SimI2cConfig config = {});

  void attach(uint8_t address7, I2cTarget& target);
  void detach(uint8_t address7);

  // Holds SDA low until the recovery sequence has clocked `clocks` times (negative: forever).
  void holdSdaLow(int clocks) { sdaHeldClocks_ = clocks; }

  const std::vector<I2cWireRecord>& wireLog() const { return log_; }
  void clearWireLog() { log_.clear(); }
  // Called with each record as it completes (bmsctl prints them live).
  void onRecord(std::function<void(const I2cWireRecord&)> sink) { sink_ = std::move(sink); }

  uint64_t transactions() const { return transactions_; }
  uint64_t busTimeUs() const { return busTimeNs_ / 1000; }  // wire time incl. stretch, excl. gaps
  uint64_t recoveries() const { return recoveries_; }
  bool busy() const { return busy_; }

 private:
  fw::Status doStart(std::span<fw::hal::I2cTransaction> list, const fw::hal::Notify& done) override;
  fw::Status doRecover() override;
  uint32_t doBitRate() const override { return config_.bitRate; }

  void runTransaction(size_t index);
  uint64_t execute(fw::hal::I2cTransaction& txn, std::string& text);  // returns wire time in ns
  uint64_t recoverNs(I2cTarget* target, std::string& text);
  void finish();

  SimClock& clock_;
  SimIrq& irq_;
  SimI2cConfig config_;
  int line_;
  std::map<uint8_t, I2cTarget*> targets_;
  std::vector<I2cWireRecord> log_;
  std::function<void(const I2cWireRecord&)> sink_;

  std::span<fw::hal::I2cTransaction> list_;
  fw::hal::Notify done_;
  bool busy_ = false;
  int sdaHeldClocks_ = 0;
  uint64_t transactions_ = 0;
  uint64_t busTimeNs_ = 0;
  uint64_t recoveries_ = 0;
};

}  // namespace bsp::host
