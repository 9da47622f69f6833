// The outage sweep of issue 15, for any board rig of an image: the monitor's link fails (an outage of a kind
// the rig knows) for a given length starting at a given point of the scan period, then heals. The sweep
// asserts that good scans resume within a bound after the heal, with comm_loss/stale_data cleared and the
// fault output off unless comm_rate holds it (then off within rateWindow scan periods more), and that no scan
// completed in between published a board as valid unless its values were measured outside the outage. It
// prints the worst recovery time as a REPORT line.
//
// A Board provides: `h` (Harness), `app` (pack(), status(), monitor().stats().scans), `faultOut`, `config`
// (scanPeriod), and `void setOutage(int kind, bool on)`, `static const char* outageName(int kind)`.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/protection/protection.hpp"
#include "core/status.hpp"
#include "core/time.hpp"

namespace test {

// A measurement already on its way when the outage starts still completes: values measured up to this long
// after the start are from before it.
inline constexpr uint64_t kInFlightUs = 5000;

template <class Board>
class OutageRig {
 public:
  explicit OutageRig(std::unique_ptr<Board> board) : board_(std::move(board)) {}

  // Runs the board from power-on to its first good scan (recovered()); returns that time.
  uint64_t boot() {
    EXPECT_TRUE(run([&] { return recovered(0); }, fw::s(10))) << "the board never came up";
    return board_->h.nowUs();
  }

  // One outage of `lengthUs` starting `phaseUs` into a scan period; returns the time from the heal to good
  // scans, or UINT64_MAX if they did not come within `limit`.
  uint64_t outage(int kind, uint64_t lengthUs, uint64_t phaseUs, fw::Duration limit) {
    const uint64_t period = board_->config.scanPeriod.us;
    const uint64_t t0 = (board_->h.nowUs() / period + 2) * period + phaseUs;
    EXPECT_TRUE(run([&] { return board_->h.nowUs() >= t0; }, fw::s(1)));
    board_->setOutage(kind, true);
    from_ = board_->h.nowUs();
    to_ = from_ + lengthUs;
    EXPECT_TRUE(
        run([&] { return board_->h.nowUs() >= to_; }, fw::us(static_cast<uint32_t>(lengthUs + 1000))));
    board_->setOutage(kind, false);
    const uint64_t healed = to_ = board_->h.nowUs();
    const bool ok = run([&] { return recovered(healed); }, limit);
    const uint64_t took = board_->h.nowUs() - healed;
    run([] { return false; }, fw::ms(300));  // and it stays so
    EXPECT_TRUE(recovered(healed)) << "relapsed after recovering";
    // comm_rate, if the outage tripped it, lets the paths on once rateWindow scans in a row validated.
    EXPECT_TRUE(run([&] { return released(); }, fw::us(static_cast<uint32_t>(period * 11))))
        << "the fault output still on " << period * 11 / 1000 << " ms after recovering";
    released_ = std::max(released_, board_->h.nowUs() - healed);
    return ok ? took : UINT64_MAX;
  }

  int badPublications() const { return bad_; }
  uint64_t worstReleaseUs() const { return released_; }  // from the heal to the fault output off
  Board& board() { return *board_; }

 private:
  // Every board's latest attempt validated, with values measured at or after `sinceUs`; neither comm_loss nor
  // stale_data is active, and the fault output is off unless comm_rate holds it: an outage long enough to
  // fail four scan attempts trips it, and it clears only once rateWindow attempts in a row validated (checked
  // after recovery by outage()).
  bool recovered(uint64_t sinceUs) const {
    for (const auto& s : board_->app.pack().boards) {
      if (!s.valid || s.last != fw::Status::Ok || board_->h.clock.expand(s.takenAt) < sinceUs) return false;
    }
    using fw::app::FaultId;
    const auto active = board_->app.status().active;
    return (!board_->faultOut.level() || (active & fw::app::bit(FaultId::CommErrorRate)) != 0) &&
           (active & (fw::app::bit(FaultId::CommLoss) | fw::app::bit(FaultId::StaleData))) == 0;
  }
  // The fault output off, with no fault active.
  bool released() const { return !board_->faultOut.level() && board_->app.status().active == 0; }

  // Runs until `done` holds or `limit` passes, checking each scan the monitor publishes.
  bool run(const std::function<bool()>& done, fw::Duration limit) {
    return board_->h.runUntil(
        [&] {
          const uint32_t scans = board_->app.monitor().stats().scans;
          if (scans != scans_) {
            scans_ = scans;
            check();
          }
          return done();
        },
        limit);
  }

  // No board may be published as valid with values measured during the outage.
  void check() {
    for (const auto& s : board_->app.pack().boards) {
      if (s.last != fw::Status::Ok) continue;
      const uint64_t t = board_->h.clock.expand(s.takenAt);
      if (t > from_ + kInFlightUs && t < to_) {
        ++bad_;
        ADD_FAILURE() << "a board was published valid with values measured at " << t
                      << " us, inside the outage " << from_ << ".." << to_;
      }
    }
  }

  std::unique_ptr<Board> board_;
  uint32_t scans_ = 0;
  uint64_t from_ = UINT64_MAX, to_ = 0;
  uint64_t released_ = 0;
  int bad_ = 0;
};

struct OutageGrid {
  std::vector<uint64_t> lengthsMs;
  std::vector<uint64_t> phasesMs;
  std::vector<int> kinds;
};

// Runs the grid on fresh boards (one per outage kind, the outages one after another on it) and asserts the
// bound, given as a function of the board's power-on-to-first-good-scan time. `label` names the REPORT line.
template <class Board>
void outageSweep(const std::string& label, const std::function<std::unique_ptr<Board>()>& make,
                 const OutageGrid& g, const std::function<uint64_t(const Board&, uint64_t bootUs)>& bound) {
  uint64_t worst = 0, bootUs = 0, limit = 0, release = 0;
  std::string where;
  int cases = 0;
  for (int kind : g.kinds) {
    OutageRig<Board> rig(make());
    bootUs = std::max(bootUs, rig.boot());
    limit = bound(rig.board(), bootUs);
    for (uint64_t len : g.lengthsMs) {
      for (uint64_t phase : g.phasesMs) {
        const uint64_t took = rig.outage(kind, len * 1000, phase * 1000, fw::s(20));
        ++cases;
        const std::string at = std::string(Board::outageName(kind)) + " " + std::to_string(len) + " ms at +" +
                               std::to_string(phase) + " ms";
        ASSERT_NE(took, UINT64_MAX) << label << ", " << at << ": never recovered";
        EXPECT_LE(took, limit) << label << ", " << at;
        if (took > worst) worst = took, where = at;
      }
    }
    EXPECT_EQ(rig.badPublications(), 0);
    release = std::max(release, rig.worstReleaseUs());
  }
  std::printf(
      "REPORT %s=%.1f (%s; bound %.1f; power-on to first good scan %.1f ms; %d outages; fault output off "
      "%.1f ms after the heal at worst)\n",
      label.c_str(), static_cast<double>(worst) / 1000.0, where.c_str(), static_cast<double>(limit) / 1000.0,
      static_cast<double>(bootUs) / 1000.0, cases, static_cast<double>(release) / 1000.0);
}

}  // namespace test
