#include "scenario_player.hpp"

#include <algorithm>

namespace bmssim {

ScenarioPlayer::ScenarioPlayer(ImageSim& sim, const Scenario& scenario)
    : sim_(sim),
      scenario_(scenario),
      boards_(sim.boards()),
      cellsPerBoard_(sim.cellsPerBoard()),
      tempsPerBoard_(sim.tempsPerBoard()),
      cells_(static_cast<size_t>(boards_ * cellsPerBoard_), kStartCellMv),
      temps_(static_cast<size_t>(boards_ * tempsPerBoard_), kStartTempDeciK) {}

void ScenarioPlayer::advance(uint32_t nowMs) {
  if (floodUntilMs_ != 0 && nowMs >= floodUntilMs_) {
    sim_.setFlood({});
    floodUntilMs_ = 0;
  }
  while (next_ < scenario_.steps.size() && scenario_.steps[next_].timeMs <= nowMs)
    apply(scenario_.steps[next_++], nowMs);
  for (const auto& [key, d] : drifts_) {
    const auto [temp, board, index] = key;
    const ValueRange r = temp ? kTempDeciKRange : kCellMvRange;
    // Whole units, truncated toward the start: the value reaches v only once the drift has covered it.
    const int64_t moved = static_cast<int64_t>(d.perSecond) * (nowMs - d.t0Ms) / 1000;
    const auto v = static_cast<int32_t>(std::clamp<int64_t>(d.start + moved, r.lo, r.hi));
    if (temp) {
      setTemp(board, index, v);
    } else {
      setCell(board, index, v);
    }
  }
  // Charge flows through a closed charge path, a discharge through a closed discharge path.
  const Paths paths = sim_.paths();
  const int32_t flowing =
      currentMa_ > 0 ? (paths.charge ? currentMa_ : 0) : (paths.discharge ? currentMa_ : 0);
  if (flowing != flowingMa_) {
    flowingMa_ = flowing;
    sim_.setCurrentMa(flowing);
  }
  std::erase_if(watching_, [&](const Step* e) {
    if (!reached(*e)) return false;
    onsets_.emplace(e->fault, nowMs);
    return true;
  });
}

void ScenarioPlayer::apply(const Step& s, uint32_t nowMs) {
  switch (s.action) {
    case Action::Current:
      currentMa_ = s.value;  // it flows as the paths allow (advance())
      break;
    case Action::Cell:
      drifts_.erase({false, s.board, s.index});
      setCell(s.board, s.index, s.value);
      break;
    case Action::AllCells:
      stopCellDrifts();
      for (int b = 0; b < boards_; ++b) {
        for (int c = 1; c <= cellsPerBoard_; ++c)
          setCell(b, c, s.value);
      }
      break;
    case Action::RampCell:
      startDrift(false, s.board, s.index, s.value, nowMs);
      break;
    case Action::RampAll:
      for (int b = 0; b < boards_; ++b) {
        for (int c = 1; c <= cellsPerBoard_; ++c)
          startDrift(false, b, c, s.value, nowMs);
      }
      break;
    case Action::Temp:
      drifts_.erase({true, s.board, s.index});
      setTemp(s.board, s.index, s.value);
      break;
    case Action::RampTemp:
      startDrift(true, s.board, s.index, s.value, nowMs);
      break;
    case Action::CommLoss:
      sim_.setCommLost(s.on);
      break;
    case Action::OpenWire:
      sim_.openWire(s.board, s.index);
      break;
    case Action::Intermittent:
      sim_.setIntermittent(s.on);
      break;
    case Action::BusOff:
      if (!sim_.busOff()) busOffUnsupported_ = true;
      break;
    case Action::Stretch:
      sim_.i2cStretch(fw::us(static_cast<uint32_t>(s.value)));
      break;
    case Action::StuckScl:
      sim_.stuckScl();
      break;
    case Action::StuckSda:
      sim_.stuckSda();
      break;
    case Action::UartNoise:
      sim_.uartNoise(static_cast<uint32_t>(s.value));
      break;
    case Action::CanErrorFrames:
      sim_.canErrorFrames(static_cast<uint32_t>(s.value));
      break;
    case Action::CellCapacity:
      sim_.setCellCapacityMah(s.value);
      break;
    case Action::SpreadCells:
      // Cell 1 of each board at the value, each other cell 1..4 quarters of the spread above it.
      stopCellDrifts();
      for (int b = 0; b < boards_; ++b) {
        for (int c = 1; c <= cellsPerBoard_; ++c)
          setCell(b, c, c == 1 ? s.value : s.value + s.spread * (1 + (c + b) % 4) / 4);
      }
      break;
    case Action::Send: {
      std::string error;  // the step was checked when parsed: a frame can be built
      if (const auto f = commands_.build(s.message, s.words, error); f && sim_.sendFrame(*f)) ++commandsSent_;
      break;
    }
    case Action::Flood: {
      const Step* step = &s;
      floodUntilMs_ = nowMs + static_cast<uint32_t>(s.value);
      sim_.setFlood([this, step]() -> std::optional<fw::hal::CanFrame> {
        std::string error;
        auto f = commands_.build(step->message, step->words, error);
        if (f) ++commandsSent_;
        return f;
      });
      break;
    }
    case Action::ExpectStorage:  // judged from the frames at the end (report.cpp)
      break;
    case Action::Expect:
      if (s.hasLimit) {
        watching_.push_back(&s);
      } else {
        onsets_.emplace(s.fault, nowMs);
      }
      break;
  }
}

void ScenarioPlayer::setCell(int board, int cell, int32_t mv) {
  int32_t& now = cells_[slot(board, cell, cellsPerBoard_)];
  if (now == mv) return;
  now = mv;
  sim_.setCellMv(board, cell, mv);
}

void ScenarioPlayer::setTemp(int board, int sensor, int32_t deciK) {
  int32_t& now = temps_[slot(board, sensor, tempsPerBoard_)];
  if (now == deciK) return;
  now = deciK;
  sim_.setTempDeciK(board, sensor, deciK);
}

// A drift starts from the present value and replaces the quantity's earlier one; 0 per second stops it.
void ScenarioPlayer::startDrift(bool temp, int board, int index, int32_t perSecond, uint32_t nowMs) {
  if (perSecond == 0) {
    drifts_.erase({temp, board, index});
    return;
  }
  const int32_t start = temp ? tempDeciK(board, index) : cellMv(board, index);
  drifts_[{temp, board, index}] = Drift{start, perSecond, nowMs};
}

void ScenarioPlayer::stopCellDrifts() {
  std::erase_if(drifts_, [](const auto& kv) { return !std::get<0>(kv.first); });
}

bool ScenarioPlayer::reached(const Step& e) const {
  const auto [lo, hi] = [&](const std::vector<int32_t>& v) {
    const auto [mn, mx] = std::minmax_element(v.begin(), v.end());
    return std::pair{v.empty() ? 0 : *mn, v.empty() ? 0 : *mx};
  }(e.watch == Watch::TempAbove || e.watch == Watch::TempBelow ? temps_ : cells_);
  switch (e.watch) {
    case Watch::CellAbove:
    case Watch::TempAbove:
      return hi >= e.value;
    case Watch::CellBelow:
    case Watch::TempBelow:
      return lo <= e.value;
    case Watch::CurrentAbove:
      return flowingMa_ >= e.value;
    case Watch::CurrentBelow:
      return flowingMa_ <= e.value;
    case Watch::None:
      break;
  }
  return true;
}

}  // namespace bmssim
