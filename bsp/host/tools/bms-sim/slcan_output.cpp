#include "slcan_output.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

namespace bmssim {
namespace {

using Clock = std::chrono::steady_clock;

class FileOutput final : public SlcanOutput {
 public:
  explicit FileOutput(std::FILE* file) : file_(file) {}
  ~FileOutput() override {
    if (file_ != nullptr) std::fclose(file_);
  }
  void step(const SentText&, uint64_t) override {}
  bool finish(const SentText& uart, std::string& error) override {
    const std::string& text = uart.text;
    const bool ok = std::fwrite(text.data(), 1, text.size(), file_) == text.size();
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed) error = std::strerror(errno);
    return ok && closed;
  }

 private:
  std::FILE* file_;
};

class PtyOutput final : public SlcanOutput {
 public:
  ~PtyOutput() override {
    if (master_ >= 0) ::close(master_);
    if (slave_ >= 0) ::close(slave_);
  }

  bool init(std::string& error) {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY);
    const char* name =
        master_ >= 0 && ::grantpt(master_) == 0 && ::unlockpt(master_) == 0 ? ::ptsname(master_) : nullptr;
    // The terminal's other end in raw mode (no echo, no CR to LF), closed again: the master then reports a
    // hang-up until a reader opens it.
    const int slave = name != nullptr ? ::open(name, O_RDWR | O_NOCTTY) : -1;
    termios raw{};
    if (slave < 0 || ::tcgetattr(slave, &raw) != 0) {
      error = std::string("cannot open a pseudo-terminal: ") + std::strerror(errno);
      if (slave >= 0) ::close(slave);
      return false;
    }
    ::cfmakeraw(&raw);
    ::cfsetspeed(&raw, B115200);
    ::tcsetattr(slave, TCSANOW, &raw);
    ::close(slave);
    ::fcntl(master_, F_SETFL, ::fcntl(master_, F_GETFL) | O_NONBLOCK);
    path_ = name;
    std::fprintf(stderr, "bms-sim: SLCAN on %s (the board's back-channel UART, 115200 8N1)\n", name);
    std::fflush(stderr);
    return true;
  }

  void step(const SentText& uart, uint64_t nowUs) override {
    if (!started_) waitForReader();
    // Paced: simulated time runs no faster than the wall clock.
    const auto now = Clock::now();
    if (!started_) start_ = now - std::chrono::microseconds(nowUs), started_ = true;
    const auto due = start_ + std::chrono::microseconds(nowUs);
    if (now < due) std::this_thread::sleep_until(due);
    collect(uart, nowUs);
    pump();
  }

  bool finish(const SentText& uart, std::string&) override {
    if (!started_) waitForReader();
    collect(uart, UINT64_MAX);
    // Wait for the reader to take the rest, as long as it keeps taking some: at most 5 s, and 1 s without
    // progress (no reader, or one that stopped). Text written to the master reaches the reader's queue a
    // little later (the kernel moves it), so the queue must be seen empty twice, 20 ms apart.
    const auto end = Clock::now() + std::chrono::seconds(5);
    auto lastProgress = Clock::now();
    size_t lastQueued = SIZE_MAX;
    for (int empty = 0; empty < 2;) {
      pump();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      int queued = 0;
      if (slave_ >= 0) ::ioctl(slave_, FIONREAD, &queued);
      const size_t left = pending_.size() + static_cast<size_t>(queued);
      empty = left == 0 ? empty + 1 : 0;
      const auto now = Clock::now();
      if (left < lastQueued) lastQueued = left, lastProgress = now;
      if (now > end || now - lastProgress > std::chrono::seconds(1)) break;
    }
    if (dropped_ != 0)
      std::fprintf(stderr, "bms-sim: the SLCAN reader fell behind: %zu bytes dropped\n", dropped_);
    waitForClose();
    return true;
  }

 private:
  static constexpr size_t kMaxPending = 64 * 1024;

