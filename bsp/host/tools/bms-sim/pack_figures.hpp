// Shared helpers for the image simulations: the open-wire sense model, the per-scan bus meter, and the
// figures, frames and protection log every binding reads back from its firmware image the same way.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "app/pack/pack_view.hpp"
#include "app/publish/publish_status.hpp"
#include "image_sim.hpp"
#include "sim/can.hpp"

namespace bmssim {

// The voltage a monitor measures across `cell` (numbered from 1) of a board whose true cell voltages are
// `truth`, with the sense wire below `openCell` disconnected (-1: none): the open cell reads nothing and the
// cell below it reads both. A change to cell c's truth therefore moves the readings of cells c and c - 1.
// The ends have one cell beside them: the bottom tap (openCell 1, VC0, which the BQ79616's current source
// pulls up, SLUSF21) leaves cell 1 reading nothing; the top tap (openCell = cells + 1, drained by the
// devices' open-wire current, SLUUBY2B / SLUSF21) leaves the top cell reading nothing.
inline int sensedMv(std::span<const int> truth, int cell, int openCell) {
  const auto i = static_cast<size_t>(cell - 1);
  if (cell == openCell) return 0;
  if (cell == openCell - 1) return i + 1 < truth.size() ? truth[i] + truth[i + 1] : 0;
  return truth[i];
}

// Highest minus lowest of a set of cell voltages (0 for none).
inline int spreadOf(const std::vector<int>& mv) {
  if (mv.empty()) return 0;
  const auto [lo, hi] = std::minmax_element(mv.begin(), mv.end());
  return *hi - *lo;
}

// The bus cost of one scan. Only a scan that directly follows the previous one in the same link epoch is
// measured: a gap (failed scans in between) or a new epoch (the link was brought up again) would bill the
// retries or the bring-up to the scan.
class ScanMeter {
 public:
  // Call after every step with the scan counter, the link epoch and the running bus totals.
  void observe(uint32_t scans, uint32_t epoch, uint64_t busUs, uint64_t transactions) {
    if (scans == lastScans_) return;
    if (scans == lastScans_ + 1 && epoch == lastEpoch_ && lastScans_ != 0) {
      busUs_ += busUs - lastBusUs_;
      transactions_ += transactions - lastTransactions_;
      ++measured_;
    }
    lastScans_ = scans, lastEpoch_ = epoch, lastBusUs_ = busUs, lastTransactions_ = transactions;
  }

  double meanBusUs() const { return measured_ ? static_cast<double>(busUs_) / measured_ : 0; }
  double meanTransactions() const { return measured_ ? static_cast<double>(transactions_) / measured_ : 0; }

 private:
  uint32_t lastScans_ = 0, lastEpoch_ = 0, measured_ = 0;
  uint64_t lastBusUs_ = 0, lastTransactions_ = 0, busUs_ = 0, transactions_ = 0;
};

// Scan counters (any monitor's stats with `scans` and `scanFailures`) and the meter's means.
template <class ScanStats>
void fillScanFigures(SimFigures& f, const ScanStats& st, fw::Duration period, const ScanMeter& meter) {
  f.scans = st.scans;
  f.scanFailures = st.scanFailures;
  f.scanPeriodMs = period.toMs();
  f.scanBusUs = meter.meanBusUs();
  f.scanTransactions = meter.meanTransactions();
}

// Every CAN frame the simulated controller put on the wire, with its completion time.
inline std::vector<SentFrame> canFrames(const bsp::host::SimCan& can) {
  std::vector<SentFrame> out;
  for (const auto& s : can.sent())
    out.push_back(
        {s.timeUs, s.frame.id, s.frame.extended, {s.frame.data.begin(), s.frame.data.begin() + s.frame.dlc}});
  return out;
}

// The controller's bus-offs as bms-sim reports them.
inline std::vector<BusOffSpan> busOffSpans(const bsp::host::SimCan& can) {
  std::vector<BusOffSpan> out;
  for (const auto& s : can.busOffLog())
    out.push_back({s.startUs, s.recoveredUs != 0 ? std::optional<uint64_t>(s.recoveredUs) : std::nullopt});
  return out;
}

// The paths of a pack whose fault output stands for them (the BQ79616 and BQ4050 images: the output drives
// the contactor or the FETs' enable, high = fault): both open while it is asserted.
inline Paths pathsOfFaultOutput(bool asserted) {
  return {!asserted, !asserted};
}

template <class App>
std::vector<fw::app::ProtectionRecord> protectionLogOf(const App& app) {
  const auto log = app.protection().log();
  return {log.begin(), log.end()};
}

inline void fillPackFigures(SimFigures& f, const fw::app::PackView& view, const fw::app::PublishStatus& st,
                            fw::Instant now, fw::Duration staleAfter) {
  f.boards = static_cast<int>(view.boards.size());
  f.validBoards = 0;
  bool any = false;
  for (const auto& b : view.boards) {
    if (fw::app::boardStatus(b, now, staleAfter) != fw::app::BoardStatus::Valid) continue;
    ++f.validBoards;
    for (uint8_t c = 0; c < view.cellsPerBoard; ++c) {
      f.minCellMv = any ? std::min<int>(f.minCellMv, b.cellMv[c]) : b.cellMv[c];
      f.maxCellMv = any ? std::max<int>(f.maxCellMv, b.cellMv[c]) : b.cellMv[c];
      any = true;
    }
  }
  f.currentMa = view.hasCurrent ? view.currentMa : 0;
  f.chargeOn = st.chargeOn;
  f.dischargeOn = st.dischargeOn;
  f.pathsKnown = st.pathsKnown;
  f.faultOutput = st.faultOutput;
  f.activeFaults = st.active;
  if (view.soc.known()) {
    f.stateOfChargePercent = (view.soc.permille + 5) / 10;  // as PackSummary rounds it
    f.socPermille = view.soc.permille;
    f.remainingMah = view.soc.remainingMah;
    f.fullChargeMah = view.soc.fullChargeMah;
    f.socBasis = static_cast<int>(view.soc.basis);
  }
}

}  // namespace bmssim
