// Test helper: writes tables into a PDF laid out the way TI's technical reference manuals are, so that
// `pdftotext -layout` (poppler, not our code) turns them into the text `regmapgen import` must read.
//
// - Every cell is placed at its column's x position in Helvetica (proportional, like TI's body font), so
//   pdftotext has to find the columns itself.
// - Long cells wrap at spaces onto the lines below (names, descriptions; units wrap as "50.6" over "mV").
// - Pages carry TI's furniture: "www.ti.com" and the section title at the top, "Submit Document Feedback",
// the
//   copyright line, the page number, the document title and its literature number with dates at the bottom.
// - A table that does not fit continues on the next page under "Table N-M. ... (continued)" and its
//   heading row again.
// Text is ASCII plus what WinAnsiEncoding has (en and em dash, degree, micro, copyright).
#pragma once

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace regmapgen::test {

struct TiTable {
  std::string caption;                         // "Table 13-1. Data Memory Table"
  std::vector<std::string> headings;           // one per column
  std::vector<int> wrapAt;                     // characters per line of each column's cells (0: no wrap)
  std::vector<std::vector<std::string>> rows;  // cells; '\n' forces a line break inside a cell
  std::string section;                         // page header title
};

class TiPdf {
 public:
  // Adds a table starting on a new page; returns the 1-based pages it occupies.
  std::pair<int, int> add(const TiTable& t) {
    const int first = static_cast<int>(pages_.size()) + 1;
    const std::vector<double> x = columns(t);
    newPage(t.section);
    caption(t.caption);
    heading(t, x);
    for (const auto& row : t.rows) {
      std::vector<std::vector<std::string>> lines;
      std::size_t height = 1;
      for (std::size_t k = 0; k < row.size(); ++k) {
        lines.push_back(wrap(row[k], k < t.wrapAt.size() ? t.wrapAt[k] : 0));
        height = std::max(height, lines.back().size());
      }
      if (y_ - static_cast<double>(height) * kLine < kBottom) {
        newPage(t.section);
        caption(t.caption + " (continued)");
        heading(t, x);
      }
      for (std::size_t i = 0; i < height; ++i) {
        for (std::size_t k = 0; k < lines.size(); ++k) {
          if (i < lines[k].size()) text(x[k], y_, lines[k][i]);
        }
        y_ -= kLine;
      }
    }
    return {first, static_cast<int>(pages_.size())};
  }

  void write(const std::string& path) {
    if (!pages_.empty() && !finished_) footer();
    finished_ = true;
    std::ofstream out(path, std::ios::binary);
    out << bytes();
  }

 private:
  static constexpr double kSize = 7, kLine = 9, kTop = 740, kBottom = 70, kLeft = 40, kGap = 12,
                          kWidth = 1190;

  // Helvetica advance widths, generously rounded up (a wider guess only widens the gaps).
  static double advance(unsigned char c) {
    if (c == ' ') return 0.28;
    if (c == 'W' || c == 'M' || c == 'm' || c == 'w' || c == '@') return 0.95;
    if (c >= 'A' && c <= 'Z') return 0.78;
    if (c == 'i' || c == 'l' || c == 'j' || c == 'I' || c == '.' || c == ',' || c == ':' || c == '|')
      return 0.3;
    return 0.6;
  }
  static double width(const std::string& s) {
    double w = 0;
    for (unsigned char c : s)
      w += (c & 0xC0) == 0x80 ? 0 : advance(c);
    return w * kSize;
  }

  static std::vector<std::string> wrap(const std::string& cell, int at) {
    std::vector<std::string> out;
    std::istringstream paragraphs(cell);
    for (std::string para; std::getline(paragraphs, para, '\n');) {
      std::istringstream words(para);
      std::string line;
      for (std::string w; words >> w;) {
        if (at > 0 && !line.empty() && static_cast<int>(line.size() + 1 + w.size()) > at) {
          out.push_back(line);
          line.clear();
        }
        line += (line.empty() ? "" : " ") + w;
      }
      if (!line.empty()) out.push_back(line);
    }
    if (out.empty()) out.emplace_back();
    return out;
  }

  std::vector<double> columns(const TiTable& t) const {
    std::vector<double> x;
    double at = kLeft;
    for (std::size_t k = 0; k < t.headings.size(); ++k) {
      x.push_back(at);
      double w = width(t.headings[k]);
      for (const auto& row : t.rows) {
        if (k < row.size()) {
          for (const std::string& l : wrap(row[k], k < t.wrapAt.size() ? t.wrapAt[k] : 0))
            w = std::max(w, width(l));
        }
      }
      at += w + kGap;
    }
    return x;
  }

  void newPage(const std::string& section) {
    if (!pages_.empty()) footer();
    pages_.emplace_back();
    y_ = kTop;
    text(kLeft, 770, "www.ti.com");
    text(kWidth - 200, 770, section);
    y_ -= kLine;
  }
  void footer() {
    const int n = static_cast<int>(pages_.size());
    text(kLeft, 40, "Submit Document Feedback");
    text(kWidth / 2 - 100, 40, "Copyright \xC2\xA9 2022 Texas Instruments Incorporated");
    text(kLeft, 28, std::to_string(100 + n));
    text(kWidth / 2 - 100, 28, "BQ76952 Technical Reference Manual");
    text(kWidth - 330, 28, "SLUUBY2B \xE2\x80\x93 SEPTEMBER 2020 \xE2\x80\x93 REVISED MAY 2022");
  }
  void caption(const std::string& c) {
    text(kWidth / 2 - width(c) / 2, y_, c);
    y_ -= 1.6 * kLine;
  }
  void heading(const TiTable& t, const std::vector<double>& x) {
    for (std::size_t k = 0; k < t.headings.size(); ++k)
      text(x[k], y_, t.headings[k]);
    y_ -= 1.3 * kLine;
  }

  // UTF-8 to WinAnsiEncoding, with PDF string escapes.
  static std::string pdfString(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const auto c = static_cast<unsigned char>(s[i]);
      std::string u = s.substr(i, (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : 1);
      i += u.size() - 1;
      char b = '?';
      if (u.size() == 1) {
        b = static_cast<char>(c);
      } else if (u == "\xE2\x80\x93") {
        b = '\x96';  // en dash
      } else if (u == "\xE2\x80\x94") {
        b = '\x97';  // em dash
      } else if (u == "\xC2\xB0") {
        b = '\xB0';  // degree
      } else if (u == "\xC2\xB5") {
        b = '\xB5';  // micro
      } else if (u == "\xC2\xA9") {
        b = '\xA9';  // copyright
      }
      if (b == '(' || b == ')' || b == '\\') out += '\\';
      out += b;
    }
    return out;
  }
  void text(double x, double y, const std::string& s) {
    std::ostringstream op;
    op << "BT /F1 " << kSize << " Tf " << x << " " << y << " Td (" << pdfString(s) << ") Tj ET\n";
    pages_.back() += op.str();
  }

  std::string bytes() const {
    std::vector<std::string> objects = {"<< /Type /Catalog /Pages 2 0 R >>"};
    std::string kids;
    for (std::size_t i = 0; i < pages_.size(); ++i)
      kids += std::to_string(3 + 2 * i) + " 0 R ";
    objects.push_back("<< /Type /Pages /Kids [" + kids + "] /Count " + std::to_string(pages_.size()) + " >>");
    const std::size_t font = 3 + 2 * pages_.size();
    for (std::size_t i = 0; i < pages_.size(); ++i) {
      objects.push_back("<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " +
                        std::to_string(static_cast<int>(kWidth)) + " 792] /Resources << /Font << /F1 " +
                        std::to_string(font) + " 0 R >> >> /Contents " + std::to_string(4 + 2 * i) +
                        " 0 R >>");
      objects.push_back("<< /Length " + std::to_string(pages_[i].size()) + " >>\nstream\n" + pages_[i] +
                        "endstream");
    }
    objects.push_back("<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica /Encoding /WinAnsiEncoding >>");
    std::string pdf = "%PDF-1.4\n";
    std::vector<std::size_t> offsets;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      offsets.push_back(pdf.size());
      pdf += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
    }
    const std::size_t xref = pdf.size();
    pdf += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
    for (std::size_t o : offsets) {
      std::string n = std::to_string(o);
      pdf += std::string(10 - n.size(), '0') + n + " 00000 n \n";
    }
    pdf += "trailer\n<< /Size " + std::to_string(objects.size() + 1) + " /Root 1 0 R >>\nstartxref\n" +
           std::to_string(xref) + "\n%%EOF\n";
    return pdf;
  }

  std::vector<std::string> pages_;  // content streams
  double y_ = kTop;
  bool finished_ = false;
};

}  // namespace regmapgen::test
