// bmsctl: run one operation against a built-in device emulator through the real firmware driver and print
// the exact wire traffic (README "Host tools").
#include <cstdio>
#include <cstring>
#include <string>

#include "bmsctl/cli.hpp"
#include "bmsctl/send.hpp"
#include "flash/flash_command.hpp"

namespace {

void printUsage(FILE* out) {
  std::fprintf(
      out,
      "usage: bmsctl trace <device> [--<option>[=value]...] <operation> [args...]\n"
      "       bmsctl send --port DEV [--node N] [--timeout MS] <command> [Signal=value ...]\n"
      "       bmsctl flash IMAGE --port DEV [options]   (options: bmsctl flash --help)\n"
      "       bmsctl --help | -h\n"
      "\n"
      "Runs <operation> through the firmware driver against an emulated <device> on virtual time and\n"
      "prints every bus transaction, then the decoded result. Exit status: 0 done, 1 the operation failed "
      "on\n"
      "the emulated bus, 2 bad arguments.\n"
      "\ndevices, their operations and options:\n");
  for (const auto& d : bmsctl::devices()) {
    std::fprintf(out, "\n  %-10s %s\n", d.name, d.summary);
    // The usage text, one line per operation or option, indented under the device.
    for (const char* line = d.usage; line != nullptr && *line != '\0';) {
      const char* end = std::strchr(line, '\n');
      const int n = static_cast<int>(end != nullptr ? end - line : static_cast<long>(std::strlen(line)));
      std::fprintf(out, "    %.*s\n", n, line);
      line = end != nullptr ? end + 1 : line + n;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    printUsage(stdout);
    return 0;
  }
  if (argc < 2) {
    printUsage(stderr);
    return 2;
  }
  if (std::strcmp(argv[1], "send") == 0) return bmsctl::runSend(argc - 2, argv + 2);
  if (std::strcmp(argv[1], "flash") == 0) return bmsctl::flash::runFlash(argc - 2, argv + 2);
  if (std::strcmp(argv[1], "trace") != 0) {
    return bmsctl::usageError(std::string("unknown command '") + argv[1] +
                              "' (expected 'trace', 'send' or 'flash')");
  }
  if (argc < 3) return bmsctl::usageError("trace needs a device; try 'bmsctl --help'");

  bmsctl::TraceRequest request;
  request.device = argv[2];
  int i = 3;
  for (; i < argc && std::strncmp(argv[i], "--", 2) == 0; ++i) {
    std::string flag = argv[i];
    std::string value;
    const auto eq = flag.find('=');
    if (eq != std::string::npos) {
      value = flag.substr(eq + 1);
      flag = flag.substr(0, eq);
    } else if (flag == "--devices") {
      if (i + 1 >= argc) return bmsctl::usageError("--devices needs a number");
      value = argv[++i];
    }
    request.flags[flag] = value;
  }
  if (i >= argc) return bmsctl::usageError("trace " + request.device + " needs an operation");
  request.operation = argv[i++];
  for (; i < argc; ++i)
    request.args.emplace_back(argv[i]);

  for (const auto& d : bmsctl::devices()) {
    if (request.device == d.name) return d.handler(request);
  }
  std::string known;
  for (const auto& d : bmsctl::devices())
    known += std::string(known.empty() ? "" : ", ") + d.name;
  return bmsctl::usageError("unknown device '" + request.device + "'" +
                            (known.empty() ? std::string() : " (known: " + known + ")"));
}
