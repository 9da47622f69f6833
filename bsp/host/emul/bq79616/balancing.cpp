// Bq79616ChainEmulator, cell balancing (the rest of the device is chain_emulator.cpp). Sources: SLUSE81E
// (BQ79616-Q1) and SLUSF21 (BQ79616) BAL_CTRL1/2, BAL_STAT, CB_CELLn_CTRL, OTCB_THRESH pages and the cell
// balancing section; SLUSDT5B (BQ75614-Q1, the same balancing block) for the manual control rules; SLUSEF2B
// (BQ756506-Q1) for TWARN and ABORTFLT details. The state advances lazily: every read, write and backend
// call first brings a device's balancing up to that moment (advanceBalance), cutting at each timer expiry and
// duty switch, so the charge each cell loses is exact for any read pattern.
#include <algorithm>

#include "bq79616/chain_emulator.hpp"
#include "bq79616/register_address.hpp"
#include "regmap/bq79616.hpp"

namespace bsp::host {

namespace {

namespace r = fw::regmap::bq79616::reg;
namespace b = fw::regmap::bq79616::bits;

using bq79616_emul::at;
constexpr uint16_t kCbCell16Ctrl = at(r::CbCell16Ctrl);
constexpr uint16_t kBalCtrl1 = at(r::BalCtrl1);
constexpr uint16_t kBalCtrl2 = at(r::BalCtrl2);
constexpr uint16_t kOtcbThresh = at(r::OtcbThresh);
constexpr uint16_t kDevConf = at(r::DevConf);
constexpr uint16_t kGpio1Hi = at(r::Gpio1Hi);
constexpr uint16_t kDietemp1Hi = at(r::Dietemp1Hi);
constexpr uint16_t kVcell16Hi = at(r::Vcell16Hi);
constexpr size_t vcellHi(int cell) {  // VCELL16 first
  return static_cast<size_t>(kVcell16Hi + 2 * (16 - cell));
}
static_assert(at(r::CbCell1Ctrl) == kCbCell16Ctrl + 15, "CB_CELL16_CTRL..CB_CELL1_CTRL are consecutive");

using BalStat = b::BalStat;
using BalCtrl2 = b::BalCtrl2;

// CB_CELLn_CTRL TIME[4:0] (SLUSE81E; BQ75614-Q1 SLUSDT5B the same): 0 stop, 1 10 s, 2 30 s, 3 60 s, 4 300 s,
// 0x05..0x10 10..120 min in 10 min steps, 0x11..0x1E 150..540 min in 30 min steps, 0x1F 600 min.
uint64_t timerUs(uint8_t code) {
  code &= 0x1F;
  constexpr uint64_t kS = 1000000;
  constexpr uint64_t kMin = 60 * kS;
  if (code == 0) return 0;
  if (code <= 4) {
    constexpr uint64_t kFirst[] = {0, 10 * kS, 30 * kS, 60 * kS, 300 * kS};
    return kFirst[code];
  }
  if (code <= 0x10) return (code - 4U) * 10 * kMin;
  if (code == 0x1F) return 600 * kMin;
  return (120 + (code - 0x10U) * 30) * kMin;
}

// BAL_CTRL1 DUTY[2:0]: the odd/even switch period of automatic control, 5 s, 10 s, 30 s, 60 s, 5, 10, 20,
// 30 min (SLUSE81E BAL_CTRL1).
uint64_t dutyUs(uint8_t ctrl1) {
  constexpr uint64_t kS = 1000000;
  constexpr uint64_t kDuty[] = {5 * kS, 10 * kS, 30 * kS, 60 * kS, 300 * kS, 600 * kS, 1200 * kS, 1800 * kS};
  return kDuty[ctrl1 & 7U];
}

int popcount(uint32_t v) {
  int n = 0;
  for (; v != 0; v &= v - 1)
    ++n;
  return n;
}

int16_t loadBe16(const uint8_t* p) {
  return static_cast<int16_t>((p[0] << 8) | p[1]);
}

}  // namespace

int32_t Bq79616ChainEmulator::setMicrovolts(const Device& d, int cell) const {
  const uint8_t* p = &d.regs[vcellHi(cell)];
  return static_cast<int32_t>(loadBe16(p)) * 19073 / 100;
}

// The channels that bleed now: running, not paused, timer left; automatic control alternates odd and even
// channels every duty period, and runs one group all the time when the other has nothing to do (SLUSDT5B
// "Example 2: ... the device is not switched between odd or even channels").
uint16_t Bq79616ChainEmulator::bleeding(const Device& d) const {
  const auto& bal = d.bal;
  const bool hostPause = BalCtrl2::fromRaw(d.regs[kBalCtrl2]).cb_pause();
  if (!bal.running || bal.otPause || hostPause) return 0;
  uint16_t on = 0;
  for (size_t c = 0; c < 16; ++c) {
    if (bal.leftUs[c] != 0) on = static_cast<uint16_t>(on | (1U << c));
  }
  if (!bal.automatic) return on;
  const auto odd = static_cast<uint16_t>(on & 0x5555U);  // bit 0 = cell 1
  const auto even = static_cast<uint16_t>(on & 0xAAAAU);
  if (odd == 0 || even == 0) return on;
  return bal.odd ? odd : even;
}

uint8_t Bq79616ChainEmulator::balanceStatus(const Device& d) const {
  const auto& bal = d.bal;
  const bool paused = bal.running && (bal.otPause || BalCtrl2::fromRaw(d.regs[kBalCtrl2]).cb_pause());
  return static_cast<uint8_t>(bal.status | (bal.running ? BalStat::cb_run_mask : 0) |
                              (paused ? BalStat::cb_inpause_mask : 0) |
                              (bal.running && bal.otPause ? BalStat::ot_pause_det_mask : 0));
}

// Brings device k's balancing to time t: timers count down only while their channel bleeds ("Cell balancing
// timers will continue the count down" once a pause ends, SLUSE81E 9.3.3.3.1), a channel stops when its timer
// runs out (CB_COMPLETE), and balancing ends when every timer has (CB_DONE).
void Bq79616ChainEmulator::advanceBalance(size_t k, uint64_t t) {
  Device& d = devices_[k];
  auto& bal = d.bal;
  while (bal.untilUs < t) {
    const uint16_t on = bleeding(d);
    if (on == 0) {
      bal.untilUs = t;
      break;
    }
    uint64_t step = t - bal.untilUs;
    const bool both = bal.automatic && [&] {
      uint16_t all = 0;
      for (size_t c = 0; c < 16; ++c) {
        if (bal.leftUs[c] != 0) all = static_cast<uint16_t>(all | (1U << c));
      }
      return (all & 0x5555U) != 0 && (all & 0xAAAAU) != 0;
    }();
    if (both) step = std::min(step, bal.phaseLeftUs);
    for (size_t c = 0; c < 16; ++c) {
      if (((on >> c) & 1U) != 0) step = std::min(step, bal.leftUs[c]);
    }
    for (size_t c = 0; c < 16; ++c) {
      if (((on >> c) & 1U) == 0) continue;
      const int64_t uv = std::max<int64_t>(0, cellNowMicrovolts(k, static_cast<int>(c + 1)));
      if (cellModel_.balanceOhms != 0)
        bal.bled[c] +=
            uv * static_cast<int64_t>(step) / (1000 * static_cast<int64_t>(cellModel_.balanceOhms));
      bal.leftUs[c] -= step;
      if (bal.leftUs[c] == 0) {
        bal.complete = static_cast<uint16_t>(bal.complete | (1U << c));
        ++balanceCounters_.expired;
      }
    }
    if (both) {
      bal.phaseLeftUs -= step;
      if (bal.phaseLeftUs == 0) {
        bal.odd = !bal.odd;
        bal.phaseLeftUs = bal.dutyUs;
      }
    }
    bal.untilUs += step;
    if (std::all_of(bal.leftUs.begin(), bal.leftUs.end(), [](uint64_t v) { return v == 0; })) {
      bal.running = false;
      bal.status = static_cast<uint8_t>(bal.status | BalStat::cb_done_mask);
    }
  }
}

// BAL_CTRL2 written with BAL_GO: "all balancing configuration registers are sampled" (SLUSE81E BAL_CTRL2).
// BAL_GO clears ABORTFLT (SLUSEF2B BAL_STAT) and the last start's INVALID_CBCONF and CB_DONE. Manual control
// (AUTO_BAL = 0) turns on every channel with a non-zero timer at once, at most eight, and neighbours only
// without DEV_CONF[NO_ADJ_CB]; otherwise balancing does not start and BAL_STAT[INVALID_CBCONF] is set
// (SLUSF21 8.3.3.1.2; SLUSDT5B: "a maximum of eight CBFETs can be enabled"). All timers 0 stops balancing
// (the host's stop, SLUSE81E 9.3.3.3).
void Bq79616ChainEmulator::balanceGo(size_t k, uint8_t ctrl2, uint64_t t) {
  advanceBalance(k, t);
  Device& d = devices_[k];
  auto& bal = d.bal;
  const auto ctrl = BalCtrl2::fromRaw(ctrl2);
  bal.status = 0;
  bal.complete = 0;
  bal.running = false;
  uint16_t channels = 0;
  for (int cell = 1; cell <= 16; ++cell) {
    const uint8_t code = d.regs[static_cast<size_t>(kCbCell16Ctrl + 16 - cell)];
    bal.leftUs[static_cast<size_t>(cell - 1)] = timerUs(code);
    if (timerUs(code) != 0) channels = static_cast<uint16_t>(channels | (1U << (cell - 1)));
  }
  bal.automatic = ctrl.auto_bal();
  bal.faultStop = ctrl.fltstop_en();
  bal.otcb = ctrl.otcb_en();
  const bool noAdjacent = b::DevConf::fromRaw(d.regs[kDevConf]).no_adj_cb();
  if (!bal.automatic && (popcount(channels) > 8 || (noAdjacent && (channels & (channels >> 1)) != 0))) {
    bal.leftUs.fill(0);
    bal.status = BalStat::invalid_cbconf_mask;
    ++balanceCounters_.invalid;
    return;
  }
  if (channels == 0) return;
  bal.running = true;
  bal.odd = true;
  bal.dutyUs = bal.phaseLeftUs = dutyUs(d.regs[kBalCtrl1]);
  bal.untilUs = t;
  ++balanceCounters_.started;
  checkBalancePause(k, t);
}

// Pauses (SLUSE81E BAL_STAT, OTCB_THRESH, 9.3.3.3.1): BAL_CTRL2[CB_PAUSE]; the die past CB TWARN
// (kCbTwarnRaw, an assumed 105 degC inside SLUSEF2B's 85..115 degC TWARN range, 10 degC hysteresis); with
// OTCB_EN an NTC on a GPIO ADC input (a reading other than 0x8000) below OTCB_THR[3:0] = 10 % + 2 % per step
// of TSREF, released above OTCB_THR + COOLOFF[6:4] = 4 % + 2 % per step (TSREF taken as 5 V: 1 % = 327.7 GPIO
// LSB of 152.59 uV).
void Bq79616ChainEmulator::checkBalancePause(size_t k, uint64_t t) {
  advanceBalance(k, t);
  Device& d = devices_[k];
  auto& bal = d.bal;
  bool warm = false;
  for (int i = 0; i < 2; ++i) {
    const int16_t raw = loadBe16(&d.regs[static_cast<size_t>(kDietemp1Hi + 2 * i)]);
    warm = warm || raw > (bal.otPause ? kCbTwarnRaw - kCbTwarnHysRaw : kCbTwarnRaw);
  }
  if (bal.otcb) {
    const uint8_t th = d.regs[kOtcbThresh];
    const int32_t tripPct = 10 + 2 * (th & 0x0F);
    const int32_t releasePct = tripPct + 4 + 2 * ((th >> 4) & 0x07);
    for (int g = 0; g < 8; ++g) {
      const int16_t raw = loadBe16(&d.regs[static_cast<size_t>(kGpio1Hi + 2 * g)]);
      if (raw == static_cast<int16_t>(-32768)) continue;
      const int32_t pctX10 = raw * 10 / 328;  // % of TSREF, tenths
      warm = warm || pctX10 < (bal.otPause ? releasePct : tripPct) * 10;
    }
  }
  if (warm && !bal.otPause && bal.running) ++balanceCounters_.paused;
  bal.otPause = warm;
}

// FLTSTOP_EN (sampled by BAL_GO): an unmasked fault stops all balancing and sets ABORTFLT, except while
// balancing is paused ("CB abort does not trigger if CB is in pause", SLUSEF2B BAL_STAT). Called whenever the
// faults may have changed (updateFaults()).
void Bq79616ChainEmulator::faultStopBalance(size_t k, bool fault, uint64_t t) {
  advanceBalance(k, t);
  Device& d = devices_[k];
  auto& bal = d.bal;
  const bool paused = bal.otPause || BalCtrl2::fromRaw(d.regs[kBalCtrl2]).cb_pause();
  if (!fault || !bal.running || !bal.faultStop || paused) return;
  bal.running = false;
  bal.leftUs.fill(0);
  bal.status = static_cast<uint8_t>(bal.status | BalStat::abortflt_mask);
  ++balanceCounters_.aborted;
}

uint16_t Bq79616ChainEmulator::balancingCells(size_t device) {
  advanceBalance(device, clock_.nowUs());
  return bleeding(devices_.at(device));
}

uint8_t Bq79616ChainEmulator::balStat(size_t device) {
  advanceBalance(device, clock_.nowUs());
  return balanceStatus(devices_.at(device));
}

int32_t Bq79616ChainEmulator::cellNowMicrovolts(size_t device, int cell) {
  const Device& d = devices_.at(device);
  return setMicrovolts(d, cell) -
         static_cast<int32_t>(bleedDropUv(d.bal.bled[static_cast<size_t>(cell - 1)], cellModel_));
}

int64_t Bq79616ChainEmulator::bledChargeMaUs(size_t device, int cell) {
  advanceBalance(device, clock_.nowUs());
  return devices_.at(device).bal.bled.at(static_cast<size_t>(cell - 1));
}

}  // namespace bsp::host
