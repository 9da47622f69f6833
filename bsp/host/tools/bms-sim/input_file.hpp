// Files bms-sim reads (--elf, --scenario): each bounded in size, each refused with one clear message.
//
// A directory, a device, a pipe that never ends (/dev/zero) or a file far larger than any input of its kind
// ends the run before it starts with one message naming the path and why (exit status 2), never an exception
// or unbounded memory. `error` says why, without the path (the caller puts it first).
#pragma once

#include <cstddef>
#include <string>

namespace bmssim {

enum class InputError { None, Missing, Unreadable };

// Reads at most `maxBytes` of `path` into `text`. Missing: there is no such file (`error` says so);
// Unreadable: a directory, a read error, or more than `maxBytes` (`error` names the limit and `what` the
// file should be, e.g. "scenario file").
InputError readInputFile(const std::string& path, size_t maxBytes, const char* what, std::string& text,
                         std::string& error);

// For a file another reader opens itself (the twin's ElfFile): a regular file of at most `maxBytes`.
InputError checkInputFile(const std::string& path, size_t maxBytes, const char* what, std::string& error);

// "16 MiB", "1 MiB", "512 KiB": a limit as the messages give it.
std::string sizeText(size_t bytes);

}  // namespace bmssim
