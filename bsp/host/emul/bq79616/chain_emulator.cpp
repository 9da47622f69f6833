// BQ79616 daisy-chain emulator (see chain_emulator.hpp for what is modelled and where each fact comes from).
#include "bq79616/chain_emulator.hpp"
#include "bq79616/register_address.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>

#include "core/bytes.hpp"
#include "core/crc.hpp"
#include "regmap/bq79616.hpp"
#include "regmap/bq79616_table.hpp"

namespace bsp::host {

namespace {

namespace r = fw::regmap::bq79616::reg;
namespace b = fw::regmap::bq79616::bits;

using bq79616_emul::at;

constexpr uint16_t kDir0Addr = at(r::Dir0Addr);
constexpr uint16_t kCommCtrl = at(r::CommCtrl);
constexpr uint16_t kControl1 = at(r::Control1);
constexpr uint16_t kControl2 = at(r::Control2);
constexpr uint16_t kAdcCtrl1 = at(r::AdcCtrl1);
constexpr uint16_t kFaultRst1 = at(r::FaultRst1);
constexpr uint16_t kFaultRst2 = at(r::FaultRst2);
constexpr uint16_t kFaultMsk2 = at(r::FaultMsk2);
constexpr uint16_t kDevConf = at(r::DevConf);
constexpr uint16_t kCustCrcHi = at(r::CustCrcHi);
constexpr uint16_t kCustCrcLo = at(r::CustCrcLo);
constexpr uint16_t kCustCrcRsltHi = at(r::CustCrcRsltHi);
constexpr uint16_t kCustCrcRsltLo = at(r::CustCrcRsltLo);
constexpr uint16_t kFaultSummary = at(r::FaultSummary);
constexpr uint16_t kFaultComm1 = at(r::FaultComm1);
constexpr uint16_t kFaultComm2 = at(r::FaultComm2);
constexpr uint16_t kFaultComm3 = at(r::FaultComm3);
constexpr uint16_t kFaultOtp = at(r::FaultOtp);
constexpr uint16_t kFaultSys = at(r::FaultSys);
constexpr uint16_t kDevStat = at(r::DevStat);
constexpr uint16_t kVcell16Hi = at(r::Vcell16Hi);
constexpr uint16_t kVcell1Lo = at(r::Vcell1Lo);
constexpr uint16_t kGpio1Hi = at(r::Gpio1Hi);
constexpr uint16_t kDietemp1Hi = at(r::Dietemp1Hi);
constexpr uint16_t kBalCtrl2 = at(r::BalCtrl2);
constexpr uint16_t kBalStat = at(r::BalStat);
constexpr uint16_t kCbComplete1 = at(r::CbComplete1);
constexpr uint16_t kCbComplete2 = at(r::CbComplete2);
constexpr uint16_t kShadowEnd = at(r::CustCrcHi);  // NVM-shadow registers 0x000 .. CUST_CRC_HI - 1
static_assert(kCustCrcLo == kCustCrcHi + 1, "CUST_CRC is one big-endian word");
// A write to any NVM shadow register, CUST_CRC included, restarts the customer CRC pass in progress.
constexpr bool isShadow(uint16_t address) {
  return address <= kCustCrcLo;
}

// FAULT_SUMMARY groups and the registers behind them (SLUSE81E §9.5.4.4, FAULT_SUMMARY).
struct Group {
  uint8_t summaryBit;
  uint8_t rst1Bit;  // FAULT_RST1 bit that clears the group (0: cleared through FAULT_RST2)
  std::vector<uint16_t> regs;
};
const std::vector<Group>& groups() {
  static const std::vector<Group> g = {
      {b::FaultSummary::fault_pwr_mask,
       b::FaultRst1::rst_pwr_mask,
       {at(r::FaultPwr1), at(r::FaultPwr2), at(r::FaultPwr3)}},
      {b::FaultSummary::fault_sys_mask, b::FaultRst1::rst_sys_mask, {kFaultSys}},
      {b::FaultSummary::fault_ovuv_mask, b::FaultRst1::rst_ov_mask, {at(r::FaultOv1), at(r::FaultOv2)}},
      {b::FaultSummary::fault_ovuv_mask, b::FaultRst1::rst_uv_mask, {at(r::FaultUv1), at(r::FaultUv2)}},
      {b::FaultSummary::fault_otut_mask, b::FaultRst1::rst_ot_mask, {at(r::FaultOt)}},
      {b::FaultSummary::fault_otut_mask, b::FaultRst1::rst_ut_mask, {at(r::FaultUt)}},
      {b::FaultSummary::fault_comm_mask, 0, {kFaultComm1, kFaultComm2, kFaultComm3}},
      {b::FaultSummary::fault_otp_mask, 0, {kFaultOtp}},
      {b::FaultSummary::fault_comp_adc_mask,
       b::FaultRst1::rst_comp_mask,
       {at(r::FaultCompGpio), at(r::FaultCompVccb1), at(r::FaultCompVccb2), at(r::FaultCompVcow1),
        at(r::FaultCompVcow2), at(r::FaultCompCbow1), at(r::FaultCompCbow2), at(r::FaultCompCbfet1),
        at(r::FaultCompCbfet2), at(r::FaultCompMisc)}},
      {b::FaultSummary::fault_prot_mask, b::FaultRst1::rst_prot_mask, {at(r::FaultProt1), at(r::FaultProt2)}},
  };
  return g;
}

constexpr uint8_t kFaultSysDrst = b::FaultSys::drst_mask;  // bit 4 (SLUSF21 FAULT_SYS)
static_assert(kFaultSysDrst == 0x10, "SLUSF21 FAULT_SYS: LFO 7, RSVD 6, GPIO 5, DRST 4");
constexpr uint8_t kComm1CommClear = 0x03;  // FAULT_COMM1: COMMCLR_DET | STOP_DET (bits 1, 0)
constexpr uint8_t kComm1UartRc = 0x04;     // FAULT_COMM1: UART_RC, a bad command frame
constexpr uint8_t kComm2Link = 0x01;       // FAULT_COMM2 bit 0: the injected link fault
constexpr uint8_t kComm3Fcomm = 0x10;      // FAULT_COMM3 bit 4: FCOMM_DET at the base
constexpr uint8_t kOtpCustCrc = b::FaultOtp::cust_crc_mask;  // bit 4 (SLUSF21 FAULT_OTP)
static_assert(kOtpCustCrc == 0x10, "SLUSF21 FAULT_OTP: DED 6, SEC 5, CUST_CRC 4, FACT_CRC 3");
// What FAULT_MSK2[MSK_OTP_CRC] keeps out of FAULT_SUMMARY (SLUSE48B fault-masking table).
constexpr uint8_t kOtpCrcBits = b::FaultOtp::cust_crc_mask | b::FaultOtp::fact_crc_mask;
constexpr uint8_t kDevStatCustCrcDone = b::DevStat::cust_crc_done_mask;  // bit 5, cleared on read
static_assert(kDevStatCustCrcDone == 0x20, "SLUSF21 DEV_STAT: FACT_CRC_DONE 6, CUST_CRC_DONE 5");

// Misuse of the backend face is a test bug: report it and stop (the firmware options build without
// exceptions).
void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "Bq79616ChainEmulator: %s\n", what);
    std::abort();
  }
}

