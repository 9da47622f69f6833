// Bq79616ChainEmulator: a daisy chain of 1..64 BQ79616 devices behind the base device's UART, for host tests
// and bmsctl. It has two faces (as Zephyr emulators do):
//   - the bus face, a bsp::host::UartPeer on SimUart: command frames and pings arrive from the driver under
//     test, response frames go back with the chain's timing;
//   - the backend face for tests: device state, registers, cell voltages and temperatures, fault injection.
//
// What it models (SLUSE81E unless noted; each choice that is an estimate says so):
// - Frames: INIT/DEV_ID/REG/DATA/CRC exactly as frame.hpp; a command with a bad CRC is dropped by the base
//   (FAULT_COMM1[UART_RC] set) and never forwarded. Single, stack, broadcast and reverse broadcast writes;
//   single, stack and broadcast reads; responses one frame per device, top of stack first (the device with
//   COMM_CTRL[TOP_STACK] starts, each device below appends its own frame after the one from above).
// - Power: every device starts in SHUTDOWN and answers nothing. A WAKE ping resets the base's registers and
//   makes it ACTIVE after tSU(WAKE_SHUT) (10 ms, the datasheet maximum). CONTROL1[SEND_WAKE] sends the WAKE
//   tone up: device j above the sender is reset and ACTIVE after (j - sender) x (1.6 ms tone + 10 ms)
//   (SLUUC56B). The base does not forward a WAKE tone by itself, so a driver that forgets SEND_WAKE fails.
//   After a SHUTDOWN ping the next WAKE brings the base up with its daisy-chain port still off; only a second
//   WAKE turns it on (SLUUC56B note). SLEEPtoACTIVE wakes SLEEPing devices without a reset (230 us + 270 us
//   per device for the tone, an estimate). HW_RESET (ping to the base, CONTROL2[SEND_HW_RESET] tone up)
//   holds a device in reset for tHWRST = 75 ms (BQ75614-Q1 sibling table), then it is in SHUTDOWN.
// - Pings are classified by their low time against the datasheet windows shrunk by `pingTolerancePercent`
//   (default 5 %), standing for the MCU clock error a real design must absorb: TI's example's 2.0 ms WAKE
//   (the window's bottom edge) is rejected, a ping in the middle of the window is accepted. Windows: COMM
//   CLEAR 15..20 bit periods, SLEEPtoACTIVE 250..300 us, WAKE 2.0..2.5 ms, SHUTDOWN 7..10 ms, HW_RESET >= 36
//   ms.
// - Addressing: a device processes only writes until it has been given an address; CONTROL1[ADDR_WR] makes
//   it keep (and not forward) the next frame; DIR0_ADDR is writable only then (SLUSE81E §9.5.4.3.9).
// - Timing on top of SimUart's 10 bits per byte: a command reaches device k k x `hopUs` after its last stop
//   bit; a device starts its response `responseUs` after the command reached it; a response frame travels
//   down at `hopUs` per device. The daisy chain is faster than the 1 Mbaud UART, so the base's UART output is
//   back to back once the first frame arrives. Defaults hopUs = 3, responseUs = 100 come from TI's bound for
//   a stack read, tWAIT_READ_MAX = (n - 1) x 3 us x 2 + m x 10 us + 100 us (BQ79600-Q1 datasheet): the
//   emulator answers as late as that bound allows, so throughput measured against it is not flattered.
// - Measurements: ADC_CTRL1 as SLUSF21 lays it out (LPF_VCELL_EN bit 3, MAIN_GO bit 2, MAIN_MODE 1:0):
//   MAIN_GO with MAIN_MODE = continuous starts the main ADC (DEV_STAT[MAIN_RUN] = 1), MAIN_MODE = 00 stops
//   it. VCELLn read 0x8000 until the main ADC has run for `adcSettleUs` (38 ms, TI's LPF settling at 26 Hz);
//   GPIOs read 0x8000 (not configured as ADC inputs) unless a test sets them; die temperatures default to
//   25 degC.
// - Customer CRC (SLUSF21 DEV_STAT, CUST_CRC_RSLT_HI/LO, FAULT_OTP; register-map summary: the NVM shadow
//   registers are in the OTP CRC check): a CRC state machine runs passes back to back, each `custCrcUs` long
//   (an estimate: TI gives no figure). A pass ends by setting CUST_CRC_RSLT to the CRC of the shadow
//   registers 0x000..0x035 (the emulator's own CRC choice), setting DEV_STAT[CUST_CRC_DONE] (cleared when
//   DEV_STAT is read) and, when the result differs from CUST_CRC, latching FAULT_OTP[CUST_CRC] (bit 4). A
//   write to a shadow register (0x000..0x037) restarts the pass in progress, so CUST_CRC_RSLT shows the new
//   contents only `custCrcUs` after the last such write, and a CUST_CRC_DONE still latched from before the
//   write says nothing about it. FAULT_MSK2[MSK_OTP_CRC] keeps FAULT_OTP[CUST_CRC/FACT_CRC] out of
//   FAULT_SUMMARY and nFAULT while the flag itself still latches (SLUSE48B fault-masking table, BQ79656-Q1
//   sibling; TI's bq79616 example masks with FAULT_MSK2 = 0x40).
// - Faults: FAULT_SUMMARY is computed from the FAULT_* registers; FAULT_RST1/2 clear their groups (a CRC
//   mismatch that is still there latches again at the next pass). A WAKE or a digital reset leaves
//   FAULT_SYS[DRST] (bit 4, SLUSF21 FAULT_SYS) set.
//   A communication fault injected into a stack device latches there (FAULT_COMM2 bit 0) and, through the
//   fault signal, in the base (FAULT_COMM3 bit 4, FCOMM_DET): the base's latch comes back while any stack
//   device still holds its fault, so it clears only when base and stack are both cleared (SLUSE81E;
//   TI E2E thread 1231370). nFAULT (attachFaultPin) is low while any awake device has a non-zero
//   FAULT_SUMMARY.
//
// - Cell balancing (balancing.cpp, each rule with its SLUSE81E / SLUSF21 source): per-channel timers
//   (CB_CELLn_CTRL) sampled by BAL_CTRL2[BAL_GO] with the rest of the balancing settings; manual control
//   (AUTO_BAL = 0) refuses more than 8 channels and, with DEV_CONF[NO_ADJ_CB] (set by default), neighbours
//   (BAL_STAT[INVALID_CBCONF], nothing starts); automatic control alternates odd and even channels every
//   BAL_CTRL1 duty period; FLTSTOP_EN stops everything on an unmasked fault (ABORTFLT); CB_PAUSE, the die
//   past CB TWARN and, with OTCB_EN, an NTC past OTCB_THR pause it with the timers held. Each balanced cell
//   loses V / balanceOhms (cell_model.hpp) and its VCELL reading falls with the charge it lost.
// - VC open-wire diagnostic (open_wire.cpp, each rule with its source): the world's open sense wires
//   (setOpenWire), DIAG_COMP_CTRL3's VC current sinks (VC0's source) and the VC open-wire comparison against
//   DIAG_COMP_CTRL2[OW_THR], its time, ADC_STAT2[DRDY_VCOW], FAULT_COMP_VCOW1/2 (in FAULT_SUMMARY and nFAULT
//   with the other FAULT_COMP_* registers), and a balancing channel's cell comparing low.
//
// Injected faults: a shorter chain (construct with fewer devices than the driver expects), a broken link
// above device k, a mute device (forwards but never answers, so the devices below it wait and stay silent),
// corrupted bytes in a device's next response(s) on the UART, a truncated next response, a sticky (optionally
// persistent) communication fault, a base receiver stuck mid-frame (until COMM CLEAR or a ping), the whole
// chain asleep, a device's digital reset (address lost), a hung device (only HW_RESET brings it back), the
// link to the base cut both ways (nothing reaches the base, nothing comes back), a device whose main ADC
// stops delivering results while DEV_STAT[MAIN_RUN] still reads 1 (until its next digital reset).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cell_model.hpp"
#include "sim/peripherals.hpp"
#include "sim/sim_clock.hpp"
#include "sim/uart.hpp"

