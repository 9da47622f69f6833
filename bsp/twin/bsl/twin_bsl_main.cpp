// twin-bsl: one of the five LaunchPad set-ups on the twin (board/board.hpp) with its ROM bootloader on a
// pseudo-terminal, for `bmsctl flash` without a board.
//
//   twin-bsl --board <preset> [--elf IMAGE] [--s1] [--command-pty] [--password HEX64] [--run MS]
//            [--frames FILE] [--timeout S] [--log] [--power-loss-after N] [--corrupt-answer N]
//            [--drop-host-byte N] [--flip-bit ADDR] [--flash FILE]
//
// The chip starts blank (MAIN flash erased: the boot code starts the BSL), or with --elf loaded (the image
// runs, unless --s1 holds the invoke pin PA18 high through the power-on). The first line on stdout is
// "twin-bsl: BSL UART on /dev/pts/N"; give that path to `bmsctl flash --port`. While the BSL waits for the
// host, simulated time follows the wall clock (its 10 s timeouts are real); while bytes travel or a command
// executes, it runs as fast as it can. Once an application has started, the twin runs it for --run ms
// (default 2000) of simulated time, writes the frames it published in that time to --frames (one line
// each: microseconds since the application started, identifier, data bytes, all hex but the time), prints
// what happened and exits 0. Exit 1: the twin stopped (an access no model covers, a NONMAIN write, a Factory
// Reset); 2: bad arguments; 3: no application ran within --timeout s of wall time (default 60). --log prints
// every command the BSL answered, with its answer.
//
// --command-pty (with --elf): the image's command link on a second pseudo-terminal (bsl/command_pty.hpp: the
// L1306's back-channel UART, or an SLCAN adapter on the G3507's CAN bus), announced on the second line as
// "twin-bsl: command link on /dev/pts/M", for `bmsctl flash --invoke app --invoke-port`. The loaded image
// then runs at wall-clock pace until it restarts into the BSL (its EnterBootloader command); --run and
// --frames count the application started after that. The line "before the BSL: ..." gives the state of the
// paths the image controls when the BSL started (FETs, fault output).
//
// Faults for tests: --power-loss-after N cuts the power right after the N-th Program Data the BSL has
// acknowledged and restores it 500 ms later (as unplugging a LaunchPad's USB cable does); --corrupt-answer N
// sends the N-th core answer with a wrong CRC; --drop-host-byte N loses the N-th byte from the host;
// --flip-bit ADDR flips bit 0 of the flash byte at ADDR once a Program Data has written it.
//
// --flash FILE: the flash data region (bsp/mspm0/linker, 0x7000..0x7FFF) is read from FILE before the chip
// starts (created erased if missing) and written back after the application ran (exit 0 only): a test sees
// what a reflash left of it (flash_file.hpp).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>

#include <poll.h>

#include "board/board.hpp"
#include "bsl/bsl_pty.hpp"
#include "bsl/command_pty.hpp"
#include "flash_file.hpp"
#include "sim/harness.hpp"