enum Tone : uint8_t { kToneWake, kToneSleepToActive, kToneShutdown, kToneHwReset };

using Registers = std::array<uint8_t, Bq79616ChainEmulator::kRegisterSpace>;

// The customer CRC over the NVM-shadow registers.
uint16_t shadowCrc(const Registers& regs) {
  return fw::crc::crc16(regs.data(), kShadowEnd);
}

// The register image a reset loads, built once: the register map's defaults, with CUST_CRC holding the CRC
// of them (the OTP holds the CRC of its own defaults).
const Registers& defaultRegisters() {
  static const Registers defaults = [] {
    Registers regs{};
    for (const auto& e : fw::regmap::bq79616::entries) {
      if (e.kind == fw::regmap::Kind::Register && e.hasDefault && e.address < regs.size())
        regs[e.address] = static_cast<uint8_t>(e.dflt);
    }
    // An unprogrammed OTP address is 0 (SLUSE81E §9.3.6.1.3.2); the runtime address starts there.
    regs[kDir0Addr] = 0;
    fw::bytes::storeBe16(&regs[kCustCrcHi], shadowCrc(regs));
    return regs;
  }();
  return defaults;
}

}  // namespace

Bq79616ChainEmulator::Bq79616ChainEmulator(SimClock& clock, SimUart& uart, size_t devices, Timing timing)
    : clock_(clock), uart_(uart), timing_(timing), devices_(devices) {
  require(devices >= 1 && devices <= kMaxDevices, "a chain has 1..64 devices");
  for (size_t k = 0; k < devices_.size(); ++k) {
    resetRegisters(devices_[k]);
    for (int c = 1; c <= 16;
         ++c)  // distinct, plausible defaults: 3.600 V + 1 mV per device + 0.1 mV per cell
      setCellMicrovolts(k, c, 3600000 + 1000 * static_cast<int32_t>(k) + 100 * c);
    for (int g = 1; g <= 8; ++g)  // GPIOs not configured as ADC inputs read 0x8000
      setGpioRaw(k, g, static_cast<int16_t>(-32768));
    setDieTempRaw(k, 1, 1000);  // 25 degC = 1000 x 0.025 degC
    setDieTempRaw(k, 2, 1000);
  }
  uart.attach(*this);
}

// --- registers -------------------------------------------------------------------------------------------

