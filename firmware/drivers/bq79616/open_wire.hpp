// OpenWireCheck: the BQ79616's own VC open-wire diagnostic, over the whole chain at once, built on the
// Chain's raw frames (chain.hpp startWrite/startRead/startPause) as the Balancer is.
//
// What the device does (SLUSF21 "Open Wire Detection"): a current sink on every VC pin, a current source on
// VC0. With a sense wire open, the filter capacitor on that pin is depleted (VC0 pulled up) and the cell
// measurement below the pin drops; the diagnostic comparison compares every cell's Main ADC measurement with
// the host's threshold DIAG_COMP_CTRL2[OW_THR] (500 mV + 300 mV x OW_THR) and latches a cell below it in
// FAULT_COMP_VCOW1 (cells 16..9) / FAULT_COMP_VCOW2 (cells 8..1), which FAULT_SUMMARY[FAULT_COMP_ADC] sums
// up (SLUSE81E table 9-23). So a failing cell n says: the wire of VCn (n >= 1) or, for cell 1, of VC0 is
// open; the cell above the open pin reads too high at the same time, so both cells beside the pin are
// suspect.
//
// The sequence (SLUSF21 "Open Wire Detection": host ensures the Main ADC runs continuously; the order and
// values as two independent BQ79616/BQ79656 drivers write them, each quoting the data sheet's steps; both
// agree): broadcast writes
//   0. BAL_CTRL2 = FLTSTOP_EN | CB_PAUSE: balancing pauses with its timers held (SLUSE81E BAL_CTRL2; a FET
//      that bleeds its cell during the comparison pulls that cell's measurement down, and the comparison
//      would report an open wire that is not there). Nothing else in BAL_CTRL2 acts without BAL_GO.
//   1. DIAG_COMP_CTRL2 = OW_THR (kThresholdCode: 1 700 mV)
//   2. DIAG_COMP_CTRL3 = OW_SNK 01 (VC sinks on; 0x10)
//   3. wait kDeplete for the capacitors to deplete (both drivers wait 3 ms: 0.47 uF at 380 uA minimum)
//   4. DIAG_COMP_CTRL3 = OW_SNK 01 | COMP_ADC_SEL 010 (VC open wire) | COMP_ADC_GO (0x15)
//   5. poll ADC_STAT2[DRDY_VCOW] (a broadcast read) every kPollInterval until every device reports it, at
//   most
//      kPolls times (then Timeout)
//   6. DIAG_COMP_CTRL3 = 0 (sinks off): always once step 2 was sent, whatever failed in between, and tried a
//      second time if it fails (a sink left on drains its cell)
//   6b. BAL_CTRL2 = FLTSTOP_EN: balancing resumes where it paused (always, as 6)
//   7. broadcast read of FAULT_COMP_VCOW1/2: the verdict
//   8. FAULT_RST1 = RST_COMP: the latch is cleared, so the next check reports afresh (a repaired wire is
//   seen)
// Bus time: 7 frames + the polls; the waits: kDeplete + about one comparison (the emulator's estimate, 1.5
// ms) rounded up to the poll interval. worstCase() bounds the whole check.
//
// A broadcast write has no answer: a write the link lost looks sent. So after a link failure during a check
// the sinks may still be on, or balancing paused; the owner runs the check again after every recovery (which
// ends with them off and resumed), and a WAKE resets both anyway.
//
// Operations (start() returns Ok when the first frame went out, Busy while the chain or a check is busy,
// NotReady before the chain is up, InvalidArgument if `failing` is shorter than the chain; the owner forwards
// the chain's completion to step(), which starts the next frame or wait (true) or ends the check (false)):
//   start(failing)  runs the check; at its end verdict() says whether `failing` holds the device's answer:
//                   failing[d] bit c = cell c + 1 of device d below the threshold (an open wire beside it).
//                   result(): Ok, or the first failure (a poll Timeout, or the chain's status of a frame).
//                   A failure after the verdict was read (the latch reset) keeps the verdict.
// Thread mode only (the monitor task).
#pragma once

#include <cstdint>
#include <span>

#include "core/status.hpp"
#include "core/time.hpp"
#include "drivers/bq79616/chain.hpp"

namespace fw::drivers::bq79616 {

class OpenWireCheck {
 public:
  // DIAG_COMP_CTRL2[OW_THR] 4: 500 + 4 x 300 = 1 700 mV. Below the lowest a Li-ion or LiFePO4 cell rests at
  // (2.0 V), above what a depleted pin leaves (TI's example uses 800 mV, another driver 2 300 mV).
  static constexpr uint8_t kThresholdCode = 4;
  static constexpr int32_t kThresholdMv = 500 + 300 * kThresholdCode;
  static constexpr Duration kDeplete = us(3300);  // 3 ms (both drivers) + 10 %
  static constexpr Duration kPollInterval = ms(1);
  static constexpr uint8_t kPolls = 10;

  explicit OpenWireCheck(Chain& chain) : chain_(chain) {}
  OpenWireCheck(const OpenWireCheck&) = delete;
  OpenWireCheck& operator=(const OpenWireCheck&) = delete;

  Status start(std::span<uint16_t> failing);
  bool step(Status chainResult);
  Status result() const { return result_; }
  bool verdict() const { return verdict_; }
  bool busy() const { return stage_ != Stage::Idle; }

  // Upper bound of one check on a chain of `devices` at 1 Mbaud (computed): the waits, every poll, and every
  // frame with its responses (a read: 100 us + 6 us per device before the first byte, 10 us per byte).
  static constexpr Duration worstCase(uint8_t devices) {
    const uint32_t write = 80 + 100 + 6U * devices;                  // a broadcast write and its slack
    const uint32_t read1 = 70 + 100 + 6U * devices + 70U * devices;  // 1 register from every device
    const uint32_t read2 = 70 + 100 + 6U * devices + 80U * devices;  // 2 registers
    return us(kDeplete.us + kPolls * (kPollInterval.us + read1) + 8 * write + read2);
  }

 private:
  enum class Stage : uint8_t {
    Idle,
    PauseBalancing,
    Threshold,
    SinksOn,
    Deplete,
    Go,
    Wait,
    Poll,
    SinksOff,
    Resume,
    Read,
    Clear
  };
  Status write(uint16_t reg, uint8_t value);
  bool next(Stage stage, Status started);
  bool polled();
  bool readVerdict();
  bool end(Status status);

  Chain& chain_;
  std::span<uint16_t> failing_;
  Stage stage_ = Stage::Idle;
  uint8_t polls_ = 0;
  bool retried_ = false;  // the sinks-off write was sent a second time
  bool verdict_ = false;
  Status failure_ = Status::Ok;  // the first failure while the sinks were on
  Status result_ = Status::Ok;
  // ADC_STAT2, or FAULT_COMP_VCOW1/2, of every device: read into the chain's receive buffer (idle during a
  // check; 512 B of SRAM saved on the 64-device build) and taken from it as each read ends.
  std::span<uint8_t> rx() { return chain_.receiveBuffer(); }
};

}  // namespace fw::drivers::bq79616
