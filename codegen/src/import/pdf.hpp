// Text of a PDF as `pdftotext -layout` prints it (poppler-utils), for `regmapgen import FILE.pdf`.
#pragma once

#include <string>

namespace regmapgen {

// A file whose first bytes are "%PDF-".
bool looksLikePdf(const std::string& bytes);

struct PdfText {
  bool ok = false;
  std::string text;   // pdftotext's output (pages separated by form feeds)
  std::string error;  // why not, with what to install when pdftotext is missing
};

// Runs `pdftotext -layout -enc UTF-8 [-f first -l last] path -` (first/last 0: every page). Reads its output
// through a pipe; waits for it to exit. Does not use a shell.
PdfText pdfToText(const std::string& path, int firstPage = 0, int lastPage = 0);

}  // namespace regmapgen