void Bq79616ChainEmulator::resetRegisters(Device& d) {
  // Measurements survive a digital reset (they are the analog front end's, written by the ADC): keep them.
  // (They lie outside the NVM shadow, so the default CUST_CRC still matches.)
  static_assert(kVcell16Hi >= kShadowEnd && kGpio1Hi >= kShadowEnd && kDietemp1Hi >= kShadowEnd);
  std::array<uint8_t, 32> cells{};
  std::copy_n(d.regs.begin() + kVcell16Hi, 32, cells.begin());
  std::array<uint8_t, 20> aux{};
  std::copy_n(d.regs.begin() + kGpio1Hi, 16, aux.begin());
  std::copy_n(d.regs.begin() + kDietemp1Hi, 4, aux.begin() + 16);
  // Balancing stops with the reset; the charge it took from the cells stays taken (balancing.cpp).
  const size_t k = static_cast<size_t>(&d - devices_.data());
  if (k < devices_.size()) advanceBalance(k, clock_.nowUs());
  const auto bled = d.bal.bled;
  d.bal = {};
  d.bal.bled = bled;
  d.bal.untilUs = clock_.nowUs();
  d.regs = defaultRegisters();
  std::copy(cells.begin(), cells.end(), d.regs.begin() + kVcell16Hi);
  std::copy_n(aux.begin(), 16, d.regs.begin() + kGpio1Hi);
  std::copy_n(aux.begin() + 16, 4, d.regs.begin() + kDietemp1Hi);
  d.regs[kFaultSys] = kFaultSysDrst;
  d.addrWr = false;
  d.addressed = false;
  d.adcRunning = false;
  d.adcFrozen = false;
  // The CRC state machine starts over on the reloaded shadow registers, whose CUST_CRC matches them.
  if (d.crcCheck != 0) clock_.cancel(d.crcCheck);
  d.crcCheck = 0;
  d.crcEpoch = d.crcLastRead = clock_.nowUs();
  d.crcResult = shadowCrc(d.regs);
  d.crcDoneLatched = false;
  // A comparison in progress ends with the reset (its registers are back to defaults: sinks off).
  d.owDoneAt = 0;
  ++d.owGeneration;
}

// --- the customer CRC state machine ----------------------------------------------------------------------

uint64_t Bq79616ChainEmulator::lastPassEnd(const Device& d, uint64_t t) const {
  const uint64_t pass = timing_.custCrcUs;
  if (t < d.crcEpoch + pass) return 0;
  return d.crcEpoch + (t - d.crcEpoch) / pass * pass;
}

// CUST_CRC_RSLT at time t: the shadow contents once a pass over them has ended, the previous result before.
uint16_t Bq79616ChainEmulator::custCrcResult(const Device& d, uint64_t t) const {
  return lastPassEnd(d, t) != 0 ? shadowCrc(d.regs) : d.crcResult;
}

// DEV_STAT[CUST_CRC_DONE] at time t: a pass has ended since DEV_STAT was last read.
bool Bq79616ChainEmulator::custCrcDone(const Device& d, uint64_t t) const {
  return d.crcDoneLatched || lastPassEnd(d, t) > d.crcLastRead;
}

// A shadow register is about to change at time t: the passes that ended over the old contents are folded
// into the result and the done flag, and a new pass starts now.
void Bq79616ChainEmulator::restartCustCrc(size_t k, uint64_t t) {
  Device& d = devices_[k];
  if (const uint64_t end = lastPassEnd(d, t); end != 0) {
    d.crcResult = shadowCrc(d.regs);
    if (end > d.crcLastRead) d.crcDoneLatched = true;
  }
  d.crcEpoch = t;
  scheduleCrcCheck(k, t + timing_.custCrcUs);
}

void Bq79616ChainEmulator::scheduleCrcCheck(size_t k, uint64_t at) {
  Device& d = devices_[k];
  if (d.crcCheck != 0) clock_.cancel(d.crcCheck);
  d.crcCheck = clock_.schedule(at, [this, k] { checkCustCrc(k); });
}

// A pass ends: a result that differs from CUST_CRC latches FAULT_OTP[CUST_CRC], masked or not.
void Bq79616ChainEmulator::checkCustCrc(size_t k) {
  Device& d = devices_[k];
  d.crcCheck = 0;
  if (d.power != Power::Active) return;
  if (shadowCrc(d.regs) != fw::bytes::loadBe16(&d.regs[kCustCrcHi])) {
    d.regs[kFaultOtp] |= kOtpCustCrc;
    updateFaults();
  }
}

void Bq79616ChainEmulator::digitalReset(size_t k, uint64_t readyAt) {
  Device& d = devices_[k];
  resetRegisters(d);
  d.power = Power::Active;
  d.readyAt = readyAt;
  d.crcEpoch = d.crcLastRead = readyAt;
}

void Bq79616ChainEmulator::tick(uint64_t now) {
  for (Device& d : devices_) {
    if (d.power == Power::HwReset && now >= d.resetUntil)
      d.power = Power::Shutdown;  // out of reset: SHUTDOWN
  }
}

bool Bq79616ChainEmulator::activeAt(const Device& d, uint64_t t) const {
  return d.power == Power::Active && !d.hung && t >= d.readyAt;
}

bool Bq79616ChainEmulator::awake(size_t device) const {
  return activeAt(devices_.at(device), clock_.nowUs());
}

