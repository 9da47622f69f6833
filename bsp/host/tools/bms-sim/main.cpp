// bms-sim: the firmware's board application on the host BSP, against emulated devices on virtual time.
//
//   bms-sim --image <preset> [--devices N] [--duration <ms>] [--scenario <name|file>]
//           [--can-layout ti|native] [--candump <file>] [--slcan <file>|pty] [--json]
//   bms-sim --elf <image.elf> [--image <preset>] ...   the image itself on the MSPM0 twin (sim_twin.hpp)
// Without --json it prints a live view every 500 ms of simulated time; with --json one summary object
// (ARCHITECTURE.md lists its keys) on stdout, and the live view on stderr when stderr is a terminal.
// --candump writes the frames with absolute times (the run starts at 2025-01-01 00:00:00 UTC); --slcan the
// L1306 board's SLCAN text (slcan_output.hpp). Exit status: 0 run completed, 2 bad arguments, 1 the run
// failed. Each image runs in its own simulator built with the image's option file (bms-sim-<preset>, see
// CMakeLists.txt); this one hands the run to it, except --elf, which it runs itself.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include <unistd.h>

#include "image_sim.hpp"
#include "report.hpp"
#include "scenario.hpp"
#include "scenario_player.hpp"
#include "sim/peripherals.hpp"
#ifndef BMS_SIM_IMAGE
#include "sim_twin.hpp"
#endif

