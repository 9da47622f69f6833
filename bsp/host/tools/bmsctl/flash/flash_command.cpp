#include "flash/flash_command.hpp"

#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <iterator>

#include <unistd.h>

#include "flash/bsl_session.hpp"
#include "flash/chips.hpp"
#include "flash/flash_image.hpp"
#include "flash/invoke_app.hpp"

namespace bmsctl::flash {

namespace {

using bsl::Message;

constexpr uint32_t kMaxPacketData =
    4096;                   // bsl.md/TI: 4 KiB per Program Data keeps a packet's wire time short
constexpr int kPasses = 2;  // erase + program again once after a lost Program Data reply

struct Options {
  std::string image, port, chip = "auto", password, invoke = "none", invokePort;
  uint32_t baud = 9600;
  uint8_t node = 1;
  int waitSeconds = 0;  // 0: 10 s, 30 s with --invoke button
  bool verifyOnly = false;
};

int fail(FlashExit code, const std::string& message) {
  std::fprintf(stderr, "bmsctl: error: %s\n", message.c_str());
  return static_cast<int>(code);
}

void warn(const std::string& message) {
  std::fprintf(stderr, "bmsctl: warning: %s\n", message.c_str());
}

std::string hex32(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

const char* const kUsage =
    "usage: bmsctl flash IMAGE --port DEV [--chip mspm0l1306|mspm0g3507|auto] [--baud RATE]\n"
    "                  [--password FILE] [--invoke button|app|none] [--invoke-port DEV] [--node N]\n"
    "                  [--wait SECONDS] [--verify-only]\n"
    "Programs IMAGE (.elf, .hex or .bin) through the MSPM0 ROM bootloader on the serial port DEV.\n";

bool parseUint(const std::string& text, uint32_t max, uint32_t& out) {
  if (text.empty() || text.size() > 10) return false;
  uint64_t v = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + static_cast<uint64_t>(c - '0');
  }
  if (v > max) return false;
  out = static_cast<uint32_t>(v);
  return true;
}

std::optional<Options> parse(int argc, char** argv, std::string& error) {
  Options o;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& into) {
      if (i + 1 >= argc || argv[i + 1][0] == '\0') {
        error = a + " needs a value";
        return false;
      }
      into = argv[++i];
      return true;
    };
    std::string v;
    if (a == "--port") {
      if (!value(o.port)) return std::nullopt;
    } else if (a == "--chip") {
      if (!value(o.chip)) return std::nullopt;
      if (o.chip != "auto" && chipByName(o.chip) == nullptr) {
        error = "--chip must be mspm0l1306, mspm0g3507 or auto";
        return std::nullopt;
      }
    } else if (a == "--baud") {
      if (!value(v)) return std::nullopt;
      if (!parseUint(v, 3000000, o.baud) || !bsl::baudRateId(o.baud)) {
        error =
            "--baud must be a rate the BSL knows: 4800, 9600, 19200, 38400, 57600, 115200, 1000000, "
            "2000000 or 3000000";
        return std::nullopt;
      }
    } else if (a == "--password") {
      if (!value(o.password)) return std::nullopt;
    } else if (a == "--invoke") {
      if (!value(o.invoke)) return std::nullopt;
      if (o.invoke != "button" && o.invoke != "app" && o.invoke != "none") {
        error = "--invoke must be button, app or none";
        return std::nullopt;
      }
    } else if (a == "--invoke-port") {
      if (!value(o.invokePort)) return std::nullopt;
    } else if (a == "--node") {
      uint32_t n = 0;
      if (!value(v)) return std::nullopt;
      if (!parseUint(v, 254, n) || n == 0) {
        error = "--node must be 1..254";
        return std::nullopt;
      }
      o.node = static_cast<uint8_t>(n);
    } else if (a == "--wait") {
      uint32_t n = 0;
      if (!value(v)) return std::nullopt;
      if (!parseUint(v, 600, n) || n == 0) {
        error = "--wait must be 1..600 seconds";
        return std::nullopt;
      }
      o.waitSeconds = static_cast<int>(n);
    } else if (a == "--verify-only") {
      o.verifyOnly = true;
    } else if (a.rfind("--", 0) == 0) {
      error = "unknown option '" + a + "' for flash";
      return std::nullopt;
    } else if (o.image.empty()) {
      o.image = a;
    } else {
      error = "flash takes one image, got '" + o.image + "' and '" + a + "'";
      return std::nullopt;
    }
  }
  if (o.image.empty()) error = "flash needs an image (.elf, .hex or .bin)";
  if (error.empty() && o.port.empty())
    error = "flash needs --port DEV (the LaunchPad's serial port, e.g. /dev/ttyACM0)";
  if (error.empty() && !o.invokePort.empty() && o.invoke != "app")
    error = "--invoke-port goes with --invoke app";
  if (!error.empty()) return std::nullopt;
  return o;
}