uint8_t Bq79616ChainEmulator::address(size_t device) const {
  return devices_.at(device).regs[kDir0Addr] & 0x3F;
}

uint8_t Bq79616ChainEmulator::reg(size_t device, uint16_t address) const {
  return readReg(device, address, clock_.nowUs());
}

void Bq79616ChainEmulator::setReg(size_t device, uint16_t address, uint8_t value) {
  devices_.at(device).regs.at(address) = value;
  updateFaults();
}

void Bq79616ChainEmulator::setCellRaw(size_t device, int cell, int16_t raw) {
  require(cell >= 1 && cell <= 16, "cells are numbered 1..16");
  advanceBalance(device, clock_.nowUs());
  const uint16_t a = static_cast<uint16_t>(kVcell16Hi + 2 * (16 - cell));  // VCELL16 first
  fw::bytes::storeBe16(&devices_.at(device).regs[a], static_cast<uint16_t>(raw));
}

void Bq79616ChainEmulator::setCellMicrovolts(size_t device, int cell, int32_t microvolts) {
  // 190.73 uV per LSB, rounded to the nearest code as an ADC would.
  const int64_t n = static_cast<int64_t>(microvolts) * 100;
  const int64_t raw = (n >= 0 ? n + 19073 / 2 : n - 19073 / 2) / 19073;
  setCellRaw(device, cell, static_cast<int16_t>(std::clamp<int64_t>(raw, -32767, 32767)));
}

int16_t Bq79616ChainEmulator::cellRaw(size_t device, int cell) const {
  const uint16_t a = static_cast<uint16_t>(kVcell16Hi + 2 * (16 - cell));
  return fw::bytes::loadBeI16(&devices_.at(device).regs[a]);
}

void Bq79616ChainEmulator::setDieTempRaw(size_t device, int index, int16_t raw) {
  const uint16_t a = static_cast<uint16_t>(kDietemp1Hi + 2 * (index - 1));
  advanceBalance(device, clock_.nowUs());
  fw::bytes::storeBe16(&devices_.at(device).regs[a], static_cast<uint16_t>(raw));
  checkBalancePause(device, clock_.nowUs());  // CB TWARN
}

void Bq79616ChainEmulator::setGpioRaw(size_t device, int gpio, int16_t raw) {
  const uint16_t a = static_cast<uint16_t>(kGpio1Hi + 2 * (gpio - 1));
  advanceBalance(device, clock_.nowUs());
  fw::bytes::storeBe16(&devices_.at(device).regs[a], static_cast<uint16_t>(raw));
  checkBalancePause(device, clock_.nowUs());  // OTCB
}

void Bq79616ChainEmulator::attachFaultPin(SimEdgeInput& nfault) {
  nfault_ = &nfault;
  updateFaults();
}

uint8_t Bq79616ChainEmulator::readReg(size_t k, uint16_t address, uint64_t t) const {
  const Device& d = devices_.at(k);
  if (address >= kVcell16Hi && address <= kVcell1Lo) {
    // No conversion yet: the result registers hold 0x8000.
    if (!d.adcRunning || d.adcFrozen || t < d.adcSince + timing_.adcSettleUs)
      return (address - kVcell16Hi) % 2 == 0 ? 0x80 : 0x00;
  }
  if (address >= kVcell16Hi && address <= kVcell1Lo) {
    // The cell as it is now: what was set, less what balancing took out of it (balancing.cpp).
    const int cell = 16 - (address - kVcell16Hi) / 2;
    const int64_t dropUv = bleedDropUv(d.bal.bled[static_cast<size_t>(cell - 1)], cellModel_);
    const int64_t raw = fw::bytes::loadBeI16(&d.regs[static_cast<size_t>(kVcell16Hi + 2 * (16 - cell))]) -
                        (dropUv * 100 + 19073 / 2) / 19073;
    const auto code = static_cast<uint16_t>(std::clamp<int64_t>(raw, -32767, 32767));
    return (address - kVcell16Hi) % 2 == 0 ? static_cast<uint8_t>(code >> 8) : static_cast<uint8_t>(code);
  }
  if (address == kBalStat) return balanceStatus(d);
  if (address == at(r::AdcStat2)) return adcStat2(d, t);
  if (address == kCbComplete1) return static_cast<uint8_t>(d.bal.complete >> 8);
  if (address == kCbComplete2) return static_cast<uint8_t>(d.bal.complete);
  if (address == kCustCrcRsltHi) return static_cast<uint8_t>(custCrcResult(d, t) >> 8);
  if (address == kCustCrcRsltLo) return static_cast<uint8_t>(custCrcResult(d, t));
  if (address == kDevStat) {
    return static_cast<uint8_t>((custCrcDone(d, t) ? kDevStatCustCrcDone : 0) |
                                (d.adcRunning ? b::DevStat::main_run_mask : 0));
  }
  if (address == kFaultSummary) {
    // A masked CRC fault stays latched in FAULT_OTP but does not reach the summary (SLUSE48B).
    const bool crcMasked = (d.regs[kFaultMsk2] & b::FaultMsk2::msk_otp_crc_mask) != 0;
    uint8_t summary = 0;
    for (const Group& g : groups()) {
      for (uint16_t a : g.regs) {
        const uint8_t visible = a == kFaultOtp && crcMasked ? d.regs[a] & ~kOtpCrcBits : d.regs[a];
        if (visible != 0) summary = static_cast<uint8_t>(summary | g.summaryBit);
      }
    }
    return summary;
  }
  if (address == kControl1) return d.regs[kControl1] & b::Control1::dir_sel_mask;  // command bits self-clear
  return d.regs.at(address);
}

