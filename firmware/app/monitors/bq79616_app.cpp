#include "app/monitors/bq79616_app.hpp"

#include "app/protection/default_limits.hpp"
#include "regmap/bq79616.hpp"

namespace fw::app {

namespace b616 = drivers::bq79616;

// Bring-up or recovery ended: run with the devices that answer (CommFault names the missing one); otherwise
// try again after retryAfterFailure.
inline void Bq79616Device::setupFinished(Status result) {
  using b616::RecoveryLevel;
  const bool wasRecovery = flags_->broughtUp;
  if (result == Status::Ok || (result == Status::CommFault && driver_.devices() > 0)) {
    setRunning(view_, true);
    forgetBalancing();
    flags_->broughtUp = true;
    // The devices' own open-wire check after the first scan: a WAKE reset the diagnostic, and a wire may
    // have opened while the chain was down. The last verdict stands until it has run.
    flags_->openWireDue = config_.openWireEvery != 0;
    loop_->scanDue = true;  // (failedInRow is 0: the loop cleared it before recover())
    // If the scans fail again before one validates, this rung was not enough: the next recovery starts one
    // higher (a chain that answers but whose ADC was never restarted needs the full bring-up).
    const RecoveryLevel reached = driver_.lastRecovery();
    if (wasRecovery) {
      flags_->from = reached == RecoveryLevel::HardwareReset
                         ? reached
                         : static_cast<RecoveryLevel>(static_cast<uint8_t>(reached) + 1);
    }
    return;
  }
  // A failed ladder has sent a WAKE at least (its last rungs are full bring-ups), so the registers are reset:
  // only a full bring-up can bring the chain back, whatever a lighter rung's probe would say.
  if (wasRecovery && flags_->from < RecoveryLevel::Rewake) flags_->from = RecoveryLevel::Rewake;
  scheduler_.startTimer(records_->retryTimer, kMonitorTask, monitor_event::kRetry, config_.retryAfterFailure);
}

namespace {
// A device's cell codes as mV and as the codes kept for the TI layout, the `suspect` cells (bit c = cell c)
// as the no-reading 0 (a code of 0 is 0 mV). Its own function: inside scanFinished()'s device loop the
// compiler ran out of registers and kept the loop's values on the stack (twin profile, 64 devices). The
// suspect cells are cleared after the conversion, in a loop that runs only when there are any: tested in the
// conversion loop they cost 6 of its 24 cycles a cell.
[[gnu::noinline]] void convertCells(int16_t* mv, int16_t* raw, const int16_t* codes, uint8_t cells,
                                    uint32_t suspect) {
  for (uint8_t c = 0; c < cells; ++c) {
    // 190.73 uV per code = 12 500 / 65 536 mV within 0.003 %: a multiply and a shift instead of a division
    // per cell, exact to the millivolt over the whole range (+-1 mV rounding).
    const int32_t code = codes[c];
    mv[c] = static_cast<int16_t>((code * 12500 + 32768) >> 16);
    raw[c] = static_cast<int16_t>(code);
  }
  suspect &= (1U << cells) - 1U;  // cells <= 16: the bit above the top cell is no cell of the device
  for (uint8_t c = 0; suspect != 0; ++c, suspect >>= 1) {
    if ((suspect & 1U) != 0) mv[c] = raw[c] = 0;
  }
}
}  // namespace

inline ScanVerdict Bq79616Device::scanFinished(Status result, Instant now) {
  if (kStats) records_->stats.lastScan = elapsed(records_->summary.started, now);
  bool anyValid = false;
  bool deviceFault = false;
  // Walked with pointers: the three per-device arrays have different strides.
  const b616::DeviceRecord* r = store_.records;
  BoardSample* s = store_.samples;
  int16_t* raw = store_.raw[0];
  const uint16_t* failing = store_.openWire;
  const uint8_t cells = config_.chain.activeCells;
  for (uint16_t d = view_.boardCount(); d != 0; --d, ++r, ++s, raw += b616::kCellsPerDevice, ++failing) {
    s->last = r->status != Status::Ok ? r->status
                                      : ((r->valid & b616::kValidCells) ? Status::Ok : Status::NotReady);
    if (s->last != Status::Ok) continue;
    // The device's own open-wire verdict: a cell below the threshold and the cell above it sit beside the pin
    // that may be open (VCn's sink pulls cell n down and cell n + 1 up; VC0's source pulls cell 1 down), so
    // neither reading is a cell voltage, however plausible it looks: both get the no-reading 0 mV.
    const uint32_t suspect = static_cast<uint32_t>(*failing) | static_cast<uint32_t>(*failing) << 1;
    convertCells(s->cellMv, raw, r->cellRaw, cells, suspect);
    const bool temps = (r->valid & b616::kValidDieTemp) != 0;  // a failed temperature read is no reading
    s->tempDeciK[0] = temps ? r->dieTemp[0] : kNoReading;
    s->tempDeciK[1] = temps ? r->dieTemp[1] : kNoReading;
    deviceFault = deviceFault || ((r->valid & b616::kValidFaults) != 0 && r->faultSummary != 0);
    s->takenAt = r->takenAt;
    s->valid = anyValid = true;
  }
  // A BQ79616 fault has no direction (its image has no FETs): both paths, which the fault output stands for.
  view_.deviceBlocks = deviceFault ? static_cast<uint8_t>(Action::AllOff) : 0;
  // Every device in use validated (all of them, or all a degraded chain still has): whatever failed before is
  // over, and the next recovery may start at the lightest rung again.
  if (driver_.devices() != 0 && records_->summary.validDevices == driver_.devices())
    flags_->from = b616::RecoveryLevel{};
  return {.newData = anyValid, .failed = result != Status::Ok};
}

// --- balancing ------------------------------------------------------------------------------------------

// After a bring-up or recovery: a WAKE reset every balancing register, a lighter rung did not; whatever was
// written is forgotten, and if anything was, one broadcast stop makes sure nothing balances that the policy
// does not want.
void Bq79616Device::forgetBalancing() {
  auto& f = *flags_;
  bool any = false;
  for (uint8_t d = 0; d < config_.chain.devices; ++d) {
    any = any || store_.balanceWritten[d] != 0;
    store_.balanceWritten[d] = 0;
    store_.balancing.cells[d] = 0;
  }
  f.stopWanted = any;
  f.dirty = 0;
}

// Once per scan, after protection saw it: the time of what stands confirmed, the policy's masks, and the work
// for the chain.
inline void Bq79616Device::balanceCheck() {
  auto& f = *flags_;
  auto& r = *records_;
  BalancingStatus& st = store_.balancing;
  const Instant now = scheduler_.now();
  const uint8_t devices = config_.chain.devices;
  st.account(devices, elapsed(r.lastCheck, now));
  r.lastCheck = now;
  policy_.decide(view_, status_.active, now, {store_.balanceWant, devices});
  st.setMode(policy_.mode());
  st.state = policy_.state();
  f.budget = kBalanceAppliesPerScan;
  // The next open-wire check, every openWireEvery scans (counted from the start of the last one).
  if (!f.openWireDue && config_.openWireEvery != 0 && --f.openWireIn == 0) f.openWireDue = true;
  const bool refresh = isDue(r.refreshAt, now);
  if (refresh) r.refreshAt = now + s(10);  // a third of the 30 s the timers run (Balancer::kTimerCode)
  bool wanted = false;
  bool standing = false;  // written or confirmed somewhere
  for (uint8_t d = 0; d < devices; ++d) {
    const uint16_t want = store_.balanceWant[d];
    const uint16_t written = store_.balanceWritten[d];
    wanted = wanted || want != 0;
    standing = standing || written != 0 || st.cells[d] != 0;
    if (want != written || (refresh && written != 0)) f.dirty |= uint64_t{1} << d;
  }
  if (!wanted && standing) {
    // Nothing balances from now on: one broadcast stop instead of a write per device.
    f.stopWanted = true;
    f.dirty = 0;
  }
  if (standing && isDue(r.statusAt, now)) {
    f.statusWanted = true;
    r.statusAt = now + s(1);
  }
}

inline Status Bq79616Device::startCommand() {
  auto& f = *flags_;
  Status started;
  if (f.openWireDue) {
    // The check pauses balancing itself (BAL_CTRL2[CB_PAUSE], timers held) and resumes it (open_wire.hpp).
    f.op = BalanceOp::OpenWire;
    f.openWireDue = false;
    f.openWireIn = config_.openWireEvery;
    records_->openWireStarted = scheduler_.now();
    started = openWire_.start({store_.openWire, config_.chain.devices});
  } else if (f.stopWanted) {
    f.op = BalanceOp::Stop;
    started = balancer_.startStopAll();
  } else if (f.dirty != 0 && f.budget != 0) {
    uint8_t d = 0;
    while (((f.dirty >> d) & 1U) == 0)
      ++d;
    f.op = BalanceOp::Apply;
    f.device = d;
    f.sending = store_.balanceWant[d];
    --f.budget;
    started = balancer_.startApply(d, f.sending);
    if (started == Status::InvalidArgument) f.dirty &= ~(uint64_t{1} << d);  // the policy keeps the rules
  } else {
    f.op = BalanceOp::Status;
    f.statusWanted = false;
    started = balancer_.startStatus(store_.balStat);
  }
  if (started != Status::Ok) {
    f.op = BalanceOp::None;
    f.budget = 0;  // the chain refused: again next scan period
  }
  return started;
}

// A frame of the balancing operation ended: the next one goes out, or the operation's result is taken.
inline void Bq79616Device::commandFinished(Status result) {
  if (flags_->op == BalanceOp::OpenWire) {
    if (openWire_.step(result)) {
      loop_->op = MonitorOp::Command;
      return;
    }
    flags_->op = BalanceOp::None;
    return openWireFinished();
  }
  if (balancer_.step(result)) {
    loop_->op = MonitorOp::Command;  // the next frame is on the bus: its completion comes back here
    return;
  }
  auto& f = *flags_;
  const BalanceOp op = f.op;
  f.op = BalanceOp::None;
  result = balancer_.result();
  if (result != Status::Ok) {
    // The chain failed (it recovers on its own): what the devices do is not known; again next period.
    f.budget = 0;
    if (op == BalanceOp::Status) {
      for (uint8_t d = 0; d < config_.chain.devices; ++d)
        store_.balancing.cells[d] = 0;
    }
    return;
  }
  switch (op) {
    case BalanceOp::Stop:
      f.stopWanted = false;
      for (uint8_t d = 0; d < config_.chain.devices; ++d)
        store_.balanceWritten[d] = 0;
      f.statusWanted = true;  // confirm it
      break;
    case BalanceOp::Apply:
      store_.balanceWritten[f.device] = f.sending;
      f.dirty &= ~(uint64_t{1} << f.device);
      if (f.dirty == 0) f.statusWanted = true;  // confirm what started
      break;
    case BalanceOp::Status:
      balanceStatusRead();
      break;
    case BalanceOp::None:
    case BalanceOp::OpenWire:
      break;
  }
}

// The open-wire check ended: its verdict (already in store_.openWire) applies from the next scan on. Without
// one (the chain failed, the comparison never ended) the last verdict stands: an open wire found stays
// open_wire until a check says otherwise.
void Bq79616Device::openWireFinished() {
  auto& st = records_->stats;
  if (openWire_.verdict()) {
    ++st.openWireChecks;
  } else {
    ++st.openWireFailed;
  }
  st.lastOpenWireCheck = elapsed(records_->openWireStarted, scheduler_.now());
}

// BAL_STAT of every device: a device balances its written cells while it reports CB_RUN and no pause; a
// device that stopped (timers out, ABORTFLT) has nothing written any more; INVALID_CBCONF or ABORTFLT make
// the policy back off (SLUSE81E BAL_STAT).
void Bq79616Device::balanceStatusRead() {
  using Stat = ::fw::regmap::bq79616::bits::BalStat;
  bool refused = false;
  for (uint8_t d = 0; d < config_.chain.devices; ++d) {
    const auto st = Stat::fromRaw(store_.balStat[d]);
    const bool running = st.cb_run() && !st.cb_inpause();
    store_.balancing.cells[d] = running ? store_.balanceWritten[d] : 0;
    if (!st.cb_run()) store_.balanceWritten[d] = 0;
    refused = refused || st.invalid_cbconf() || st.abortflt();
  }
  if (refused) policy_.refused(scheduler_.now());
}

// The image's monitor task: its code (the loop with the chain's part folded in) is compiled here once.
template class MonitorTask<Bq79616Device>;

}  // namespace fw::app