namespace bsp::host {

class Bq79616ChainEmulator final : public UartPeer {
 public:
  struct Timing {
    uint32_t hopUs = 3;
    uint32_t responseUs = 100;
    uint32_t wakeSetupUs = 10000;
    uint32_t toneUs = 1600;
    uint32_t stackWakeUs = 10000;
    uint32_t sleepToActiveUs = 230;
    uint32_t sleepToActiveToneUs = 270;
    uint32_t hwResetUs = 75000;
    uint32_t adcSettleUs = 38000;
    uint32_t custCrcUs = 2000;    // one pass of the customer CRC state machine (estimate, see above)
    uint32_t owDepleteUs = 2000;  // sinks on this long deplete an open pin (estimate, open_wire.cpp)
    uint32_t owCompareUs = 1500;  // one VC open-wire comparison (estimate, open_wire.cpp)
    uint32_t pingTolerancePercent = 5;
  };

  enum class Power : uint8_t { Shutdown, Sleep, Active, HwReset };

  static constexpr size_t kMaxDevices = 64;
  static constexpr size_t kRegisterSpace = 0x1000;

  Bq79616ChainEmulator(SimClock& clock, SimUart& uart, size_t devices, Timing timing);
  Bq79616ChainEmulator(SimClock& clock, SimUart& uart, size_t devices)
      : Bq79616ChainEmulator(clock, uart, devices, Timing{}) {}

