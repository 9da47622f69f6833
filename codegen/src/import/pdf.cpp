#include "import/pdf.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string_view>
#include <vector>

#include "diag/diag.hpp"

extern char** environ;

namespace regmapgen {

namespace {

constexpr const char* kInstall =
    "reading a PDF needs pdftotext from poppler-utils (Debian/Ubuntu: sudo apt-get install poppler-utils; "
    "Fedora: sudo dnf install poppler-utils; macOS: brew install poppler), or convert it yourself with "
    "'pdftotext -layout FILE.pdf table.txt' and import table.txt";

// A pdftotext -layout text of a whole TRM is a few megabytes; anything far larger is not a TRM.
constexpr std::size_t kMaxText = kMaxInputBytes;

// Pages per pdftotext run at least: each run parses the file's cross-reference table and fonts again.
constexpr int kMinPagesPerRun = 8;

// A child process whose standard output is a pipe we read.
struct Child {
  pid_t pid = 0;
  int fd = -1;
  std::string out;
  int status = 0;
  bool done = false;
};

// Starts `argv[0]` (looked up in PATH) with stdout into a pipe and stderr to /dev/null (pdftotext reports
// every font it cannot map, "Syntax Error: Unknown character collection ...", which says nothing about the
// text; its exit status says whether it read the file). 0 or the errno of the failure.
int start(std::vector<std::string> args, Child& c) {
  std::vector<char*> argv;
  for (std::string& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  int fds[2];
  if (pipe(fds) != 0) return errno;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  const int spawned = posix_spawnp(&c.pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  if (spawned != 0) {
    close(fds[0]);
    return spawned;
  }
  c.fd = fds[0];
  return 0;
}

// Reads what is there on c's pipe; at its end waits for the child. `total` counts every child's bytes; past
// kMaxText the rest is read and dropped (so the child can finish) and `tooLong` set.
void readSome(Child& c, std::size_t& total, bool& tooLong) {
  char buf[65536];
  const ssize_t n = read(c.fd, buf, sizeof buf);
  if (n < 0 && errno == EINTR) return;
  if (n > 0) {
    total += static_cast<std::size_t>(n);
    if (total > kMaxText) {
      tooLong = true;
    } else {
      c.out.append(buf, static_cast<std::size_t>(n));
    }
    return;
  }
  close(c.fd);
  c.fd = -1;
  while (waitpid(c.pid, &c.status, 0) < 0 && errno == EINTR) {
  }
  c.done = true;
}

// The number of pages pdfinfo reports, or 0.
int pageCount(const std::string& path) {
  Child c;
  if (start({"pdfinfo", path}, c) != 0) return 0;
  std::size_t total = 0;
  bool tooLong = false;
  while (!c.done)
    readSome(c, total, tooLong);
  if (!WIFEXITED(c.status) || WEXITSTATUS(c.status) != 0) return 0;
  const std::size_t at = c.out.find("\nPages:");
  if (at == std::string::npos) return 0;
  const std::size_t digits = c.out.find_first_of("0123456789", at);
  if (digits == std::string::npos) return 0;
  int n = 0;
  for (std::size_t i = digits; i < c.out.size() && c.out[i] >= '0' && c.out[i] <= '9' && n < 1000000; ++i)
    n = n * 10 + (c.out[i] - '0');
  return n;
}

std::string statusText(int status) {
  return WIFEXITED(status) ? std::to_string(WEXITSTATUS(status)) : std::string("signal");
}

}  // namespace

bool looksLikePdf(const std::string& bytes) {
  return bytes.rfind("%PDF-", 0) == 0;
}

int pdfWorkers() {
  const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  return static_cast<int>(std::clamp(cpus, 1L, 16L));
}

PdfText pdfToText(const std::string& path, int firstPage, int lastPage) {
  PdfText r;
  // The pages to read, cut into runs: a 207-page TRM costs pdftotext about 1.5 s of one CPU, which one run
  // per CPU divides (pdfinfo gives the page count; without it, or for a few pages, one run does it all).
  int first = firstPage > 0 ? firstPage : 1;
  int last = lastPage;
  if (last == 0) last = pageCount(path);
  std::vector<std::pair<int, int>> runs;
  const int workers = pdfWorkers();
  if (last >= first && last > 0) {
    const int pages = last - first + 1;
    const int n = std::clamp(pages / kMinPagesPerRun, 1, 2 * workers);  // 2 per worker: runs differ in cost
    for (int k = 0; k < n; ++k) {
      const int a = first + pages * k / n, b = first + pages * (k + 1) / n - 1;
      runs.emplace_back(a, b);
    }
  } else {
    runs.emplace_back(firstPage, lastPage);  // pdfinfo failed: one run, pdftotext says what is wrong
  }

  std::vector<Child> children(runs.size());
  std::size_t next = 0, running = 0, total = 0;
  bool tooLong = false;
  int failed = 0;  // errno of a failed start
  while (next < runs.size() || running > 0) {
    while (next < runs.size() && static_cast<int>(running) < workers && failed == 0) {
      std::vector<std::string> args = {"pdftotext", "-layout", "-enc", "UTF-8"};
      if (runs[next].first > 0) {
        args.insert(args.end(),
                    {"-f", std::to_string(runs[next].first), "-l", std::to_string(runs[next].second)});
      }
      args.insert(args.end(), {path, "-"});
      failed = start(args, children[next]);
      if (failed == 0) ++running;
      ++next;
    }
    if (running == 0) break;
    std::vector<pollfd> fds;
    std::vector<Child*> owners;
    for (Child& c : children) {
      if (c.fd >= 0) {
        fds.push_back({c.fd, POLLIN, 0});
        owners.push_back(&c);
      }
    }
    if (poll(fds.data(), fds.size(), -1) < 0 && errno != EINTR) break;
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (fds[i].revents == 0) continue;
      readSome(*owners[i], total, tooLong);
      if (owners[i]->done) --running;
    }
  }
  if (failed != 0) {
    r.error = failed == ENOENT ? kInstall : std::string("cannot run pdftotext: ") + std::strerror(failed);
    return r;
  }
  for (const Child& c : children) {
    if (WIFEXITED(c.status) && WEXITSTATUS(c.status) == 127) {
      r.error = kInstall;
      return r;
    }
    if (!WIFEXITED(c.status) || WEXITSTATUS(c.status) != 0) {
      r.error = "pdftotext could not read " + path + " (exit status " + statusText(c.status) + ")";
      return r;
    }
  }
  if (tooLong) {
    r.error = "the text of " + path + " is over " + std::to_string(kMaxText >> 20) +
              " MiB; import a range of pages with --pages A-B";
    return r;
  }
  for (const Child& c : children)
    r.text += c.out;
  r.ok = true;
  return r;
}

}  // namespace regmapgen