namespace {

using Wall = std::chrono::steady_clock;

int usage(const std::string& message) {
  std::fprintf(stderr, "twin-bsl: error: %s\n", message.c_str());
  return 2;
}

bool parseNumber(const char* text, uint64_t& out) {
  char* end = nullptr;
  out = std::strtoull(text, &end, 0);
  return end != text && *end == '\0';
}

std::string hexBytes(const std::vector<uint8_t>& data) {
  std::string s;
  char buf[4];
  for (uint8_t b : data) {
    std::snprintf(buf, sizeof buf, "%02X", b);
    s += buf;
  }
  return s.empty() ? "-" : s;
}

// "t<iii><l><dd..>" (the images' SLCAN lines) back into an identifier and data.
bool decodeSlcan(const std::string& line, uint32_t& id, std::vector<uint8_t>& data) {
  if (line.size() < 5 || line[0] != 't') return false;
  id = static_cast<uint32_t>(std::strtoul(line.substr(1, 3).c_str(), nullptr, 16));
  const size_t dlc = static_cast<size_t>(line[4] - '0');
  if (dlc > 8 || line.size() < 5 + 2 * dlc) return false;
  data.clear();
  for (size_t i = 0; i < dlc; ++i)
    data.push_back(static_cast<uint8_t>(std::strtoul(line.substr(5 + 2 * i, 2).c_str(), nullptr, 16)));
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string preset, elfPath, framesPath, passwordHex, flashPath;
  bool s1 = false, log = false, commandPty = false;
  uint64_t runMs = 2000, timeoutS = 60, powerLossAfter = 0, corruptAnswer = 0, dropHostByte = 0;
  std::optional<uint64_t> flipBit;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    auto number = [&](uint64_t& out) {
      const char* v = value();
      return v != nullptr && parseNumber(v, out);
    };
    if (a == "--board" || a == "--elf" || a == "--frames" || a == "--password" || a == "--flash") {
      const char* v = value();
      if (v == nullptr) return usage(a + " needs a value");
      (a == "--board"    ? preset
       : a == "--elf"    ? elfPath
       : a == "--frames" ? framesPath
       : a == "--flash"  ? flashPath
                         : passwordHex) = v;
    } else if (a == "--s1") {
      s1 = true;
    } else if (a == "--command-pty") {
      commandPty = true;
    } else if (a == "--log") {
      log = true;
    } else if (a == "--run") {
      if (!number(runMs) || runMs == 0) return usage("--run needs a number of milliseconds");
    } else if (a == "--timeout") {
      if (!number(timeoutS) || timeoutS == 0) return usage("--timeout needs a number of seconds");
    } else if (a == "--power-loss-after") {
      if (!number(powerLossAfter) || powerLossAfter == 0) return usage("--power-loss-after needs a count");
    } else if (a == "--corrupt-answer") {
      if (!number(corruptAnswer) || corruptAnswer == 0) return usage("--corrupt-answer needs a count");
    } else if (a == "--drop-host-byte") {
      if (!number(dropHostByte) || dropHostByte == 0) return usage("--drop-host-byte needs a count");
    } else if (a == "--flip-bit") {
      uint64_t v = 0;
      if (!number(v)) return usage("--flip-bit needs an address");
      flipBit = v;
    } else {
      return usage("unknown option '" + a + "'");
    }
  }
  const auto id = twin::imageByPreset(preset);
  if (!id) return usage("--board must name one of the five images' boards (e.g. lp-mspm0g3507-bq79616)");
  if (commandPty && elfPath.empty()) return usage("--command-pty needs --elf (an image to take the command)");

  bsp::host::Harness h;
  twin::Board board(*id, h.clock, 2);
  twin::Machine& m = board.machine();
  twin::RomBsl& bsl = board.chip().bsl();
  // The pack at rest, as bms-sim's idle scenario: 3.7 V cells, 25 degC.
  if (auto* e = board.bq769x()) {
    for (uint8_t c = 1; c <= 16; ++c)
      e->setCellMv(c, 3700);
  }
  if (auto* chain = board.chain()) {
    for (size_t d = 0; d < chain->size(); ++d) {
      for (int c = 1; c <= 16; ++c)
        chain->setCellMicrovolts(d, c, 3700000);
    }
  }
  if (!passwordHex.empty()) {
    std::array<uint8_t, 32> pw{};
    if (passwordHex.size() != 64) return usage("--password needs 64 hex digits");
    for (size_t i = 0; i < 32; ++i)
      pw[i] = static_cast<uint8_t>(std::strtoul(passwordHex.substr(2 * i, 2).c_str(), nullptr, 16));
    bsl.setPassword(pw);
  }

