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

// The text `pdftotext -layout -enc UTF-8 [-f first -l last] path -` prints (first/last 0: every page), made
// by several pdftotext runs over consecutive page ranges at once (one per CPU, pdfWorkers(); the page count
// from pdfinfo), read through pipes and joined in page order: the same text, in about 1/CPUs of the time.
// Waits for every run to exit; does not use a shell. pdftotext's warnings are dropped; a run that fails
// makes the whole conversion fail with its exit status.
PdfText pdfToText(const std::string& path, int firstPage = 0, int lastPage = 0);

// How many pdftotext runs go at once: the CPUs online (1..16).
int pdfWorkers();

}  // namespace regmapgen
