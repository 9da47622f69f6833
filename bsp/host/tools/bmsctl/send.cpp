#include "bmsctl/send.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <optional>
#include <string>
#include <vector>

#include "app/publish/slcan.hpp"
#include "bmsctl/cli.hpp"
#include "can/bms.hpp"
#include "commands/command_frames.hpp"

namespace bmsctl {
namespace {

namespace bms = fw::can::bms;
using Clock = std::chrono::steady_clock;

constexpr int kRefused = 1, kNoAnswer = 3, kPortError = 4;

// "clear-faults" -> "ClearFaults"; a name already in CamelCase stays as it is.
std::string messageName(const std::string& word) {
  std::string out;
  bool upper = true;
  for (char c : word) {
    if (c == '-' || c == '_') {
      upper = true;
      continue;
    }
    out += upper && c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c;
    upper = false;
  }
  return out;
}

class Port {
 public:
  ~Port() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool open(const std::string& path, std::string& error) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    termios t{};
    if (fd_ < 0 || ::tcgetattr(fd_, &t) != 0) {
      error = "cannot open " + path + ": " + std::strerror(errno);
      return false;
    }
    ::cfmakeraw(&t);
    ::cfsetspeed(&t, B115200);
    t.c_cflag |= CLOCAL | CREAD;
    if (::tcsetattr(fd_, TCSANOW, &t) != 0) {
      error = "cannot set " + path + " to 115200 8N1: " + std::strerror(errno);
      return false;
    }
    ::tcflush(fd_, TCIFLUSH);
    return true;
  }
  bool write(const std::string& text) {
    size_t done = 0;
    for (int tries = 0; done < text.size() && tries < 1000; ++tries) {
      const ssize_t n = ::write(fd_, text.data() + done, text.size() - done);
      if (n > 0) {
        done += static_cast<size_t>(n);
      } else if (n < 0 && errno != EAGAIN) {
        return false;
      } else {
        pollfd p{fd_, POLLOUT, 0};
        ::poll(&p, 1, 10);
      }
    }
    return done == text.size();
  }
  // The next line (ended by CR or BEL, which it includes), or nullopt at `deadline`.
  std::optional<std::string> line(Clock::time_point deadline) {
    for (;;) {
      const size_t end = buffer_.find_first_of("\r\a");
      if (end != std::string::npos) {
        std::string l = buffer_.substr(0, end + 1);
        buffer_.erase(0, end + 1);
        return l;
      }
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) return std::nullopt;
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left)) <= 0) continue;
      char in[256];
      const ssize_t n = ::read(fd_, in, sizeof in);
      if (n > 0) buffer_.append(in, static_cast<size_t>(n));
      if (n == 0 || (n < 0 && errno != EAGAIN)) return std::nullopt;  // the other end closed
    }
  }

 private:
  int fd_ = -1;
  std::string buffer_;
};

// `n` hex digits at `at`, or -1.
long hexAt(const std::string& l, size_t at, size_t n) {
  long v = 0;
  for (size_t i = at; i < at + n; ++i) {
    const char c = l[i];
    const int d = c >= '0' && c <= '9'   ? c - '0'
                  : c >= 'A' && c <= 'F' ? c - 'A' + 10
                  : c >= 'a' && c <= 'f' ? c - 'a' + 10
                                         : -1;
    if (d < 0) return -1;
    v = v << 4 | d;
  }
  return v;
}

// A standard 't' line back into a frame.
std::optional<fw::hal::CanFrame> parseLine(const std::string& l) {
  if (l.size() < 6 || l[0] != 't' || l.back() != '\r') return std::nullopt;
  const long id = hexAt(l, 1, 3), dlc = hexAt(l, 4, 1);
  if (id < 0 || dlc < 0 || dlc > 8 || l.size() != 6 + 2 * static_cast<size_t>(dlc)) return std::nullopt;
  fw::hal::CanFrame f{static_cast<uint32_t>(id), false, static_cast<uint8_t>(dlc), {}};
  for (long i = 0; i < dlc; ++i) {
    const long b = hexAt(l, 5 + 2 * static_cast<size_t>(i), 2);
    if (b < 0) return std::nullopt;
    f.data[static_cast<size_t>(i)] = static_cast<uint8_t>(b);
  }
  return f;
}