  std::optional<uint64_t> appStart;
  uint64_t sessionStart = 0, sessionEnd = 0, programs = 0;
  bool cut = false, flip = false, bslSeen = false;
  auto seconds = [&](uint64_t cycle) { return static_cast<double>(cycle) / m.clockHz(); };
  // When the BSL starts after the image ran: the paths' state, from the pins the image drove before the reset
  // (the reset itself releases the fault output pin at the BSL's first cycle).
  auto reportPaths = [&](uint64_t bslCycle) {
    std::string text;
    char buf[96];
    auto before = [&](const std::vector<twin::PinEdge>& edges) -> const twin::PinEdge* {
      const twin::PinEdge* last = nullptr;
      for (const auto& e : edges) {
        if (e.cycle < bslCycle) last = &e;
      }
      return last;
    };
    if (const auto* e = before(board.fetsOn())) {
      std::snprintf(buf, sizeof buf, "FETs %s since %.6f s", e->level ? "on" : "off", seconds(e->cycle));
      text += buf;
    }
    if (const auto* e = before(board.faultOutput())) {
      std::snprintf(buf, sizeof buf, "%sfault output %s since %.6f s", text.empty() ? "" : ", ",
                    e->level ? "high" : "low", seconds(e->cycle));
      text += buf;
    }
    std::printf("twin-bsl: %.6f s: before the BSL: %s\n", seconds(m.now()),
                text.empty() ? "-" : text.c_str());
  };
  m.onReset([&](twin::ResetKind) {
    if (m.coreHeld()) {
      appStart.reset();
    } else {
      appStart = m.now();
      std::printf("twin-bsl: %.6f s: application started\n", static_cast<double>(m.now()) / m.clockHz());
    }
  });
  bsl.onCommand([&](const twin::RomBsl::Record& r) {
    if (r.text.rfind("started: ", 0) == 0 || log) {
      std::printf("twin-bsl: %.6f s: BSL %s\n", static_cast<double>(r.cycle) / m.clockHz(), r.text.c_str());
    }
    if (r.text.rfind("started: ", 0) == 0 && commandPty && !bslSeen) reportPaths(r.cycle);
    if (r.text.rfind("started: ", 0) == 0) bslSeen = true;
    if (r.command == 0x12 && r.result == -1 && sessionStart == 0) sessionStart = r.cycle;
    if (r.command == 0x40) sessionEnd = r.cycle;
    if (r.command == 0x20 && r.result == 0) {
      ++programs;
      if (powerLossAfter != 0 && programs == powerLossAfter) cut = true;
      if (flipBit) flip = true;
    }
  });
  if (corruptAnswer != 0) bsl.corruptAnswerCrc(static_cast<unsigned>(corruptAnswer));

  twin::BslPty pty(m, bsl);
  std::string error;
  if (!pty.open(error)) {
    std::fprintf(stderr, "twin-bsl: error: %s\n", error.c_str());
    return 1;
  }
  if (dropHostByte != 0) pty.dropHostByte(dropHostByte);
  std::optional<twin::CommandPty> command;
  if (commandPty) {
    command.emplace(board);
    if (!command->open(error)) {
      std::fprintf(stderr, "twin-bsl: error: %s\n", error.c_str());
      return 1;
    }
  }
  twin::ElfFile elf;
  const int invokePin = board.chip().pincm(0, 18);
  if (s1) board.chip().pins().setExternal(invokePin, twin::Drive::High);
  if (!elfPath.empty()) {
    if (!elf.load(elfPath)) {
      std::fprintf(stderr, "twin-bsl: error: %s\n", elf.error().c_str());
      return 1;
    }
    if (!board.load(elf)) {
      std::fprintf(stderr, "twin-bsl: error: %s\n", board.error().c_str());
      return 1;
    }
  } else {
    m.powerOn();
  }
  // --flash: the data region from the file (created erased), written back when the application has run.
  const twin::FlashRegion region =
      elfPath.empty() ? twin::kLinkerDataRegion : twin::dataRegion(elf).value_or(twin::kLinkerDataRegion);
  if (!flashPath.empty() && !twin::loadFlashFile(m, region, flashPath, error)) {
    std::fprintf(stderr, "twin-bsl: error: --flash: %s\n", error.c_str());
    return 1;
  }
  board.chip().pins().setExternal(invokePin, twin::Drive::None);  // S1 released; the board pulls PA18 down
  std::printf("twin-bsl: BSL UART on %s (%s board)\n", pty.path().c_str(), preset.c_str());
  if (command) {
    std::printf("twin-bsl: command link on %s (%s)\n", command->path().c_str(),
                id->part == twin::Part::L1306 ? "UART0 PA9/PA8, 115200 Bd" : "SLCAN adapter on the CAN bus");
  }
  std::fflush(stdout);

