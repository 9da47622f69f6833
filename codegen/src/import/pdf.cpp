#include "import/pdf.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
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

}  // namespace

bool looksLikePdf(const std::string& bytes) {
  return bytes.rfind("%PDF-", 0) == 0;
}

PdfText pdfToText(const std::string& path, int firstPage, int lastPage) {
  PdfText r;
  std::vector<std::string> args = {"pdftotext", "-layout", "-enc", "UTF-8"};
  if (firstPage > 0) {
    args.insert(args.end(), {"-f", std::to_string(firstPage), "-l", std::to_string(lastPage)});
  }
  args.insert(args.end(), {path, "-"});
  std::vector<char*> argv;
  for (std::string& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);

  int pipeFds[2];
  if (pipe(pipeFds) != 0) {
    r.error = std::string("cannot create a pipe: ") + std::strerror(errno);
    return r;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
  // pdftotext reports every font it cannot map ("Syntax Error: Unknown character collection ..."), which
  // says nothing about the text; its exit status says whether it read the file.
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addclose(&actions, pipeFds[0]);
  posix_spawn_file_actions_addclose(&actions, pipeFds[1]);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "pdftotext", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipeFds[1]);
  if (spawned != 0) {
    close(pipeFds[0]);
    r.error = spawned == ENOENT ? kInstall : std::string("cannot run pdftotext: ") + std::strerror(spawned);
    return r;
  }
  char buf[65536];
  bool tooLong = false;
  for (;;) {
    const ssize_t n = read(pipeFds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    if (r.text.size() + static_cast<std::size_t>(n) > kMaxText) {
      tooLong = true;  // keep reading (and discarding) so pdftotext can finish
      continue;
    }
    r.text.append(buf, static_cast<std::size_t>(n));
  }
  close(pipeFds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
    r.error = kInstall;
  } else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    r.error = "pdftotext could not read " + path + " (exit status " +
              (WIFEXITED(status) ? std::to_string(WEXITSTATUS(status)) : std::string("signal")) + ")";
  } else if (tooLong) {
    r.error = "the text of " + path + " is over " + std::to_string(kMaxText >> 20) +
              " MiB; import a range of pages with --pages A-B";
  } else {
    r.ok = true;
  }
  return r;
}

}  // namespace regmapgen