// --- pings -----------------------------------------------------------------------------------------------

std::string Bq79616ChainEmulator::onPing(fw::Duration low, uint64_t endUs) {
  ++counters_.pings;
  tick(endUs);
  if (disconnected_) return "";  // the base never sees the line go low
  const uint64_t tNs = static_cast<uint64_t>(low.us) * 1000;
  const uint64_t tol = timing_.pingTolerancePercent;
  const uint64_t bitNs = uart_.byteTimeUs() * 100;  // 10 bit periods per byte
  auto insideNs = [&](uint64_t minNs, uint64_t maxNs) {
    return tNs * 100 >= minNs * (100 + tol) && (maxNs == 0 || tNs * 100 <= maxNs * (100 - tol));
  };
  auto inside = [&](uint64_t minUs, uint64_t maxUs) { return insideNs(minUs * 1000, maxUs * 1000); };
  Device& base = devices_[0];
  // A hung base reacts to nothing but HW_RESET.
  if (insideNs(15 * bitNs, 20 * bitNs)) {
    if (activeAt(base, endUs)) {
      rxBuf_.clear();
      desync_ = false;
      base.regs[kFaultComm1] |= kComm1CommClear;
      updateFaults();
    }
    return "COMM_CLEAR";
  }
  if (inside(250, 300)) {
    if (!base.hung) {
      if (base.power == Power::Sleep) {
        base.power = Power::Active;
        base.readyAt = endUs + timing_.sleepToActiveUs;
      } else if (activeAt(base, endUs)) {
        base.regs[kFaultComm1] |= kComm1CommClear;  // a SLEEPtoACTIVE in ACTIVE is also a comm clear
      }
      rxBuf_.clear();
      desync_ = false;
      toneUp(0, endUs + timing_.sleepToActiveUs, kToneSleepToActive);
      updateFaults();
    }
    return "SLEEPtoACTIVE";
  }
  if (inside(2000, 2500)) {
    if (!base.hung && base.power != Power::HwReset) {
      if (wakesSinceShutdownPing_ < 2) ++wakesSinceShutdownPing_;
      digitalReset(0, endUs + timing_.wakeSetupUs);  // WAKE resets the registers (SLUSE81E §9.4)
      rxBuf_.clear();
      desync_ = false;
      updateFaults();
    }
    return "WAKE";
  }
  if (inside(7000, 10000)) {
    for (size_t k = 0; k < devices_.size() && reaches(k); ++k) {
      if (!devices_[k].hung) devices_[k].power = Power::Shutdown;
    }
    wakesSinceShutdownPing_ = 0;
    updateFaults();
    return "SHUTDOWN";
  }
  if (inside(36000, 0)) {
    base.hung = false;
    base.power = Power::HwReset;
    base.resetUntil = endUs + timing_.hwResetUs;
    resetRegisters(base);
    rxBuf_.clear();
    desync_ = false;
    updateFaults();
    return "HW_RESET";
  }
  ++counters_.rejectedPings;
  return "";
}

// Tones travel up from device `from`: device j (> from) gets its tone (j - from - 1) device-delays later.
void Bq79616ChainEmulator::toneUp(size_t from, uint64_t t, uint8_t kind) {
  if (from == 0 && wakesSinceShutdownPing_ < 2) return;  // the base's daisy-chain port is still off
  for (size_t j = from + 1; j < devices_.size() && reaches(j); ++j) {
    Device& d = devices_[j];
    const uint64_t n = j - from;
    switch (kind) {
      case kToneWake:
        if (d.hung || d.power == Power::HwReset) return;  // a dead device forwards nothing
        digitalReset(j, t + n * (timing_.toneUs + timing_.stackWakeUs));
        break;
      case kToneSleepToActive:
        if (d.hung) return;
        if (d.power == Power::Sleep) {
          d.power = Power::Active;
          d.readyAt = t + n * (timing_.sleepToActiveUs + timing_.sleepToActiveToneUs);
        }
        break;
      case kToneShutdown:
        if (d.hung) return;
        d.power = Power::Shutdown;
        break;
      default:  // HW_RESET resets even a hung device
        d.hung = false;
        d.power = Power::HwReset;
        d.resetUntil = t + n * 1000 + timing_.hwResetUs;
        resetRegisters(d);
        break;
    }
  }
}

// --- frames ----------------------------------------------------------------------------------------------

