// bms-sim: the firmware's board application on the host BSP, against emulated devices on virtual time.
//
//   bms-sim --image <preset> [--devices N] [--duration <ms>] [--scenario <name|file>]
//           [--can-layout ti|native] [--candump <file>] [--json]
//   bms-sim --elf <image.elf> [--image <preset>] ...   the image itself on the MSPM0 twin (sim_twin.hpp)
// Without --json it prints a live view every 500 ms of simulated time; with --json one summary object
// (ARCHITECTURE.md lists its keys). Exit status: 0 run completed, 2 bad arguments, 1 the run failed.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>

#include "image_sim.hpp"
#include "report.hpp"
#include "scenario.hpp"
#include "sim/peripherals.hpp"
#include "sim_twin.hpp"

namespace bmssim {
namespace {

int usage(const std::string& message) {
  std::fprintf(stderr, "bms-sim: error: %s\n", message.c_str());
  return 2;
}

void printHelp() {
  std::printf(
      "usage: bms-sim --image <preset> [--devices N] [--duration <ms>] [--scenario <name|file>]\n"
      "               [--can-layout ti|native] [--candump <file>] [--json]\n"
      "       bms-sim --elf <build/<preset>/<preset>.elf> [--image <preset>] [same options]\n"
      "               runs the firmware image itself on the MSPM0 instruction-level twin "
      "(bsp/twin)\n\nimages:\n");
  for (const auto& e : images())
    std::printf("  %-24s %s\n", e.image, e.summary);
  std::printf("\nscenarios:");
  for (const auto& n : builtinNames())
    std::printf(" %s", n.c_str());
  std::printf(" (or a file: see bsp/host/tools/bms-sim/scenario.hpp)\n");
}

bool parseUint(const char* text, uint32_t max, uint32_t& out) {
  char* end = nullptr;
  const unsigned long v = std::strtoul(text, &end, 10);
  if (end == text || *end != '\0' || v > max) return false;
  out = static_cast<uint32_t>(v);
  return true;
}

// A quantity that drifts linearly from a start time.
struct Ramp {
  int board, index;
  double start, slopePerMs;
  uint64_t t0;
  bool temp;
};

}  // namespace

int run(int argc, char** argv) {
  SimOptions opt;
  std::string scenarioArg = "idle", candump, layout = "native";
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (a == "--help" || a == "-h") {
      printHelp();
      return 0;
    } else if (a == "--json") {
      json = true;
    } else if (a == "--image" || a == "--scenario" || a == "--candump" || a == "--can-layout" ||
               a == "--elf") {
      const char* v = value();
      if (v == nullptr) return usage(a + " needs a value");
      (a == "--image"      ? opt.image
       : a == "--scenario" ? scenarioArg
       : a == "--candump"  ? candump
       : a == "--elf"      ? opt.elf
                           : layout) = v;
    } else if (a == "--devices" || a == "--duration") {
      const char* v = value();
      uint32_t n = 0;
      if (v == nullptr || !parseUint(v, a == "--devices" ? 64 : 3600000, n) || n == 0) {
        return usage(a + (a == "--devices" ? " needs a number 1..64" : " needs a number of ms, 1..3600000"));
      }
      if (a == "--devices") {
        opt.devices = static_cast<int>(n);
      } else {
        opt.durationMs = n;
      }
    } else {
      return usage("unknown option '" + a + "' (try --help)");
    }
  }
  if (opt.image.empty() && opt.elf.empty()) return usage("--image or --elf is required (try --help)");
  if (layout != "native" && layout != "ti") return usage("--can-layout must be ti or native");
  opt.tiLayout = layout == "ti";
  if (opt.tiLayout && !opt.elf.empty())
    return usage("--can-layout applies to host runs; an image has its layout built in");

  const ImageEntry* entry = nullptr;
  for (const auto& e : images()) {
    if (opt.image == e.image) entry = &e;
  }
  if (entry == nullptr && opt.elf.empty()) {
    std::string known;
    for (const auto& e : images())
      known += std::string(known.empty() ? "" : ", ") + e.image;
    return usage("unknown image '" + opt.image + "' (known: " + known + ")");
  }
  std::optional<Scenario> scenario = builtinScenario(scenarioArg);
  if (!scenario) {
    std::string error;
    scenario = loadScenario(scenarioArg, error);
    if (!scenario) {
      if (error.find("cannot read") != std::string::npos) {
        return usage("unknown scenario '" + scenarioArg + "' (not a built-in name, and no such file)");
      }
      std::fprintf(stderr, "%s\n", error.c_str());
      return 2;
    }
  }
  if (opt.devices == 0) opt.devices = entry != nullptr ? entry->defaultDevices : 2;

  std::string error;
  std::unique_ptr<ImageSim> sim = opt.elf.empty() ? entry->make(opt, error) : makeTwinSim(opt, error);
  if (!sim) return usage(error);
  if (opt.tiLayout && sim->figures().output != "can") return usage("--can-layout applies to CAN images only");