  // Until a reader opens the terminal (the master stops reporting a hang-up), at most 60 s, and 250 ms more
  // for it to finish opening (pyserial discards what is queued once it has set the port up). Then bms-sim
  // opens the terminal's other end too: the text stays queued if the reader leaves, and finish() can see how
  // much the reader has not taken yet.
  void waitForReader() {
    pollfd p{master_, POLLIN, 0};
    auto end = Clock::now() + std::chrono::seconds(60);
    while (::poll(&p, 1, 0) >= 0 && (p.revents & POLLHUP) != 0 && Clock::now() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    slave_ = ::open(path_.c_str(), O_RDWR | O_NOCTTY);
    // Until the reader sends O (its port is set up and it listens), at most 10 s: on a loaded machine
    // python-can took over 3 s to send it once, and the text sent before it was discarded with its set-up.
    end = Clock::now() + std::chrono::seconds(10);
    while (!sawCommand('O') && Clock::now() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }

  // After the run: until the reader closes the terminal (the master hangs up once no one else holds it
  // open), at most 30 s, or 2 s after it sent C. Its C is not the end yet: python-can writes C and then waits
  // for the terminal to drain it (tcdrain) before it closes, so the master stays open, and read, until the
  // hang-up. Ending at the C closed the master under that wait, and python-can's shutdown raised an I/O error
  // (readme.slcan_recipe, now and then).
  void waitForClose() {
    if (slave_ >= 0) ::close(slave_);
    slave_ = -1;
    auto end = Clock::now() + std::chrono::seconds(30);
    bool closing = false;
    pollfd p{master_, POLLIN, 0};
    while (Clock::now() < end) {
      if (sawCommand('C') && !closing) {
        closing = true;
        end = std::min(end, Clock::now() + std::chrono::seconds(2));
      }
      if (::poll(&p, 1, 0) >= 0 && (p.revents & POLLHUP) != 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  // Reads what the reader sent and keeps it for the board (takeInput()); true once a line of it was the
  // SLCAN command `command` alone ("O\r").
  bool sawCommand(char command) {
    char in[256];
    ssize_t n;
    bool seen = false;
    while ((n = ::read(master_, in, sizeof in)) > 0) {
      input_.append(in, static_cast<size_t>(n));
      for (ssize_t i = 0; i < n; ++i) {
        if (in[i] == '\r') {
          seen = seen || line_ == std::string(1, command);
          line_.clear();
        } else if (line_.size() < 32) {
          line_ += in[i];
        }
      }
    }
    return seen;
  }

  // Takes the text whose write has finished by `nowUs`. Writes go one at a time (the UART is busy until its
  // last byte left), so only the newest can still be on the line: its bytes are what arrived since the step
  // before it began.
  void collect(const SentText& uart, uint64_t nowUs) {
    const std::string& text = uart.text;
    const auto& times = uart.writeEndsUs;
    if (times.size() != writesSeen_) inFlightFrom_ = sizeSeen_, writesSeen_ = times.size();
    sizeSeen_ = text.size();
    const size_t ready = !times.empty() && times.back() > nowUs ? inFlightFrom_ : text.size();
    if (ready > taken_) pending_.append(text, taken_, ready - taken_), taken_ = ready;
    if (pending_.size() > kMaxPending) {
      const size_t excess = pending_.size() - kMaxPending;
      pending_.erase(0, excess);
      dropped_ += excess;
    }
  }

  std::string takeInput() override {
    pump();
    std::string out;
    out.swap(input_);
    return out;
  }

  // Hands what it can to the terminal without blocking, and keeps what the reader sent (takeInput()).
  void pump() {
    (void)sawCommand('O');
    while (!pending_.empty()) {
      const ssize_t n = ::write(master_, pending_.data(), pending_.size());
      if (n <= 0) break;
      pending_.erase(0, static_cast<size_t>(n));
    }
  }

  int master_ = -1;
  int slave_ = -1;
  std::string path_;
  std::string line_;  // the reader's command line so far
  bool started_ = false;
  Clock::time_point start_{};
  std::string pending_;
  std::string input_;  // what the reader sent, not taken yet
  size_t taken_ = 0, sizeSeen_ = 0, inFlightFrom_ = 0, writesSeen_ = 0, dropped_ = 0;
};

}  // namespace

std::unique_ptr<SlcanOutput> SlcanOutput::open(const std::string& target, std::string& error) {
  if (target == "pty") {
    auto pty = std::make_unique<PtyOutput>();
    if (!pty->init(error)) return nullptr;
    return pty;
  }
  std::FILE* file = std::fopen(target.c_str(), "wb");
  if (file == nullptr) {
    error = "cannot write " + target + ": " + std::strerror(errno);
    return nullptr;
  }
  return std::make_unique<FileOutput>(file);
}

}  // namespace bmssim