void Bq79616ChainEmulator::onHostBytes(std::span<const uint8_t> bytes, uint64_t endUs) {
  tick(endUs);
  Device& base = devices_[0];
  if (!activeAt(base, endUs) || desync_ || disconnected_) {
    counters_.ignoredBytes += bytes.size();
    return;
  }
  rxBuf_.insert(rxBuf_.end(), bytes.begin(), bytes.end());
  while (!rxBuf_.empty()) {
    const uint8_t init = rxBuf_[0];
    const uint8_t type = (init >> 4) & 0x07;
    if ((init & 0x80) == 0 || type == 7) {  // not a command frame's first byte
      ++counters_.ignoredBytes;
      base.regs[kFaultComm1] |= kComm1UartRc;
      rxBuf_.erase(rxBuf_.begin());
      continue;
    }
    const FrameType kind{type, type == 0 || type == 2 || type == 4, type == 0 || type == 1};
    const size_t dataBytes = kind.read ? 1 : static_cast<size_t>(init & 0x07) + 1;
    const size_t size = 1 + (kind.single ? 1 : 0) + 2 + dataBytes + 2;
    if (rxBuf_.size() < size) break;  // wait for the rest of the frame
    std::vector<uint8_t> frame(rxBuf_.begin(), rxBuf_.begin() + static_cast<std::ptrdiff_t>(size));
    rxBuf_.erase(rxBuf_.begin(), rxBuf_.begin() + static_cast<std::ptrdiff_t>(size));
    if (fw::crc::crc16(frame.data(), frame.size()) != 0) {
      ++counters_.badCommandCrc;
      base.regs[kFaultComm1] |= kComm1UartRc;
      continue;
    }
    ++counters_.commandFrames;
    process(frame, kind, endUs);
  }
  updateFaults();
}

void Bq79616ChainEmulator::process(const std::vector<uint8_t>& frame, FrameType kind, uint64_t endUs) {
  const auto [type, read, single] = kind;
  const uint8_t target = single ? frame[1] : 0;
  const size_t at = single ? 2 : 1;
  const auto reg = static_cast<uint16_t>((frame[at] << 8) | frame[at + 1]);
  const std::span<const uint8_t> data(frame.data() + at + 2, frame.size() - at - 4);
  const bool reverse = type == 6;
  // A reverse broadcast goes the other way from the base's DIR_SEL: with the normal direction selected it
  // leaves through the port no device is on (no ring in this model), so only the base takes it.
  const bool baseReversed = (devices_[0].regs[kControl1] & b::Control1::dir_sel_mask) != 0;

  std::vector<size_t> reached;
  std::vector<uint64_t> reachedAt(devices_.size(), 0);
  for (size_t k = 0; k < devices_.size(); ++k) {
    if (k > 0 && (!reaches(k) || wakesSinceShutdownPing_ < 2)) break;
    if (k > 0 && reverse && !baseReversed) break;
    Device& d = devices_[k];
    const uint64_t t = endUs + k * timing_.hopUs;
    if (!activeAt(d, t)) break;  // a device that is not awake forwards nothing
    reached.push_back(k);
    reachedAt[k] = t;
    const bool swallow = d.addrWr;  // ADDR_WR: this frame is the device's own, it is not forwarded
    if (!read) {
      const bool mine = type == 5 || type == 6 || (type == 1 && d.regs[kDir0Addr] == target) ||
                        (type == 3 && (d.regs[kCommCtrl] & b::CommCtrl::stack_dev_mask) != 0);
      if (mine) applyWrite(k, reg, data, t);
    }
    if (swallow) {
      d.addrWr = false;
      break;
    }
  }
  if (!read) return;

  const size_t count = static_cast<size_t>(data[0] & 0x7F) + 1;
  std::vector<size_t> order;  // responders, in the order their frames reach the host
  if (type == 0) {
    for (size_t k : reached) {
      if (devices_[k].addressed && devices_[k].regs[kDir0Addr] == target && !devices_[k].muted) {
        order.push_back(k);
        break;
      }
    }
  } else {
    // The device with TOP_STACK starts; every device below it (down to the base for a broadcast read, to the
    // lowest stack device for a stack read) appends its frame once the frame from above has passed.
    size_t top = SIZE_MAX;
    for (size_t k : reached) {
      if (devices_[k].addressed && (devices_[k].regs[kCommCtrl] & b::CommCtrl::top_stack_mask) != 0) top = k;
    }
    if (top == SIZE_MAX) return;
    for (size_t k = top + 1; k-- > 0;) {
      const Device& d = devices_[k];
      const bool stack = (d.regs[kCommCtrl] & b::CommCtrl::stack_dev_mask) != 0;
      if (type == 2 && !stack) break;
      if (!d.addressed || d.muted) break;  // it never answers, so the devices below it keep waiting
      order.push_back(k);
    }
  }
  if (order.empty()) return;
  const size_t first = order.front();
  respond(order, reg, count, reachedAt[first] + timing_.responseUs + first * timing_.hopUs, reachedAt);
}

