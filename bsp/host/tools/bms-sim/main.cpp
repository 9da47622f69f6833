// bms-sim: the firmware's board application on the host BSP, against emulated devices on virtual time.
//
//   bms-sim --image <preset> [--devices N] [--duration <ms>] [--scenario <name|file>]
//           [--can-layout ti|native] [--candump <file>] [--slcan <file>|pty] [--json]
//   bms-sim --elf <image.elf> [--image <preset>] ...   the image itself on the MSPM0 twin (sim_twin.hpp)
// Every option is one row of kOptions: the parser accepts those rows only and --help prints them all.
// Without --json it prints a live view every 500 ms of simulated time; with --json one summary object
// (README "Host tools" lists its keys) on stdout, and the live view on stderr when stderr is a terminal.
// --profile (with --elf) writes the cycles per function and per interrupt (bsp/twin/profiler.hpp).
// --candump writes the frames with absolute times (the run starts at 2025-01-01 00:00:00 UTC); --slcan the
// L1306 board's SLCAN text (slcan_output.hpp). An option the image cannot honour (--can-layout ti on an image
// without the TI layout, --devices on a one-device image) is refused before the run.
// Exit status: 0 the run completed and every scenario `expect` was met; 1 the run failed (the twin stopped,
// an output could not be written); 2 bad arguments or input (an option, a scenario file, a file too large or
// not a file, an option the image cannot honour); 3 the run completed and an `expect` was missed
// (scenario.hpp). Each image runs in its own simulator built with the image's option file
// (bms-sim-<preset>, see CMakeLists.txt); this one hands the run to it, except --elf, which it runs itself.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include <unistd.h>

#include "image_sim.hpp"
#include "input_file.hpp"
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

// Every option the parser accepts, with its value and its help line.
struct OptionSpec {
  const char* name;
  const char* value;  // nullptr: a switch
  const char* help;
};
constexpr OptionSpec kOptions[] = {
    {"--image", "<preset>", "the image to run (below); with --elf, the image the ELF must be"},
    {"--elf", "<file.elf>",
     "run the firmware image itself on the MSPM0 instruction-level twin (bsp/twin) instead of the host "
     "build"},
    {"--devices", "<N>", "BQ79616 chain length, 1..64 (default 2); the other images have one device"},
    {"--duration", "<ms>", "simulated time, 1..3600000 ms (default 10000)"},
    {"--scenario", "<name|file>",
     "a built-in scenario (below, default idle) or a scenario file (scenario.hpp)"},
    {"--can-layout", "ti|native",
     "native (default) or seed 001's TI layout, which only lp-mspm0g3507-bq79616 builds (host runs only)"},
    {"--candump", "<file>",
     "the CAN frames in candump -l format, absolute times from 2025-01-01 00:00:00 UTC"},
    {"--slcan", "<file>|pty",
     "an L1306 image's SLCAN text: the exact bytes to a file, or live on a pseudo-terminal (its path goes to "
     "stderr; the run starts when a reader sends SLCAN's O, keeps wall-clock time, and waits for the reader "
     "to close the terminal) for python-can or slcand, both ways: what they send reaches the board's UART "
     "receiver"},
    {"--flash", "<file>",
     "with --elf: the flash data region (bsp/mspm0/linker) is read from FILE at start and written back at "
     "the "
     "end, so a later run starts with what this one left; a missing FILE is created erased"},
    {"--no-crystal", nullptr,
     "with --elf: a board fault, no HFXT crystal (the G3507's CAN clock; the L1306 has none): the start-up "
     "monitor reports it dead (bsp/twin/periph/sysctl.hpp)"},
    {"--json", nullptr, "one JSON summary on stdout (the live view goes to stderr when that is a terminal)"},
    {"--profile", "<file>",
     "with --elf: CPU cycles per function and per interrupt of the run, to a file (format: "
     "bsp/twin/profiler.hpp)"},
    {"--help", nullptr, "this text (also -h)"},
};

const OptionSpec* optionNamed(const std::string& name) {
  for (const auto& o : kOptions) {
    if (name == o.name || (name == "-h" && std::string(o.name) == "--help")) return &o;
  }
  return nullptr;
}

void printHelp() {
  std::printf(
      "usage: bms-sim --image <preset> [options]\n"
      "       bms-sim --elf <build/<preset>/<preset>.elf> [options]\n\noptions:\n");
  for (const auto& o : kOptions) {
    const std::string head = std::string(o.name) + (o.value != nullptr ? std::string(" ") + o.value : "");
    std::printf("  %-26s %s\n", head.c_str(), o.help);
  }
  std::printf("\nimages:\n");
  for (const auto& e : images())
    std::printf("  %-24s %s\n", e.image.c_str(), e.summary.c_str());
  std::printf("\nscenarios:");
  for (const auto& n : builtinNames())
    std::printf(" %s", n.c_str());
  std::printf(" (or a file: see bsp/host/tools/bms-sim/scenario.hpp)\n");
  std::printf(
      "\nexit status: 0 done, every expect met; 1 the run failed; 2 bad arguments or input; 3 an expect of "
      "the scenario was missed\n");
}

bool parseUint(const char* text, uint32_t max, uint32_t& out) {
  char* end = nullptr;
  const unsigned long v = std::strtoul(text, &end, 10);
  if (end == text || *end != '\0' || v > max) return false;
  out = static_cast<uint32_t>(v);
  return true;
}

// An ELF of a firmware image with its debug information is about 0.5 MiB; the parts' flash is 128 KiB.
constexpr size_t kMaxElfBytes = 16U << 20;

}  // namespace