// 32 raw bytes, or 64 hex digits (spaces, commas, newlines and "0x" prefixes allowed).
bool loadPassword(const std::string& path, std::array<uint8_t, 32>& out, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open the password file";
    return false;
  }
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() == 32) {
    std::copy(text.begin(), text.end(), out.begin());
    return true;
  }
  std::vector<uint8_t> bytes;
  int line = 1, column = 0, nibbles = 0;
  uint8_t current = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    ++column;
    if (c == '\n') {
      ++line, column = 0;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r' || c == ',') continue;
    if (c == '0' && i + 1 < text.size() && (text[i + 1] == 'x' || text[i + 1] == 'X') && nibbles % 2 == 0) {
      ++i, ++column;
      continue;
    }
    const int v = c >= '0' && c <= '9'   ? c - '0'
                  : c >= 'a' && c <= 'f' ? c - 'a' + 10
                  : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                         : -1;
    if (v < 0) {
      error = path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": not a hex digit";
      return false;
    }
    current = static_cast<uint8_t>(current << 4 | v);
    if (++nibbles % 2 == 0) bytes.push_back(current);
  }
  if (bytes.size() != 32 || nibbles % 2 != 0) {
    error = path + ": the BSL password is 32 bytes (32 raw bytes or 64 hex digits); the file gives " +
            std::to_string(bytes.size()) + (nibbles % 2 ? " and a half" : "");
    return false;
  }
  std::copy(bytes.begin(), bytes.end(), out.begin());
  return true;
}

class Progress {
 public:
  Progress(uint32_t total) : total_(total), tty_(isatty(STDERR_FILENO) != 0), start_(Clock::now()) {}
  void update(uint32_t done) {
    done_ = done;
    if (!tty_) return;
    const double s = seconds();
    std::fprintf(stderr, "\rbmsctl: programming %u / %u B  %3u %%  %.1f kB/s ", done, total_,
                 total_ ? 100U * done / total_ : 100U, s > 0 ? done / s / 1000.0 : 0.0);
    std::fflush(stderr);
  }
  void end() {
    if (tty_ && done_ != 0) std::fprintf(stderr, "\n");
    done_ = 0;
  }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  uint32_t total_, done_ = 0;
  bool tty_;
  Clock::time_point start_;
};

// A failed outcome as its exit status and message.
int failure(const Outcome& o, const std::string& what) {
  switch (o.kind) {
    case Outcome::Kind::Ok:
      break;
    case Outcome::Kind::NoAnswer:
      return fail(FlashExit::TransferError, "the BSL stopped answering (" + what + ", 3 attempts)");
    case Outcome::Kind::Rejected:
      return fail(FlashExit::TransferError, "the BSL would not take " + what + ": " + bsl::ackText(o.code));
    case Outcome::Kind::ReplyLost:
      return fail(FlashExit::TransferError, "the reply to " + what + " was lost or garbled");
    case Outcome::Kind::Message:
      switch (static_cast<Message>(o.code)) {
        case Message::Locked:
          return fail(FlashExit::Locked, "the BSL is locked (" + bsl::messageText(o.code) + ") at " + what +
                                             ": it relocks 10 s after its last command; run bmsctl again");
        case Message::PasswordError:
          return fail(FlashExit::WrongPassword, "wrong BSL password (" + bsl::messageText(o.code) + ")");
        case Message::MultiplePasswordError:
          return fail(FlashExit::Locked, bsl::messageText(o.code) +
                                             ": the device took its configured security "
                                             "alert; reset it and give the right --password");
        case Message::InvalidMemoryRange:
          return fail(FlashExit::OutOfRange, "the BSL refused " + what + ": " + bsl::messageText(o.code));
        default:
          return fail(FlashExit::FlashFailed, "the BSL failed " + what + ": " + bsl::messageText(o.code));
      }
  }
  return 0;
}

