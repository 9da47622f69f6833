// Bq79616ChainEmulator, the VC open-wire diagnostic (the rest of the device is chain_emulator.cpp).
//
// Sources: SLUSF21 (BQ79616) "Open Wire Detection": a current sink on every VC pin and a current source on
// VC0; with a wire open and the sink (source) on, the pin's filter capacitor is depleted (VC0 pulled up) and
// the cell measurement drops; the diagnostic comparison compares each cell's Main ADC measurement with the
// host's threshold and reports the result in FAULT_COMP_VCOW1/2; SLUSE81E table 9-23: FAULT_COMP_VCOW1/2 are
// part of FAULT_SUMMARY[FAULT_COMP_ADC]. Register layout as TI's BQ79616 register header gives it (checked
// against two BQ79616/BQ79656 drivers that quote TI's procedure and write the same values):
// DIAG_COMP_CTRL2[OW_THR] bits 3:0 (500 mV + 300 mV x OW_THR), DIAG_COMP_CTRL3 COMP_ADC_GO bit 0
// (self-clearing), COMP_ADC_SEL bits 3:1 (010 = VC open wire), OW_SNK bits 5:4 (01 = VC sinks), ADC_STAT2
// [DRDY_VCOW] bit 3, FAULT_COMP_VCOW1 = cells 16..9 and VCOW2 = cells 8..1 (bit 0 = the lowest cell),
// FAULT_COMP_MISC[COMP_ADC_ABORT] bit 1 ("aborted due to improper setting").
// Estimates (TI gives no figure; each is the safe side for the firmware):
// - owDepleteUs (2 ms): how long the sinks must be on before GO for an open pin to read below any threshold.
//   TI's procedure waits 3 ms (0.47 uF at 380 uA minimum); a driver that does not wait sees nothing.
// - owCompareUs (1.5 ms): from GO to DRDY_VCOW; a driver must poll, not assume.
// - A channel that balances during the comparison compares low (its FET loads the cell's filter): the host
//   has to pause balancing for the check, or it reports open wires that are not there.
// - Main ADC not running at GO: COMP_ADC_ABORT, no DRDY_VCOW ("host ensures the Main ADC runs continuously").
// Not modelled: what the readings do while the sinks are on (VCELL registers keep what the test set).
#include "bq79616/chain_emulator.hpp"
#include "bq79616/register_address.hpp"
#include "regmap/bq79616.hpp"

namespace bsp::host {

namespace {

namespace r = fw::regmap::bq79616::reg;

using bq79616_emul::at;
constexpr uint16_t kDiagCompCtrl2 = at(r::DiagCompCtrl2);
constexpr uint16_t kDiagCompCtrl3 = at(r::DiagCompCtrl3);
constexpr uint16_t kActiveCell = at(r::ActiveCell);
constexpr uint16_t kFaultCompVcow1 = at(r::FaultCompVcow1);
constexpr uint16_t kFaultCompVcow2 = at(r::FaultCompVcow2);
constexpr uint16_t kFaultCompMisc = at(r::FaultCompMisc);
constexpr uint8_t kGo = 0x01;
constexpr uint8_t kSelMask = 0x0E, kSelVcOw = 0x02 << 1;
constexpr uint8_t kSnkMask = 0x30, kSnkVc = 0x01 << 4;
constexpr uint8_t kDrdyVcow = 0x08;
constexpr uint8_t kCompAdcAbort = 0x02;

}  // namespace

void Bq79616ChainEmulator::setOpenWire(size_t device, int pin, bool open) {
  Device& d = devices_.at(device);
  const uint32_t bit = 1U << static_cast<unsigned>(pin);
  d.openPins = open ? d.openPins | bit : d.openPins & ~bit;
}

bool Bq79616ChainEmulator::owSinksOn(size_t device) const {
  return (devices_.at(device).regs[kDiagCompCtrl3] & kSnkMask) == kSnkVc;
}

void Bq79616ChainEmulator::diagCompCtrl3(size_t k, uint8_t value, uint64_t t) {
  Device& d = devices_[k];
  const bool wasOn = (d.regs[kDiagCompCtrl3] & kSnkMask) == kSnkVc;
  d.regs[kDiagCompCtrl3] = static_cast<uint8_t>(value & ~kGo);  // COMP_ADC_GO self-clears
  if (!wasOn && (value & kSnkMask) == kSnkVc) d.sinksSince = t;
  if ((value & kGo) == 0 || (value & kSelMask) != kSelVcOw) return;
  ++d.owGeneration;
  if (!d.adcRunning) {
    d.owDoneAt = 0;
    d.regs[kFaultCompMisc] |= kCompAdcAbort;
    updateFaults();
    return;
  }
  // The comparison samples the pins now: an open pin is depleted only if its sink has been on long enough.
  d.owDoneAt = t + timing_.owCompareUs;
  d.owDepleted = (value & kSnkMask) == kSnkVc && wasOn && t >= d.sinksSince + timing_.owDepleteUs;
  const uint32_t gen = d.owGeneration;
  clock_.schedule(d.owDoneAt, [this, k, gen] { owComplete(k, gen); });
}

// The comparison ends: every active cell below OW_THR latches its VCOW bit.
void Bq79616ChainEmulator::owComplete(size_t k, uint32_t generation) {
  Device& d = devices_[k];
  if (generation != d.owGeneration || d.power != Power::Active) return;
  const bool depleted = d.owDepleted;
  const int cells = 6 + (d.regs[kActiveCell] & 0x0F);
  const int32_t thresholdUv = (500 + 300 * (d.regs[kDiagCompCtrl2] & 0x0F)) * 1000;
  advanceBalance(k, d.owDoneAt);
  const uint16_t balancing = bleeding(d);
  uint16_t low = 0;
  for (int n = 1; n <= cells && n <= 16; ++n) {
    // Cell n lies between VC(n-1) and VCn: VCn's sink pulls it down when VCn is open; VC0's source pulls cell
    // 1 down when VC0 is open. Pins above the active cells are not measured.
    const bool open = depleted && ((d.openPins >> n) & 1U || (n == 1 && (d.openPins & 1U) != 0));
    const int32_t uv = static_cast<int32_t>(cellRaw(k, n)) * 19073 / 100;
    if (open || uv < thresholdUv || ((balancing >> (n - 1)) & 1U) != 0)
      low = static_cast<uint16_t>(low | 1U << (n - 1));
  }
  d.regs[kFaultCompVcow1] |= static_cast<uint8_t>(low >> 8);
  d.regs[kFaultCompVcow2] |= static_cast<uint8_t>(low);
  ++owComparisons_;
  updateFaults();
}

// ADC_STAT2[DRDY_VCOW]: the last VC open-wire comparison has ended (cleared by the next GO).
uint8_t Bq79616ChainEmulator::adcStat2(const Device& d, uint64_t t) const {
  return d.owDoneAt != 0 && t >= d.owDoneAt ? kDrdyVcow : 0;
}

}  // namespace bsp::host