void Bq79616ChainEmulator::respond(const std::vector<size_t>& order, uint16_t reg, size_t count,
                                   uint64_t startUs, const std::vector<uint64_t>& reachedAt) {
  std::vector<uint8_t> out;
  for (size_t k : order) {
    Device& d = devices_[k];
    advanceBalance(k, reachedAt[k]);
    std::vector<uint8_t> f;
    f.push_back(static_cast<uint8_t>(count - 1));
    f.push_back(d.regs[kDir0Addr] & 0x3F);
    f.push_back(static_cast<uint8_t>(reg >> 8));
    f.push_back(static_cast<uint8_t>(reg));
    for (size_t i = 0; i < count; ++i)
      f.push_back(reg + i < kRegisterSpace ? readReg(k, static_cast<uint16_t>(reg + i), reachedAt[k]) : 0);
    if (reg <= kDevStat && reg + count > kDevStat) {
      // Reading DEV_STAT clears CUST_CRC_DONE (SLUSF21 DEV_STAT).
      d.crcDoneLatched = false;
      d.crcLastRead = reachedAt[k];
    }
    const uint16_t crc = fw::crc::crc16(f.data(), f.size());
    f.push_back(static_cast<uint8_t>(crc));
    f.push_back(static_cast<uint8_t>(crc >> 8));
    if (d.corruptTimes > 0 && d.corruptIndex < f.size()) {
      --d.corruptTimes;
      f[d.corruptIndex] ^= d.corruptMask;
    }
    out.insert(out.end(), f.begin(), f.end());
    ++counters_.responses;
  }
  if (out.size() > truncateAt_) out.resize(truncateAt_);
  truncateAt_ = SIZE_MAX;
  uart_.peerSend(out, startUs);
}

void Bq79616ChainEmulator::applyWrite(size_t k, uint16_t reg, std::span<const uint8_t> data, uint64_t t) {
  for (size_t i = 0; i < data.size(); ++i) {
    const auto a = static_cast<uint16_t>(reg + i);
    if (a < kRegisterSpace) writeReg(k, a, data[i], t);
  }
}

void Bq79616ChainEmulator::writeReg(size_t k, uint16_t address, uint8_t value, uint64_t t) {
  Device& d = devices_[k];
  if (isShadow(address) && d.regs[address] != value) restartCustCrc(k, t);
  if (address == kDir0Addr) {
    if (d.addrWr) {  // only in auto-addressing mode (SLUSE81E §9.5.4.3.9)
      d.regs[kDir0Addr] = value & 0x3F;
      d.addressed = true;
    }
    return;
  }
  if (address == kControl1) {
    d.regs[kControl1] = value & b::Control1::dir_sel_mask;
    if ((value & b::Control1::addr_wr_mask) != 0) d.addrWr = true;
    if ((value & b::Control1::soft_reset_mask) != 0) {
      digitalReset(k, t + 1000);  // tRST 1 ms; the reset also sends a WAKE tone up
      toneUp(k, t + 1000, kToneWake);
      return;
    }
    if ((value & b::Control1::send_wake_mask) != 0) toneUp(k, t, kToneWake);
    if ((value & b::Control1::send_slptoact_mask) != 0) toneUp(k, t, kToneSleepToActive);
    if ((value & b::Control1::send_shutdown_mask) != 0) toneUp(k, t, kToneShutdown);
    if ((value & b::Control1::goto_sleep_mask) != 0) d.power = Power::Sleep;
    if ((value & b::Control1::goto_shutdown_mask) != 0) d.power = Power::Shutdown;
    return;
  }
  if (address == kControl2) {
    d.regs[kControl2] = value & b::Control2::tsref_en_mask;
    if ((value & b::Control2::send_hw_reset_mask) != 0) toneUp(k, t, kToneHwReset);
    return;
  }
  if (address == kFaultRst1) {
    for (const Group& g : groups()) {
      if (g.rst1Bit != 0 && (value & g.rst1Bit) != 0) {
        for (uint16_t a : g.regs)
          d.regs[a] = 0;
      }
    }
    return;
  }
  if (address == kFaultRst2) {
    if ((value & b::FaultRst2::rst_comm1_mask) != 0) d.regs[kFaultComm1] = 0;
    if ((value & b::FaultRst2::rst_comm2_mask) != 0) d.regs[kFaultComm2] = 0;
    if ((value & (b::FaultRst2::rst_comm3_hb_mask | b::FaultRst2::rst_comm3_ftone_mask |
                  b::FaultRst2::rst_comm3_fcomm_mask)) != 0) {
      d.regs[kFaultComm3] = 0;
    }
    if ((value & (b::FaultRst2::rst_otp_crc_mask | b::FaultRst2::rst_otp_data_mask)) != 0) {
      d.regs[kFaultOtp] = 0;
      // A mismatch that is still there latches again when the next pass ends.
      const uint64_t pass = timing_.custCrcUs;
      if (t >= d.crcEpoch) scheduleCrcCheck(k, d.crcEpoch + ((t - d.crcEpoch) / pass + 1) * pass);
    }
    return;
  }
  if (address == kBalCtrl2) {
    // BAL_GO self-clears and samples the balancing settings; CB_PAUSE acts at once (balancing.cpp).
    advanceBalance(k, t);
    d.regs[kBalCtrl2] = static_cast<uint8_t>(value & ~b::BalCtrl2::bal_go_mask);
    if ((value & b::BalCtrl2::bal_go_mask) != 0) {
      balanceGo(k, value, t);
    } else {
      checkBalancePause(k, t);
    }
    return;
  }
  if (address == at(r::DiagCompCtrl3)) return diagCompCtrl3(k, value, t);  // open_wire.cpp
  if (address == kAdcCtrl1) {
    d.regs[kAdcCtrl1] = value;
    const bool go = (value & b::AdcCtrl1::main_go_mask) != 0;
    const auto mode = value & b::AdcCtrl1::main_mode_mask;
    if (go && mode != 0 && !d.adcRunning) {
      d.adcRunning = true;
      d.adcSince = t;
    } else if (mode == 0) {
      d.adcRunning = false;
    }
    return;
  }
  // Read-only registers ignore writes; everything else is stored.
  const auto* e =
      fw::regmap::findByAddress(fw::regmap::bq79616::entries, fw::regmap::Kind::Register, address);
  if (e != nullptr && e->access == fw::regmap::Access::ReadOnly) return;
  d.regs[address] = value;
}