  // --- bus face ------------------------------------------------------------------------------------------
  void onHostBytes(std::span<const uint8_t> bytes, uint64_t endUs) override;
  std::string onPing(fw::Duration low, uint64_t endUs) override;

  // --- backend face --------------------------------------------------------------------------------------
  size_t size() const { return devices_.size(); }
  Power power(size_t device) const { return devices_.at(device).power; }
  bool awake(size_t device) const;  // ACTIVE and done waking up, now
  bool addressed(size_t device) const { return devices_.at(device).addressed; }
  uint8_t address(size_t device) const;
  // The register as a read would return it now (computed registers included).
  uint8_t reg(size_t device, uint16_t address) const;
  void setReg(size_t device, uint16_t address, uint8_t value);
  void setCellMicrovolts(size_t device, int cell, int32_t microvolts);  // cell 1..16
  void setCellRaw(size_t device, int cell, int16_t raw);
  int16_t cellRaw(size_t device, int cell) const;
  void setDieTempRaw(size_t device, int index, int16_t raw);  // index 1..2, 0.025 degC per LSB
  void setGpioRaw(size_t device, int gpio, int16_t raw);      // gpio 1..8
  void attachFaultPin(SimEdgeInput& nfault);
  const Timing& timing() const { return timing_; }

  // --- fault injection -----------------------------------------------------------------------------------
  void breakLinkAbove(size_t device);  // nothing passes between `device` and `device + 1`
  void healLink();
  void setMuted(size_t device, bool muted);
  // XORs `mask` into byte `index` of `device`'s response frame on the UART, for its next `times` responses.
  void corruptResponse(size_t device, size_t index, uint8_t mask, int times = 1);
  void truncateNextResponse(size_t keepBytes);  // the base stops after `keepBytes` bytes of the next response
  void injectCommFault(size_t device, bool persistent);
  void endCommFaultCause(size_t device);  // a persistent fault's cause goes away (the latch stays)
  void desyncBase();                      // the base's receiver waits for a frame that never completes
  void sleepAll();
  void shutdownAll();
  void resetDevice(size_t device);  // digital reset: registers to defaults, address and role lost
  void hangDevice(size_t device);   // ignores frames, tones and pings until a HW_RESET
  void setDisconnected(bool cut);   // the MCU-to-base link is cut both ways
  void freezeAdc(size_t device);    // VCELLn read 0x8000 until the device's next digital reset