void usage(FILE* out) {
  std::fprintf(out,
               "usage: bmsctl send --port DEV [--node N] [--timeout MS] <command> [Signal=value ...]\n"
               "\ncommands (bms.yaml; kebab-case works too, e.g. clear-faults):\n");
  for (const auto& m : fw::can::bms::table::kMessages) {
    if (m.received) std::fprintf(out, "  %s\n", m.name);
  }
}

}  // namespace

int runSend(int argc, char** argv) {
  std::string port, command;
  std::vector<std::string> words;
  uint32_t node = 1, timeoutMs = 1000;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      usage(stdout);
      return 0;
    }
    if (a == "--port" || a == "--node" || a == "--timeout") {
      if (i + 1 >= argc) return usageError(a + " needs a value");
      const std::string v = argv[++i];
      if (a == "--port") {
        port = v;
      } else if (auto n = parseNumber(v, a == "--node" ? 255 : 60000)) {
        (a == "--node" ? node : timeoutMs) = *n;
      } else {
        return usageError(a + (a == "--node" ? " needs a node number 0..255" : " needs 0..60000 ms"));
      }
    } else if (a.rfind("--", 0) == 0) {
      return usageError("send: unknown option " + a + " (try 'bmsctl send --help')");
    } else if (command.empty()) {
      command = a;
    } else {
      words.push_back(a);
    }
  }
  if (port.empty()) return usageError("send needs --port DEV (the board's serial port, e.g. /dev/ttyACM0)");
  if (command.empty()) return usageError("send needs a command (try 'bmsctl send --help')");
  const auto* message = bmstool::findMessage(messageName(command));
  if (message == nullptr || !message->received) {
    return usageError("unknown command '" + command + "' (try 'bmsctl send --help')");
  }
  bool hasTarget = false;
  for (const auto& w : words)
    hasTarget |= w.rfind("Target=", 0) == 0;
  if (!hasTarget) words.push_back("Target=" + std::to_string(node));

  // The alive counter: from the clock, so two runs in a row rarely repeat it (the board refuses a repeat).
  bmstool::CommandBuilder builder(static_cast<uint8_t>(std::time(nullptr) & 0x0F));
  std::string error;
  auto frame = builder.build(*message, words, error);
  if (!frame) return usageError(error);

  Port p;
  if (!p.open(port, error)) {
    std::fprintf(stderr, "bmsctl: error: %s\n", error.c_str());
    return kPortError;
  }
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeoutMs);
  for (int attempt = 0; attempt < 2; ++attempt) {
    uint8_t text[fw::app::slcan::kMaxEncodedLength];
    const size_t n = fw::app::slcan::encode(*frame, text);
    const std::string out =
        std::string(attempt == 0 ? "O\r" : "") + std::string(reinterpret_cast<char*>(text), n);
    if (!p.write(out)) {
      std::fprintf(stderr, "bmsctl: error: cannot write to %s: %s\n", port.c_str(), std::strerror(errno));
      return kPortError;
    }
    // The answer: CommandAck for this command, then its data frames in the same write.
    std::optional<bms::CommandAck> ack;
    std::string ackText;
    while (auto l =
               p.line(ack ? std::min(deadline, Clock::now() + std::chrono::milliseconds(50)) : deadline)) {
      const auto f = parseLine(*l);
      if (!f) continue;
      if (!ack && f->id == bms::CommandAck::kId && bms::CommandAck::unpack(*f).command == frame->id) {
        ack = bms::CommandAck::unpack(*f);
        ackText = bmstool::describe(*f);
        if (ack->result == 0) std::printf("%s\n", ackText.c_str());
      } else if (ack && ack->result == 0 && f->id >= 0x581 && f->id <= 0x584) {
        std::printf("%s\n", bmstool::describe(*f).c_str());
      }
    }
    if (!ack) {
      std::fprintf(
          stderr,
          "bmsctl: error: no answer from %s within %u ms (is it the board's SLCAN port, and the board "
          "running an image with commands?)\n",
          port.c_str(), timeoutMs);
      return kNoAnswer;
    }
    if (ack->result == 2 && attempt == 0) {  // repeated counter: the next one
      frame = builder.build(*message, words, error);
      continue;
    }
    (void)p.write("C\r");
    if (ack->result != 0) {
      std::fprintf(stderr, "bmsctl: refused: %s\n", ackText.c_str());
      return kRefused;
    }
    return 0;
  }
  return kRefused;
}

}  // namespace bmsctl
