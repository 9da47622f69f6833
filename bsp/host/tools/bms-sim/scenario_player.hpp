// ScenarioPlayer: plays a parsed, checked scenario (scenario.hpp) on an image, millisecond by millisecond.
//
// It keeps the emulated pack's cells, sensors and current as the scenario set them, applies each step when
// its time comes, moves the drifts (integer mV or 0.1 K, clamped to the scenario ranges, pushed to the image
// only when the value changes), and records the onset of each expected condition from the same integers the
// image was given, so an onset can never trail what the firmware saw.
// The current is the load's or the charger's: it flows only while the emulated device has the path for its
// direction closed (ImageSim::paths(), read at every millisecond: a path that opens stops the current from
// the next one), so protection that opens a path stops what it protects against, and occ / ocd onsets are
// those of the current that flows.
#pragma once

#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

#include "commands/command_frames.hpp"
#include "image_sim.hpp"
#include "scenario.hpp"

namespace bmssim {

class ScenarioPlayer {
 public:
  // The scenario must have passed checkScenario() for this image (boards, cells and sensors exist).
  ScenarioPlayer(ImageSim& sim, const Scenario& scenario);

  // Brings the pack to `nowMs`: the steps due, then the drifts, then the onsets. Call with 0, 1, 2, ...
  // before the firmware runs that millisecond.
  void advance(uint32_t nowMs);

  const Onsets& onsets() const { return onsets_; }
  bool busOffUnsupported() const { return busOffUnsupported_; }
  uint64_t commandsSent() const { return commandsSent_; }  // send steps and flood frames
  int32_t demandMa() const { return currentMa_; }   // what the load or charger draws or drives (`current`)
  int32_t flowingMa() const { return flowingMa_; }  // what flows through the pack's paths
  int32_t cellMv(int board, int cell) const { return cells_[slot(board, cell, cellsPerBoard_)]; }
  int32_t tempDeciK(int board, int sensor) const { return temps_[slot(board, sensor, tempsPerBoard_)]; }

 private:
  struct Drift {
    int32_t start;
    int32_t perSecond;
    uint32_t t0Ms;
  };
  using DriftKey = std::tuple<bool, int, int>;  // temperature?, board, cell or sensor

  static size_t slot(int board, int index, int perBoard) {
    return static_cast<size_t>(board) * static_cast<size_t>(perBoard) + static_cast<size_t>(index - 1);
  }
  void apply(const Step& step, uint32_t nowMs);
  void setCell(int board, int cell, int32_t mv);
  void setTemp(int board, int sensor, int32_t deciK);
  void startDrift(bool temp, int board, int index, int32_t perSecond, uint32_t nowMs);
  void stopCellDrifts();
  bool reached(const Step& expect) const;

  ImageSim& sim_;
  const Scenario& scenario_;
  int boards_, cellsPerBoard_, tempsPerBoard_;
  std::vector<int32_t> cells_, temps_;
  int32_t currentMa_ = 0;
  int32_t flowingMa_ = 0;
  std::map<DriftKey, Drift> drifts_;
  std::vector<const Step*> watching_;  // expects with a limit not reached yet
  Onsets onsets_;
  size_t next_ = 0;
  bool busOffUnsupported_ = false;
  bmstool::CommandBuilder commands_;  // the counters of every message the steps send
  uint32_t floodUntilMs_ = 0;
  uint64_t commandsSent_ = 0;
};

}  // namespace bmssim