  const auto wallStart = Wall::now();
  auto wallPrev = wallStart;
  std::optional<uint64_t> powerBackAt;
  auto nowUs = [&] { return m.now() / m.cyclesPerUs(); };
  for (;;) {
    pty.service();
    if (command) command->service();
    std::fflush(stdout);
    if (m.stopped()) {
      std::printf("twin-bsl: the twin stopped: %s\n", m.stopReason().c_str());
      return 1;
    }
    // With a command link, the loaded image waits for its command: the run counts from the application the
    // BSL started.
    const bool awaitingInvoke = command && !bslSeen;
    if (appStart && !awaitingInvoke && m.now() >= *appStart + runMs * 1000 * m.cyclesPerUs()) break;
    if (Wall::now() - wallStart > std::chrono::seconds(timeoutS)) {
      std::printf("twin-bsl: no application ran within %llu s\n", static_cast<unsigned long long>(timeoutS));
      return 3;
    }
    if (cut) {  // the power goes: nothing answers until it is back
      cut = false;
      bsl.stop();
      powerBackAt = nowUs() + 500000;
      std::printf("twin-bsl: %.6f s: power lost (after Program Data %llu)\n",
                  static_cast<double>(m.now()) / m.clockHz(), static_cast<unsigned long long>(programs));
    }
    if (flip && flipBit && *flipBit < m.flash().size() && m.flash()[*flipBit] != 0xFF) {
      m.flash()[*flipBit] ^= 0x01;
      std::printf("twin-bsl: flipped bit 0 of the flash byte at 0x%08llX\n",
                  static_cast<unsigned long long>(*flipBit));
      flipBit.reset();
    }
    flip = false;
    if (powerBackAt && nowUs() >= *powerBackAt) {
      powerBackAt.reset();
      m.reset(twin::ResetKind::Por, "power restored");
    }
    const bool appRuns = !m.coreHeld() && !awaitingInvoke;
    if (appRuns || pty.inFlight() || bsl.busy() || powerBackAt || (command && command->inFlight())) {
      board.runUntilUs(nowUs() + 1000);  // work in hand: as fast as it goes
      wallPrev = Wall::now();
    } else {          // waiting for the host: simulated time follows the wall clock
      if (command) {  // either terminal
        pollfd p[2] = {{pty.fd(), POLLIN, 0}, {command->fd(), POLLIN, 0}};
        poll(p, 2, 5);
      } else {
        pty.waitForHost(5);
      }
      const auto now = Wall::now();
      const auto us = std::chrono::duration_cast<std::chrono::microseconds>(now - wallPrev).count();
      wallPrev = now;
      board.runUntilUs(nowUs() + static_cast<uint64_t>(std::max<long long>(us, 1)));
    }
  }

  if (sessionStart != 0 && sessionEnd > sessionStart) {
    std::printf(
        "twin-bsl: BSL session %.3f s simulated from the first Connection to Start Application; %llu "
        "bytes from the host, %llu to it, %llu lost to a rate mismatch\n",
        static_cast<double>(sessionEnd - sessionStart) / m.clockHz(),
        static_cast<unsigned long long>(pty.hostBytes()), static_cast<unsigned long long>(pty.bslBytes()),
        static_cast<unsigned long long>(bsl.bytesLost() + pty.lostToHost()));
  }
  size_t frames = 0;
  std::ofstream out;
  if (!framesPath.empty()) out.open(framesPath);
  auto emit = [&](uint64_t cycle, uint32_t canId, const std::vector<uint8_t>& data) {
    if (cycle < *appStart) return;
    ++frames;
    if (out)
      out << (cycle - *appStart) / m.cyclesPerUs() << " " << std::hex << canId << std::dec << " "
          << hexBytes(data) << "\n";
  };
  for (const auto& f : board.canFrames())
    emit(f.endCycle, f.frame.id, {f.frame.data.begin(), f.frame.data.begin() + f.frame.dlc});
  for (const auto& line : board.slcanLines()) {
    uint32_t canId = 0;
    std::vector<uint8_t> data;
    if (decodeSlcan(line.text, canId, data)) emit(line.cycle, canId, data);
  }
  if (!flashPath.empty() && !twin::saveFlashFile(m, region, flashPath, error)) {
    std::fprintf(stderr, "twin-bsl: error: --flash: %s\n", error.c_str());
    return 1;
  }
  std::printf("twin-bsl: the application ran %llu ms: %zu frames%s\n", static_cast<unsigned long long>(runMs),
              frames, framesPath.empty() ? "" : (" written to " + framesPath).c_str());
  return 0;
}
