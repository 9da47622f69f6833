#include "input_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace bmssim {

std::string sizeText(size_t bytes) {
  if (bytes % (1U << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  if (bytes % (1U << 10) == 0) return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + " bytes";
}

namespace {

InputError notFound(int err, std::string& error) {
  error = std::strerror(err);
  return err == ENOENT ? InputError::Missing : InputError::Unreadable;
}

InputError tooLarge(size_t maxBytes, const char* what, std::string& error) {
  error = std::string("larger than ") + sizeText(maxBytes) + ", which no " + what + " needs";
  return InputError::Unreadable;
}

}  // namespace

InputError readInputFile(const std::string& path, size_t maxBytes, const char* what, std::string& text,
                         std::string& error) {
  text.clear();
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return notFound(errno, error);
  if (S_ISDIR(st.st_mode)) {
    error = std::string("a directory, not a ") + what;
    return InputError::Unreadable;
  }
  // A regular file says its size; a pipe or device is read up to the limit and no further.
  if (S_ISREG(st.st_mode) && static_cast<unsigned long long>(st.st_size) > maxBytes)
    return tooLarge(maxBytes, what, error);
  std::FILE* in = std::fopen(path.c_str(), "rb");
  if (in == nullptr) return notFound(errno, error);
  char buf[4096];
  size_t n = 0;
  while (text.size() <= maxBytes && (n = std::fread(buf, 1, sizeof buf, in)) > 0)
    text.append(buf, n);
  const bool failed = std::ferror(in) != 0;
  const int err = errno;
  std::fclose(in);
  if (failed) {
    error = std::string("cannot read it: ") + std::strerror(err);
    return InputError::Unreadable;
  }
  if (text.size() > maxBytes) {
    text.clear();
    return tooLarge(maxBytes, what, error);
  }
  return InputError::None;
}

InputError checkInputFile(const std::string& path, size_t maxBytes, const char* what, std::string& error) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return notFound(errno, error);
  if (S_ISDIR(st.st_mode)) {
    error = std::string("a directory, not a ") + what;
    return InputError::Unreadable;
  }
  if (!S_ISREG(st.st_mode)) {
    error = std::string("not a regular file (a device or a pipe), not a ") + what;
    return InputError::Unreadable;
  }
  if (static_cast<unsigned long long>(st.st_size) > maxBytes) return tooLarge(maxBytes, what, error);
  return InputError::None;
}

}  // namespace bmssim