  auto& h = sim->harness();
  // The watchdog supervision every image's main() sets up: fed every 250 ms if every watched task made
  // progress. Its longest gap shows whether anything stalled.
  bsp::host::SimWatchdog watchdog(h.clock);
  h.sched.superviseWatchdog(watchdog, fw::ms(250));
  std::vector<Ramp> ramps;
  std::map<std::pair<int, int>, double> cells, temps;
  auto cellNow = [&](int b, int c) {
    auto it = cells.find({b, c});
    return it == cells.end() ? 3700.0 : it->second;
  };
  auto tempNow = [&](int b, int s) {
    auto it = temps.find({b, s});
    return it == temps.end() ? 2982.0 : it->second;
  };
  double onsetMs = -1;
  bool busOffUnsupported = false;
  auto checkRange = [&](int b, int c, int max) { return b >= 0 && b < sim->boards() && c >= 1 && c <= max; };

  auto apply = [&](const Step& s) -> bool {
    const auto& a = s.args;
    const uint64_t now = h.nowUs();
    if (s.action == "current") {
      sim->setCurrentMa(static_cast<int>(a[0]));
    } else if (s.action == "cell" || s.action == "ramp-cell") {
      const int b = static_cast<int>(a[0]), c = static_cast<int>(a[1]);
      if (!checkRange(b, c, sim->cellsPerBoard())) return false;
      if (s.action == "cell") {
        cells[{b, c}] = a[2];
        sim->setCellMv(b, c, static_cast<int>(a[2]));
      } else {
        ramps.push_back({b, c, cellNow(b, c), a[2] / 1000.0, now, false});
      }
    } else if (s.action == "all-cells" || s.action == "ramp-all") {
      for (int b = 0; b < sim->boards(); ++b) {
        for (int c = 1; c <= sim->cellsPerBoard(); ++c) {
          if (s.action == "all-cells") {
            cells[{b, c}] = a[0];
            sim->setCellMv(b, c, static_cast<int>(a[0]));
          } else {
            ramps.push_back({b, c, cellNow(b, c), a[0] / 1000.0, now, false});
          }
        }
      }
    } else if (s.action == "temp" || s.action == "ramp-temp") {
      const int b = static_cast<int>(a[0]), t = static_cast<int>(a[1]);
      if (!checkRange(b, t, sim->tempsPerBoard())) return false;
      if (s.action == "temp") {
        temps[{b, t}] = a[2];
        sim->setTempDeciK(b, t, static_cast<int>(a[2]));
      } else {
        ramps.push_back({b, t, tempNow(b, t), a[2] / 1000.0, now, true});
      }
    } else if (s.action == "comm-loss") {
      sim->setCommLost(s.text == "on");
    } else if (s.action == "open-wire") {
      const int b = static_cast<int>(a[0]), c = static_cast<int>(a[1]);
      if (!checkRange(b, c, sim->cellsPerBoard())) return false;
      sim->openWire(b, c);
    } else if (s.action == "intermittent") {
      sim->setIntermittent(s.text == "on");
    } else if (s.action == "bus-off") {
      if (!sim->busOff()) busOffUnsupported = true;
    } else if (s.action == "onset") {
      if (onsetMs < 0) onsetMs = static_cast<double>(now) / 1000.0;
    }
    return true;
  };

  // Run: steps at their times, ramps updated every millisecond, the live view every 500 ms.
  Report report(*sim, opt, *scenario, json);
  size_t next = 0;
  const uint64_t endUs = static_cast<uint64_t>(opt.durationMs) * 1000;
  for (uint64_t t = 0;; t += 1000) {
    while (next < scenario->steps.size() && static_cast<uint64_t>(scenario->steps[next].timeMs) * 1000 <= t) {
      if (!apply(scenario->steps[next])) {
        return usage("scenario step at " + std::to_string(scenario->steps[next].timeMs) +
                     " ms names a board, cell or sensor this image does not have");
      }
      ++next;
    }
    for (const Ramp& r : ramps) {
      const double v = r.start + r.slopePerMs * static_cast<double>(t - r.t0) / 1000.0;
      if (r.temp) {
        temps[{r.board, r.index}] = v;
        sim->setTempDeciK(r.board, r.index, static_cast<int>(std::lround(v)));
      } else {
        cells[{r.board, r.index}] = v;
        sim->setCellMv(r.board, r.index, static_cast<int>(std::lround(v)));
      }
      // Onset of a threshold scenario: the first millisecond the emulated value reaches the limit.
      const bool above = scenario->watchKind == (r.temp ? "temp-above" : "cell-above");
      if (onsetMs < 0 && above && v >= scenario->threshold) onsetMs = static_cast<double>(t) / 1000.0;
    }
    if (t >= endUs) break;
    sim->runFor(fw::us(1000));
    if (const std::string why = sim->failure(); !why.empty()) {
      std::fprintf(stderr, "bms-sim: %s\n", why.c_str());
      return 1;
    }
    sim->afterStep();
    report.tick(h.nowUs());
  }

  report.finish(onsetMs, busOffUnsupported, sim->boardWatchdog() ? *sim->boardWatchdog() : watchdog);
  if (!candump.empty() && !report.writeCandump(candump)) {
    std::fprintf(stderr, "bms-sim: error: cannot write %s\n", candump.c_str());
    return 1;
  }
  return 0;
}

}  // namespace bmssim

int main(int argc, char** argv) {
  return bmssim::run(argc, argv);
}