int run(int argc, char** argv) {
  SimOptions opt;
  std::string scenarioArg = "idle", candump, layout = "native", slcan, profile;
  bool json = false, devicesGiven = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const OptionSpec* o = optionNamed(a);
    if (o == nullptr) return usage("unknown option '" + a + "' (try --help)");
    const std::string name = o->name;
    if (name == "--help") {
      printHelp();
      return 0;
    }
    if (o->value == nullptr) {  // --json, --no-crystal
      (name == "--json" ? json : opt.noCrystal) = true;
      continue;
    }
    const char* v = i + 1 < argc ? argv[++i] : nullptr;
    if (v == nullptr || *v == '\0') return usage(name + " needs a value: " + o->value);
    if (name == "--devices" || name == "--duration") {
      uint32_t n = 0;
      if (!parseUint(v, name == "--devices" ? 64 : kMaxTimeMs, n) || n == 0) {
        return usage(name +
                     (name == "--devices" ? " needs a number 1..64" : " needs a number of ms, 1..3600000"));
      }
      if (name == "--devices") {
        opt.devices = static_cast<int>(n);
        devicesGiven = true;
      } else {
        opt.durationMs = n;
      }
      continue;
    }
    (name == "--image"      ? opt.image
     : name == "--scenario" ? scenarioArg
     : name == "--candump"  ? candump
     : name == "--slcan"    ? slcan
     : name == "--elf"      ? opt.elf
     : name == "--profile"  ? profile
     : name == "--flash"    ? opt.flashFile
                            : layout) = v;
  }
  if (opt.image.empty() && opt.elf.empty()) return usage("--image or --elf is required (try --help)");
  if (layout != "native" && layout != "ti") return usage("--can-layout must be ti or native");
  opt.tiLayout = layout == "ti";
  if (opt.tiLayout && !opt.elf.empty())
    return usage("--can-layout applies to host runs; an image has its layout built in");
  if (!profile.empty() && opt.elf.empty())
    return usage("--profile applies to --elf runs: it counts the image's own instructions on the twin");
  if (opt.noCrystal && opt.elf.empty())
    return usage("--no-crystal applies to --elf runs: a fault of the twin's board");
  if (!opt.flashFile.empty() && opt.elf.empty())
    return usage("--flash applies to --elf runs: it keeps the twin's flash data region");
  if (!opt.elf.empty()) {
    std::string error;
    if (checkInputFile(opt.elf, kMaxElfBytes, "firmware ELF", error) != InputError::None)
      return usage(opt.elf + ": " + error);
  }

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
        return usage("unknown scenario '" + scenarioArg + "' (not a built-in name, and no such file)");
      }
      std::fprintf(stderr, "%s\n", diag.error.c_str());
      return 2;
    }
  }
  if (entry != nullptr && entry->make == nullptr && opt.elf.empty())
    return usage("bms-sim has no host board for " + entry->image + ": " + entry->missing);
  if (opt.devices == 0) opt.devices = entry != nullptr ? entry->defaultDevices : 2;

  std::string error;
#ifdef BMS_SIM_IMAGE
  std::unique_ptr<ImageSim> sim = entry->make(opt, error);
#else
  std::unique_ptr<ImageSim> sim = opt.elf.empty() ? entry->make(opt, error) : makeTwinSim(opt, error);
#endif
  if (!sim) return usage(error);
  // Options the image cannot honour are refused, never ignored.
  if (opt.tiLayout && sim->figures().output != "can") return usage("--can-layout applies to CAN images only");
  if (opt.tiLayout && !sim->sendsTiLayout()) {
    return usage(
        "--can-layout ti: " + opt.image +
        " has no TI layout (its options.cmake builds FW_CAN_TI_LAYOUT=0); only lp-mspm0g3507-bq79616 "
        "sends seed 001's layout");
  }
  if (devicesGiven && opt.devices != sim->boards()) {
    return usage("--devices " + std::to_string(opt.devices) + ": " + opt.image +
                 " has one monitor device; --devices sets the length of a BQ79616 chain");
  }
  // The steps against this image, before anything runs: a board it does not have is an error at its line.
  // Warnings are for files (a built-in's steps past --duration or its current on a BQ79616 are expected).
  const ImageSim::FaultLinks links = sim->faultLinks();
  const bool fits = checkScenario(*scenario,
                                  {sim->boards(), sim->cellsPerBoard(), sim->tempsPerBoard(),
                                   sim->hasCurrent(), links.i2c, links.uart, links.can},
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

  if (!profile.empty()) sim->startProfile();
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

  const size_t missed = report.finish(
      {player.onsets(), player.busOffUnsupported(), player.demandMa(), player.flowingMa(), sim->paths()},
      sim->boardWatchdog() ? *sim->boardWatchdog() : watchdog);
  if (!candump.empty() && !report.writeCandump(candump)) {
    std::fprintf(stderr, "bms-sim: error: cannot write %s\n", candump.c_str());
    return 1;
  }
  if (!opt.flashFile.empty() && !sim->saveFlash(error)) {
    std::fprintf(stderr, "bms-sim: error: --flash %s: %s\n", opt.flashFile.c_str(), error.c_str());
    return 1;
  }
  if (!profile.empty() && !sim->writeProfile(profile, error)) {
    std::fprintf(stderr, "bms-sim: error: cannot write %s: %s\n", profile.c_str(), error.c_str());
    return 1;
  }
  if (slcanOut && !slcanOut->finish(*sim->slcanText(), error)) {
    std::fprintf(stderr, "bms-sim: error: cannot write %s: %s\n", slcan.c_str(), error.c_str());
    return 1;
  }
  if (missed != 0) {
    std::fprintf(stderr, "bms-sim: %zu expect(s) of %s missed\n", missed, scenario->name.c_str());
    return 3;
  }
  return 0;
}

}  // namespace bmssim

int main(int argc, char** argv) {
  return bmssim::run(argc, argv);
}
