// Issue 15: input that made `regmapgen check` and `import` crash, overflow the stack or take quadratic time.
// Each must end in a file:line:col error, with nothing undefined on the way (these tests run under ASan and
// UBSan, which abort on the old code).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>

#include "import/import.hpp"
#include "import/table_reader.hpp"
#include "test_support.hpp"

namespace regmapgen {
namespace {

// The first rendered diagnostic line, e.g. "t.yaml:8:15: error: ...".
std::string firstLine(const std::string& text) {
  return text.substr(0, text.find('\n'));
}

TEST(HostileInput, FieldBeyondBit31WithoutWidthIsAnErrorNotUndefinedShift) {
  // No width, so nothing bounded the bit number: the mask shifted a 64-bit 1 by 70.
  const auto c = test::checkText(
      "family: t\n"
      "fieldsets:\n"
      "  - name: Foo\n"
      "    description: x\n"
      "    source: unverified\n"
      "    fields:\n"
      "      - name: A\n"
      "        bits: 70\n"
      "      - name: B\n"
      "        bits: \"63:0\"\n");
  EXPECT_NE(c.text.find("t.yaml:8:15: error: fieldset 'Foo' field 'A': bit 70 is beyond bit 31"),
            std::string::npos)
      << c.text;
  EXPECT_NE(c.text.find("t.yaml:10:15: error: fieldset 'Foo' field 'B': bit 63 is beyond bit 31"),
            std::string::npos)
      << c.text;
  EXPECT_NE(c.text.find("has no 'width' (required)"), std::string::npos) << c.text;
}

TEST(HostileInput, ValuesOf50000CharactersAreLineLengthErrors) {
  // Each of these went through std::regex, which recursed once per character.
  const std::string big(50000, '9');
  for (const std::string& value : {"1." + big, big, "0x" + big, "SLUU" + std::string(50000, 'A')}) {
    for (const char* key : {"min", "scale", "source"}) {
      const auto c = test::checkText(std::string("family: t\ncommands:\n  - name: A\n    addr: 0x10\n") +
                                     "    type: U1\n    access: r\n    description: x\n    " + key + ": " +
                                     value + "\n");
      EXPECT_EQ(firstLine(c.text).rfind("t.yaml:", 0), 0u) << c.text.substr(0, 300);
      EXPECT_NE(c.text.find("t.yaml:8:4097: error: line is " +
                            std::to_string(value.size() + 6 + std::string(key).size()) +
                            " bytes long; lines are limited to 4096 bytes"),
                std::string::npos)
          << c.text.substr(0, 300);
    }
  }
  const auto family = test::checkText("family: a" + std::string(60000, 'b') + "\n");
  EXPECT_NE(family.text.find("t.yaml:1:4097: error: line is 60009 bytes long"), std::string::npos);
}

TEST(HostileInput, LongLinesAreShownAsAWindowAroundTheCaret) {
  const auto c = test::checkText("family: t\ncommands: " + std::string(3000, 'x') + "\n");
  // The source line under the message is cut to about 120 characters around the caret.
  std::istringstream in(c.text);
  std::string line;
  while (std::getline(in, line))
    EXPECT_LT(line.size(), 200u) << line.substr(0, 200);
}

TEST(HostileInput, NestingTenThousandLevelsDeepIsAnError) {
  // Block mappings and block sequences of 10 000 lines, one column deeper each (back to column 1 every 200
  // lines), and a flow sequence 2 000 levels deep.
  std::string maps = "family: t\nx:\n", seqs = "family: t\nx:\n";
  for (int i = 1; i <= 10000; ++i) {
    maps += std::string(static_cast<std::size_t>(i % 200 + 1), ' ') + "a:\n";
    seqs += std::string(static_cast<std::size_t>(i % 200 + 1), ' ') + "-\n";
  }
  const std::string flow = "family: t\nx: " + std::string(2000, '[') + std::string(2000, ']') + "\n";
  for (const std::string& text : {maps, seqs, flow}) {
    const auto c = test::checkText(text);
    EXPECT_NE(c.text.find("error: nesting deeper than 32 levels"), std::string::npos)
        << c.text.substr(0, 400);
    EXPECT_EQ(firstLine(c.text).rfind("t.yaml:", 0), 0u) << c.text.substr(0, 300);
  }
  // One message for the flow sequence, not one per open bracket.
  const auto c = test::checkText(flow);
  EXPECT_EQ(c.text.find("unterminated flow sequence"), std::string::npos) << c.text.substr(0, 400);
  EXPECT_NE(c.text.find("t.yaml:2:35: error: nesting deeper than 32 levels"), std::string::npos) << c.text;
}

TEST(HostileInput, ManyErrorsPrintAtMost200) {
  std::string text = "family: t\n";
  for (int i = 0; i < 1000; ++i)
    text += "\tbad: tab\n";
  const auto c = test::checkText(text);
  EXPECT_GE(c.errors, 1000u);
  EXPECT_NE(c.text.find("more diagnostic(s) not shown"), std::string::npos);
  EXPECT_LT(std::count(c.text.begin(), c.text.end(), '^'), 201);
}

// A family of n subcommands at consecutive codes, each with its own fieldset, and a last entry that repeats
// the first one's code.
std::string manyEntries(int n) {
  std::string text = "family: t\nsubcommands:\n";
  for (int i = 0; i < n; ++i) {
    text += "  - name: E" + std::to_string(i) + "\n    addr: " + std::to_string(i) +
            "\n    type: H1\n    access: r\n    fieldset: F" + std::to_string(i) +
            "\n    description: x\n    source: unverified\n";
  }
  text +=
      "  - name: Again\n    addr: 0\n    type: U1\n    access: r\n    description: x\n    source: "
      "unverified\nfieldsets:\n";
  for (int i = 0; i < n; ++i) {
    text += "  - name: F" + std::to_string(i) +
            "\n    width: 8\n    description: x\n    source: unverified\n    fields:\n      - name: A\n"
            "        bits: 0\n";
  }
  return text;
}

// Seconds check() takes on a built model (the best of three runs), and its rendered diagnostics.
double secondsToCheck(const std::string& text, std::string& rendered) {
  Sources sources;
  sources.add("t.yaml", text);
  Diagnostics built(sources);
  const Model model = build(sources, built);
  double best = 1e9;
  for (int run = 0; run < 3; ++run) {
    Diagnostics diag(sources);
    const auto start = std::chrono::steady_clock::now();
    check(model, diag);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    std::ostringstream out;
    diag.render(out);
    rendered = out.str();
  }
  return best;
}

TEST(HostileInput, CheckIsLinearInTheEntries) {
  // Issue 24: 16 000 entries took 20 s, as each entry's address was compared with every entry before it and
  // each fieldset looked for its users among all entries. Eight times the entries must take about eight times
  // as long (a quadratic check takes 64 times); the ratio of the best of three runs is compared, not a time.
  std::string small, large;
  const double tSmall = secondsToCheck(manyEntries(1000), small);
  const double tLarge = secondsToCheck(manyEntries(8000), large);
  const double ratio = tLarge / std::max(tSmall, 1e-6);
  std::printf(
      "REPORT regmapgen.check_8000_entries_ms=%.1f check_1000_entries_ms=%.1f ratio=%.1f (linear: 8, "
      "quadratic: 64; measured, host build)\n",
      tLarge * 1e3, tSmall * 1e3, ratio);
  EXPECT_LT(ratio, 24.0);
  // Still finds the one duplicate, named against the first entry, and nothing else.
  EXPECT_NE(large.find("t.yaml:56004:11: error: duplicate address 0x0000: subcommand 'Again' and subcommand "
                       "'E0' (t.yaml:4)"),
            std::string::npos)
      << large.substr(0, 400);
  EXPECT_EQ(std::count(large.begin(), large.end(), '^'), 1);
}

struct Imported {
  int rc = 0;
  std::string yaml, err;
};

Imported import(const std::string& text) {
  std::ostringstream out, err;
  Imported r;
  r.rc = runImport("in.txt", text, ImportOptions{}, out, err);
  r.yaml = out.str();
  r.err = err.str();
  return r;
}

TEST(HostileInput, ImportOfA50000CharacterValueIsAnError) {
  for (const std::string& cell : {std::string(50000, '1') + " mV", "0x" + std::string(50000, '1')}) {
    const auto r = import("Address | Name | Type | Units\n0x10 | A | U1 | 1\n0x11 | B | U1 | " + cell + "\n");
    EXPECT_EQ(r.rc, 1);
    EXPECT_EQ(r.yaml, "");
    EXPECT_EQ(firstLine(r.err).rfind("in.txt:3:4097: error: line is ", 0), 0u) << r.err.substr(0, 200);
  }
}

TEST(HostileInput, ImportOfALongLineOfBarsIsAnErrorAndLinear) {
  const auto r = import("Address | Name | Type\n" + std::string(200000, '|') + "\n");
  EXPECT_EQ(r.rc, 1);
  EXPECT_EQ(firstLine(r.err),
            "in.txt:2:4097: error: line is 200000 bytes long; lines are limited to 4096 bytes");
  // Within the limit, a row of 4 000 cells is read in one pass; every cell keeps its column.
  const TableText t = readTables("Address | Name | Type\n0x10 | A | U1" + std::string(4000, '|') + "x\n");
  ASSERT_EQ(t.events.size(), 2u);
  EXPECT_EQ(t.events[1].cells.size(), 4003u);
  EXPECT_EQ(t.events[1].cells.back().text, "x");
  EXPECT_EQ(t.events[1].cells.back().col, 4014);
}

}  // namespace
}  // namespace regmapgen