  // --- open wire (open_wire.cpp) ------------------------------------------------------------------------
  // The sense wire of pin VC`pin` (0 = the bottom tap, 16 = the top of a 16-cell device) opens or closes. The
  // readings stay what the test sets (the pin's filter capacitor holds the node between checks); only the
  // device's own diagnostic sees it.
  void setOpenWire(size_t device, int pin, bool open);
  bool owSinksOn(size_t device) const;                       // DIAG_COMP_CTRL3[OW_SNK] = VC sinks, now
  uint32_t owComparisons() const { return owComparisons_; }  // VC open-wire comparisons completed

  // --- balancing (balancing.cpp) ---------------------------------------------------------------------------
  void setCellModel(const CellModel& model) { cellModel_ = model; }
  uint16_t balancingCells(size_t device);  // channels bleeding now (bit c = cell c + 1)
  uint8_t balStat(size_t device);          // BAL_STAT as a read would return it now
  int32_t cellNowMicrovolts(size_t device, int cell);
  int64_t bledChargeMaUs(size_t device, int cell);
  struct BalanceCounters {
    uint32_t started = 0;  // BAL_GO that started balancing
    uint32_t invalid = 0;  // BAL_GO refused with INVALID_CBCONF
    uint32_t aborted = 0;  // balancing stopped by an unmasked fault (FLTSTOP_EN)
    uint32_t expired = 0;  // channels whose timer ran out
    uint32_t paused = 0;   // pauses begun (host, CB TWARN, OTCB)
  };
  const BalanceCounters& balanceCounters() const { return balanceCounters_; }
  // CB TWARN, the die temperature that pauses balancing (balancing.cpp).
  static constexpr int16_t kCbTwarnRaw = 4200;    // 105 degC at 0.025 degC per LSB
  static constexpr int16_t kCbTwarnHysRaw = 400;  // 10 degC

  struct Counters {
    uint64_t commandFrames = 0;  // command frames with a good CRC the base accepted
    uint64_t badCommandCrc = 0;
    uint64_t ignoredBytes = 0;  // bytes the base did not take (asleep, desynchronised, not a frame)
    uint64_t responses = 0;     // response frames sent to the host
    uint64_t pings = 0;
    uint64_t rejectedPings = 0;  // low times outside every window
  };
  const Counters& counters() const { return counters_; }

 private:
  struct Device {
    std::array<uint8_t, kRegisterSpace> regs{};
    Power power = Power::Shutdown;
    uint64_t readyAt = 0;
    uint64_t resetUntil = 0;
    uint64_t adcSince = 0;
    bool adcRunning = false;
    bool addrWr = false;
    bool addressed = false;
    bool muted = false;
    bool hung = false;
    bool adcFrozen = false;
    bool commCause = false;
    int corruptTimes = 0;
    size_t corruptIndex = 0;
    uint8_t corruptMask = 0;
    // The customer CRC state machine: passes end at crcEpoch + k x custCrcUs (k >= 1).
    uint64_t crcEpoch = 0;        // start of the first pass over the current shadow contents
    uint64_t crcLastRead = 0;     // last read of DEV_STAT (clears CUST_CRC_DONE)
    uint16_t crcResult = 0;       // CUST_CRC_RSLT until a pass over the current contents ends
    bool crcDoneLatched = false;  // a pass ended before crcEpoch and DEV_STAT was not read since
    SimClock::EventId crcCheck = 0;
    // The VC open-wire diagnostic (open_wire.cpp).
    uint32_t openPins = 0;      // the world: bit p = the wire of VCp is open
    uint64_t sinksSince = 0;    // when DIAG_COMP_CTRL3 last turned the VC sinks on
    uint64_t owDoneAt = 0;      // the running comparison ends (0: none since the last GO)
    uint32_t owGeneration = 0;  // a reset or a new GO makes a pending completion void
    bool owDepleted = false;    // the sinks had been on long enough when the comparison started
    // Cell balancing (balancing.cpp).
    struct Balance {
      bool running = false;  // BAL_STAT[CB_RUN]
      bool automatic = false;
      bool faultStop = false;  // FLTSTOP_EN, as BAL_GO sampled it
      bool otcb = false;       // OTCB_EN, as BAL_GO sampled it
      bool otPause = false;    // OT_PAUSE_DET
      bool odd = true;         // automatic control: the odd channels' turn
      uint8_t status = 0;      // BAL_STAT's latched bits: INVALID_CBCONF, ABORTFLT, CB_DONE
      uint64_t untilUs = 0;    // the state below covers the time up to here
      uint64_t phaseLeftUs = 0;
      uint64_t dutyUs = 0;
      std::array<uint64_t, 16> leftUs{};  // each channel's timer
      std::array<int64_t, 16> bled{};     // mA x us each cell lost
      uint16_t complete = 0;              // CB_COMPLETE1/2
    } bal;
  };