// Re-latches faults whose cause is still there, then drives nFAULT.
void Bq79616ChainEmulator::updateFaults() {
  const uint64_t now = clock_.nowUs();
  tick(now);
  bool stackComm = false;
  for (size_t k = 0; k < devices_.size(); ++k) {
    Device& d = devices_[k];
    if (d.commCause) d.regs[kFaultComm2] |= kComm2Link;
    if (k > 0 && d.regs[kFaultComm2] != 0) stackComm = true;
  }
  // The base learns of a stack device's communication fault through the fault signal and latches FCOMM_DET;
  // the latch comes back as long as a stack device still reports its fault.
  if (stackComm && devices_[0].power == Power::Active) devices_[0].regs[kFaultComm3] |= kComm3Fcomm;
  for (size_t k = 0; k < devices_.size(); ++k)
    faultStopBalance(k, readReg(k, kFaultSummary, now) != 0, now);
  if (nfault_ == nullptr) return;
  bool fault = false;
  const Device& base = devices_[0];
  if (base.power == Power::Active && (base.regs[kDevConf] & b::DevConf::nfault_en_mask) != 0) {
    for (size_t k = 0; k < devices_.size(); ++k) {
      if (devices_[k].power == Power::Active && readReg(k, kFaultSummary, now) != 0) fault = true;
    }
  }
  nfault_->drive(!fault);
}

// --- fault injection -------------------------------------------------------------------------------------

void Bq79616ChainEmulator::breakLinkAbove(size_t device) {
  brokenAbove_ = static_cast<int>(device);
}
void Bq79616ChainEmulator::healLink() {
  brokenAbove_ = -1;
}
void Bq79616ChainEmulator::setMuted(size_t device, bool muted) {
  devices_.at(device).muted = muted;
}
void Bq79616ChainEmulator::corruptResponse(size_t device, size_t index, uint8_t mask, int times) {
  Device& d = devices_.at(device);
  d.corruptIndex = index;
  d.corruptMask = mask;
  d.corruptTimes = times;
}
void Bq79616ChainEmulator::truncateNextResponse(size_t keepBytes) {
  truncateAt_ = keepBytes;
}
void Bq79616ChainEmulator::injectCommFault(size_t device, bool persistent) {
  Device& d = devices_.at(device);
  d.regs[device == 0 ? kFaultComm3 : kFaultComm2] |= device == 0 ? kComm3Fcomm : kComm2Link;
  d.commCause = persistent;
  updateFaults();
}
void Bq79616ChainEmulator::endCommFaultCause(size_t device) {
  devices_.at(device).commCause = false;
}
void Bq79616ChainEmulator::desyncBase() {
  desync_ = true;
}
void Bq79616ChainEmulator::sleepAll() {
  for (Device& d : devices_) {
    if (d.power == Power::Active) d.power = Power::Sleep;
  }
  updateFaults();
}
void Bq79616ChainEmulator::shutdownAll() {
  for (Device& d : devices_)
    d.power = Power::Shutdown;
  updateFaults();
}
void Bq79616ChainEmulator::resetDevice(size_t device) {
  digitalReset(device, clock_.nowUs() + 1000);
  updateFaults();
}
void Bq79616ChainEmulator::hangDevice(size_t device) {
  devices_.at(device).hung = true;
}
void Bq79616ChainEmulator::setDisconnected(bool cut) {
  disconnected_ = cut;
}
void Bq79616ChainEmulator::freezeAdc(size_t device) {
  devices_.at(device).adcFrozen = true;
}

}  // namespace bsp::host