// How to start the bootloader by hand: on the image's LaunchPad, or on either when the part is not known yet.
std::string procedure(const Chip* chip) {
  if (chip != nullptr) return std::string("on the ") + chip->launchpad + ": " + chip->invokeProcedure;
  std::string text;
  for (const Chip& c : chips())
    text += std::string(text.empty() ? "on the " : "; on the ") + c.launchpad + ": " + c.invokeProcedure;
  return text;
}

std::string noAnswerText(const Options& o, const Chip* chip, int waited) {
  return "no answer from the bootloader on " + o.port + " within " + std::to_string(waited) +
         " s. Start it " + procedure(chip) + ".";
}

}  // namespace

int runFlash(int argc, char** argv) {
  if (argc >= 1 && (std::strcmp(argv[0], "--help") == 0 || std::strcmp(argv[0], "-h") == 0)) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  std::string error;
  const std::optional<Options> parsed = parse(argc, argv, error);
  if (!parsed) {
    std::fprintf(stderr, "bmsctl: error: %s\n%s", error.c_str(), kUsage);
    return static_cast<int>(FlashExit::Usage);
  }
  const Options& o = *parsed;

  // The image, and the part it is for: nothing touches the port before the image is known to be writable.
  const std::optional<FlashImage> image = FlashImage::load(o.image, error);
  if (!image) return fail(FlashExit::ImageUnreadable, error);
  const auto sp = image->word(0);
  const Chip* imageChip = sp ? chipFromStack(*sp) : nullptr;
  const Chip* chip = o.chip == "auto" ? imageChip : chipByName(o.chip);
  if (imageChip != nullptr && chip != imageChip) {
    return fail(FlashExit::WrongChip, o.image + " is an " + imageChip->title +
                                          " image (initial stack pointer " + hex32(*sp) + "), not for the " +
                                          chip->title + " --chip names");
  }
  if (chip != nullptr) {
    const std::string range = checkRange(*image, *chip);
    if (!range.empty()) return fail(FlashExit::OutOfRange, range);
  }
  std::array<uint8_t, 32> password;
  password.fill(0xFF);  // a fresh device's BSL password (SLAU887 4.3.3)
  if (!o.password.empty() && !loadPassword(o.password, password, error)) return fail(FlashExit::Usage, error);

  SerialPort::OpenError openError;
  std::string detail;
  std::unique_ptr<SerialPort> port = SerialPort::open(o.port, openError, detail);
  switch (openError) {
    case SerialPort::OpenError::None:
      break;
    case SerialPort::OpenError::Missing:
      return fail(FlashExit::PortMissing, o.port + ": no such port (" + detail +
                                              "); the LaunchPad's back-channel is usually /dev/ttyACM0, or "
                                              "/dev/serial/by-id/usb-Texas_Instruments_XDS110_*-if00");
    case SerialPort::OpenError::NotATerminal:
      return fail(FlashExit::PortMissing, o.port + ": not a serial port (" + detail + ")");
    case SerialPort::OpenError::Busy:
      return fail(FlashExit::PortBusy,
                  o.port + " is in use by another program (" + detail +
                      "); close it (a terminal, slcand, ModemManager: bsp/mspm0/README.md)");
    case SerialPort::OpenError::Permission:
      return fail(FlashExit::PortPermission,
                  o.port + ": " + detail +
                      "; add yourself to the port's group (sudo usermod -aG dialout "
                      "$USER, then log in again)");
    case SerialPort::OpenError::Other:
      return fail(FlashExit::Failed, o.port + ": " + detail);
  }

  // Invoke.
  if (o.invoke == "app") {
    std::unique_ptr<SerialPort> other;
    SerialPort* link = port.get();
    if (!o.invokePort.empty()) {
      other = SerialPort::open(o.invokePort, openError, detail);
      if (!other) return fail(FlashExit::PortMissing, o.invokePort + ": " + detail);
      link = other.get();
    }
    link->setBaud(115200);  // the images' SLCAN rate
    std::optional<bool> g3507;
    if (chip != nullptr) g3507 = std::string(chip->name) == "mspm0g3507";
    const InvokeResult r = invokeApplication(*link, other != nullptr, o.node, g3507);
    if (r.kind == InvokeResult::Kind::WrongImage) return fail(FlashExit::WrongChip, r.text);
    if (r.kind != InvokeResult::Kind::Entered) return fail(FlashExit::InvokeFailed, r.text);
    port->setBaud(9600);
  } else if (o.invoke == "button") {
    const int wait = o.waitSeconds ? o.waitSeconds : 30;
    std::fprintf(stderr, "bmsctl: start the bootloader %s. Waiting up to %d s.\n", procedure(chip).c_str(),
                 wait);
  }
  const int waitSeconds = o.waitSeconds ? o.waitSeconds : o.invoke == "button" ? 30 : 10;
  BslSession session(*port, warn);
  bool already = false;
  if (!session.connect(Clock::now() + std::chrono::seconds(waitSeconds), already)) {
    return fail(FlashExit::NoAnswer, noAnswerText(o, chip, waitSeconds));
  }
  if (already) warn("the BSL's session was open already (MSG 0x06 to Connection): continuing in it");

  bsl::DeviceInfo info;
  if (Outcome r = session.deviceInfo(info); !r.ok()) return failure(r, "Get Device Info");
  session.setBufferSize(info.bufferSize);
  const Chip* device = chipFromBslBuffer(info.bufferSize);
  char buffer[8];
  std::snprintf(buffer, sizeof buffer, "0x%04X", info.bufferSize);
  if (device != nullptr && chip != nullptr && device != chip) {
    return fail(FlashExit::WrongChip, "the device is an " + std::string(device->title) + " (BSL buffer " +
                                          buffer + "); " + o.image + " is for the " + chip->title);
  }
  if (device == nullptr && chip == nullptr) {
    return fail(FlashExit::WrongChip, std::string("cannot tell which part the device is (BSL buffer ") +
                                          buffer + ") nor the image: give --chip");
  }
  if (device == nullptr) {
    warn(std::string("the BSL's buffer size ") + buffer + " names no known part; trusting " +
         (o.chip == "auto" ? "the image" : "--chip") + ": " + chip->title);
  }
  if (chip == nullptr) {
    chip = device;
    const std::string range = checkRange(*image, *chip);
    if (!range.empty()) return fail(FlashExit::OutOfRange, range);
  }
  if (info.bufferSize < 12 + 64) {
    return fail(FlashExit::Failed,
                std::string("the BSL's buffer (") + buffer + ") is too small to program through");
  }

  if (o.baud != 9600) {
    if (Outcome r = session.changeBaud(o.baud); !r.ok())
      return failure(r, "Change Baud Rate to " + std::to_string(o.baud));
  }
  if (Outcome r = session.unlock(password); !r.ok()) {
    if (r.kind == Outcome::Kind::Message && r.code == static_cast<uint8_t>(Message::PasswordError)) {
      return fail(
          FlashExit::WrongPassword,
          "wrong BSL password (" + bsl::messageText(r.code) +
              "); not retried: each wrong password costs a 2 s lockout and the third one the device's "
              "security alert (SLAU887 4.3.3). Give the 32-byte password with --password FILE");
    }
    if (r.kind == Outcome::Kind::Message) return failure(r, "Unlock Bootloader");
    return fail(FlashExit::TransferError,
                "the answer to Unlock Bootloader was lost; not repeated (a wrong password must never be sent "
                "twice by itself): run bmsctl again");
  }

  uint32_t maxChunk = std::min<uint32_t>(kMaxPacketData, (info.bufferSize - 12U) / 8U * 8U);
  FlashPlan plan = flash::plan(*image, maxChunk);
  Progress progress(plan.programBytes);
  size_t packets = 0;
  if (!o.verifyOnly) {
    for (int pass = 1; pass <= kPasses; ++pass) {
      for (const Range& e : plan.erase) {
        if (Outcome r = session.rangeErase(e.begin, e.end - 1); !r.ok()) {
          return failure(r, "Flash Range Erase " + hex32(e.begin) + ".." + hex32(e.end - 1));
        }
      }
      std::deque<ProgramChunk> queue(plan.chunks.begin(), plan.chunks.end());
      uint32_t done = 0;
      bool again = false;
      while (!queue.empty()) {
        const ProgramChunk chunk = queue.front();
        const unsigned resendsBefore = session.resends();
        const Outcome r = session.program(chunk.address, chunk.bytes);
        const std::string what = "Program Data at " + hex32(chunk.address);
        if (r.ok()) {
          queue.pop_front();
          ++packets;
          done += static_cast<uint32_t>(chunk.bytes.size());
          progress.update(done);
          continue;
        }
        progress.end();
        if (r.kind == Outcome::Kind::Rejected && r.code == bsl::kAckPacketTooBig && maxChunk > 64) {
          maxChunk = maxChunk / 2 / 8 * 8;
          warn("the BSL took a " + std::to_string(chunk.bytes.size()) +
               "-byte Program Data packet as too big (" + bsl::ackText(r.code) + "); sending at most " +
               std::to_string(maxChunk) + " bytes a packet");
          queue.pop_front();
          const auto pieces = split(chunk, maxChunk);
          queue.insert(queue.begin(), pieces.begin(), pieces.end());
          continue;
        }
        // After a resend the words may have been written by the first copy: that failure says nothing.
        const bool uncertain = r.kind == Outcome::Kind::ReplyLost ||
                               (r.kind == Outcome::Kind::Message && session.resends() != resendsBefore);
        if (uncertain && pass < kPasses) {
          warn("cannot tell whether " + what + " was written; erasing and programming again (pass " +
               std::to_string(pass + 1) + " of " + std::to_string(kPasses) + ")");
          again = true;
          break;
        }
        if (r.kind == Outcome::Kind::NoAnswer) {
          return fail(FlashExit::TransferError,
                      "the BSL stopped answering at " + what + " (" + std::to_string(done) + " of " +
                          std::to_string(plan.programBytes) +
                          " B written, 3 attempts); the reset vector is written last, so the device starts "
                          "its bootloader again at its next reset: run bmsctl again");
        }
        return failure(r, what);
      }
      progress.end();
      if (!again) break;
    }
  }

  for (const VerifyWindow& w : plan.verify) {
    uint32_t crc = 0;
    const std::string what = hex32(w.range.begin) + ".." + hex32(w.range.end - 1);
    if (Outcome r = session.verify(w.range.begin, w.range.size(), crc); !r.ok()) {
      return failure(r, "Standalone Verification " + what);
    }
    if (crc != w.expectedCrc) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "CRC mismatch in %s: the device reports 0x%08X, the image gives 0x%08X", what.c_str(),
                    crc, w.expectedCrc);
      return fail(FlashExit::CrcMismatch,
                  text + std::string(o.verifyOnly ? " (the flash holds something else)" : " (flash again)"));
    }
  }
  if (o.verifyOnly) {
    uint32_t checked = 0;
    for (const VerifyWindow& w : plan.verify)
      checked += w.range.size();
    std::printf("bmsctl: %s matches the %s's flash: %zu window%s, %u B, CRC verified\n", o.image.c_str(),
                chip->title, plan.verify.size(), plan.verify.size() == 1 ? "" : "s", checked);
    return 0;
  }
  if (Outcome r = session.startApplication(); !r.ok()) {
    return fail(
        FlashExit::TransferError,
        "the image is flashed and verified, but Start Application was not acknowledged; press NRST to "
        "run it");
  }
  uint32_t sectors = 0;
  for (const Range& e : plan.erase)
    sectors += e.size() / kSectorSize;
  std::printf(
      "bmsctl: flashed %s (%s, %zu B) into the %s at %u Bd in %.1f s: %u sectors erased, %u B in %zu "
      "packets, CRC verified, application started\n",
      o.image.c_str(), image->format(), image->byteCount(), chip->title, o.baud, progress.seconds(), sectors,
      plan.programBytes, packets);
  return 0;
}

}  // namespace bmsctl::flash