  bool activeAt(const Device& d, uint64_t t) const;
  void tick(uint64_t now);
  bool reaches(size_t k) const { return brokenAbove_ < 0 || k <= static_cast<size_t>(brokenAbove_); }
  void resetRegisters(Device& d);
  void digitalReset(size_t k, uint64_t readyAt);
  // A command frame's INIT byte decoded: request type 0..6, and what the type implies.
  struct FrameType {
    uint8_t type;
    bool read;    // single, stack or broadcast read: one data byte (the count)
    bool single;  // a device address follows INIT
  };
  void process(const std::vector<uint8_t>& frame, FrameType kind, uint64_t endUs);
  void applyWrite(size_t k, uint16_t reg, std::span<const uint8_t> data, uint64_t t);
  void writeReg(size_t k, uint16_t address, uint8_t value, uint64_t t);
  uint8_t readReg(size_t k, uint16_t address, uint64_t t) const;
  void respond(const std::vector<size_t>& order, uint16_t reg, size_t count, uint64_t startUs,
               const std::vector<uint64_t>& reachedAt);
  void toneUp(size_t from, uint64_t t, uint8_t kind);
  void updateFaults();
  // The customer CRC engine (see the header comment).
  uint64_t lastPassEnd(const Device& d, uint64_t t) const;  // 0: no pass has ended since crcEpoch
  uint16_t custCrcResult(const Device& d, uint64_t t) const;
  bool custCrcDone(const Device& d, uint64_t t) const;
  void restartCustCrc(size_t k, uint64_t t);
  void scheduleCrcCheck(size_t k, uint64_t at);
  void checkCustCrc(size_t k);

  SimClock& clock_;
  SimUart& uart_;
  Timing timing_;
  std::vector<Device> devices_;
  std::vector<uint8_t> rxBuf_;
  int brokenAbove_ = -1;
  bool desync_ = false;
  bool disconnected_ = false;
  int wakesSinceShutdownPing_ = 2;  // 2 = the daisy-chain port is on
  size_t truncateAt_ = SIZE_MAX;
  SimEdgeInput* nfault_ = nullptr;
  Counters counters_;
  CellModel cellModel_;
  BalanceCounters balanceCounters_;
  // open_wire.cpp
  void diagCompCtrl3(size_t k, uint8_t value, uint64_t t);
  void owComplete(size_t k, uint32_t generation);
  uint8_t adcStat2(const Device& d, uint64_t t) const;
  uint32_t owComparisons_ = 0;
  // balancing.cpp
  void balanceGo(size_t k, uint8_t ctrl2, uint64_t t);
  void advanceBalance(size_t k, uint64_t t);
  void checkBalancePause(size_t k, uint64_t t);
  void faultStopBalance(size_t k, bool fault, uint64_t t);
  uint16_t bleeding(const Device& d) const;
  uint8_t balanceStatus(const Device& d) const;
  int32_t setMicrovolts(const Device& d, int cell) const;
};

}  // namespace bsp::host