namespace bmssim {
namespace {

int usage(const std::string& message) {
  std::fprintf(stderr, "bms-sim: error: %s\n", message.c_str());
  return 2;
}

void printHelp() {
  std::printf(
      "usage: bms-sim --image <preset> [--devices N] [--duration <ms>] [--scenario <name|file>]\n"
      "               [--can-layout ti|native] [--candump <file>] [--slcan <file>|pty] [--json]\n\n"
      "  --candump FILE   the frames in candump -l format, absolute times from 2025-01-01 00:00:00 UTC\n"
      "  --slcan FILE     the exact SLCAN text an L1306 board's back-channel UART sends\n"
      "  --slcan pty      the same, live on a pseudo-terminal (its path goes to stderr; the run keeps\n"
      "                   wall-clock time) for python-can's slcan interface or slcand, both ways: what\n"
      "                   they send reaches the board's UART receiver\n\n"
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

}  // namespace

int run(int argc, char** argv) {
  SimOptions opt;
  std::string scenarioArg = "idle", candump, layout = "native", slcan;
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
               a == "--slcan" || a == "--elf") {
      const char* v = value();
      if (v == nullptr || *v == '\0') return usage(a + " needs a value");
      (a == "--image"      ? opt.image
       : a == "--scenario" ? scenarioArg
       : a == "--candump"  ? candump
       : a == "--slcan"    ? slcan
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
#ifdef BMS_SIM_IMAGE
  if (opt.image != BMS_SIM_IMAGE) return usage("this simulator runs " BMS_SIM_IMAGE " only");
  if (!opt.elf.empty()) return usage("--elf runs in bms-sim itself, not in an image's own simulator");
#else
  // Each image has its own simulator, built with the image's option set (bms-sim-<preset> beside this one,
  // CMakeLists.txt): run it with the same arguments, so what bms-sim shows is what the image's options do.
  // --elf runs here: the image itself is the option set.
  char self[4096];
  const ssize_t n = opt.elf.empty() ? readlink("/proc/self/exe", self, sizeof self - 1) : 0;
  if (n > 0) {
    std::string path(self, static_cast<size_t>(n));
    path = path.substr(0, path.rfind('/') + 1) + "bms-sim-" + opt.image;
    if (access(path.c_str(), X_OK) == 0) {
      execv(path.c_str(), argv);
      std::fprintf(stderr, "bms-sim: error: cannot run %s: %s\n", path.c_str(), std::strerror(errno));
      return 1;
    }
  }
#endif
  std::optional<Scenario> scenario = builtinScenario(scenarioArg);
  const bool builtin = scenario.has_value();
  Diagnostics diag;
  if (!builtin) {
    scenario = loadScenario(scenarioArg, diag);
    if (!scenario) {
      if (diag.unreadable) {
        return usage("unknown scenario '" + scenarioArg + "' (not a built-in name, and not a readable file)");
      }
      std::fprintf(stderr, "%s\n", diag.error.c_str());
      return 2;
    }
  }
  if (opt.devices == 0) opt.devices = entry != nullptr ? entry->defaultDevices : 2;

  std::string error;
#ifdef BMS_SIM_IMAGE
  std::unique_ptr<ImageSim> sim = entry->make(opt, error);
#else
  std::unique_ptr<ImageSim> sim = opt.elf.empty() ? entry->make(opt, error) : makeTwinSim(opt, error);
#endif
  if (!sim) return usage(error);
  if (opt.tiLayout && sim->figures().output != "can") return usage("--can-layout applies to CAN images only");
  // The steps against this image, before anything runs: a board it does not have is an error at its line.
  // Warnings are for files (a built-in's steps past --duration or its current on a BQ79616 are expected).
  const bool fits =
      checkScenario(*scenario, {sim->boards(), sim->cellsPerBoard(), sim->tempsPerBoard(), sim->hasCurrent()},
                    opt.durationMs, diag);
  for (const auto& w : diag.warnings) {
    if (!builtin) std::fprintf(stderr, "%s\n", w.c_str());
  }
  if (!fits) {
    std::fprintf(stderr, "%s\n", diag.error.c_str());
    return 2;
  }
  std::unique_ptr<SlcanOutput> slcanOut;
  if (!slcan.empty()) {
    if (!sim->slcanText()) {
      return usage("--slcan applies to the L1306 images (SLCAN on the back-channel UART); use --candump");
    }
    slcanOut = SlcanOutput::open(slcan, error);
    if (!slcanOut) return usage(error);
  }

  auto& h = sim->harness();
  // The watchdog supervision every image's main() sets up: fed every 250 ms if every watched task made
  // progress. Its longest gap shows whether anything stalled.
  bsp::host::SimWatchdog watchdog(h.clock);
  h.sched.superviseWatchdog(watchdog, fw::ms(250));
  // Run: each millisecond the scenario moves the pack, then the firmware runs. The live view comes every
  // 500 ms of simulated time; with --json it goes to stderr when that is a terminal (a 64-device chain runs
  // slower than real time, and stdout then holds only the summary).
  ScenarioPlayer player(*sim, *scenario);
  Report report(*sim, opt, *scenario, json);
  if (slcanOut) report.attachSlcan(*slcanOut);
  report.setLiveOutput(!json ? stdout : isatty(fileno(stderr)) ? stderr : nullptr);
  for (uint32_t t = 0;; ++t) {
    player.advance(t);
    if (t >= opt.durationMs) break;
    if (slcanOut) {
      if (const std::string in = slcanOut->takeInput(); !in.empty()) sim->serialSend(in);
    }
    sim->runFor(fw::us(1000));
    if (const std::string why = sim->failure(); !why.empty()) {
      std::fprintf(stderr, "bms-sim: %s\n", why.c_str());
      return 1;
    }
    sim->afterStep();
    report.tick(h.nowUs());
  }

  report.finish(player.onsets(), player.busOffUnsupported(),
                sim->boardWatchdog() ? *sim->boardWatchdog() : watchdog);
  if (!candump.empty() && !report.writeCandump(candump)) {
    std::fprintf(stderr, "bms-sim: error: cannot write %s\n", candump.c_str());
    return 1;
  }
  if (slcanOut && !slcanOut->finish(*sim->slcanText(), error)) {
    std::fprintf(stderr, "bms-sim: error: cannot write %s: %s\n", slcan.c_str(), error.c_str());
    return 1;
  }
  return 0;
}

}  // namespace bmssim

int main(int argc, char** argv) {
  return bmssim::run(argc, argv);
}
