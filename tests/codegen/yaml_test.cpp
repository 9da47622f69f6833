// The YAML-subset reader: what it accepts, where it says things are, and that it reports every syntax error.
#include <gtest/gtest.h>

#include <sstream>

#include "diag/diag.hpp"
#include "yaml/yaml.hpp"

namespace regmapgen::yaml {
namespace {

struct Parsed {
  Node root;
  std::size_t errors = 0;
  std::string diagnostics;
};

Parsed parseText(const std::string& text) {
  Sources sources;
  const int f = sources.add("x.yaml", text);
  Diagnostics diag(sources);
  Parsed p;
  p.root = parse(sources, f, diag);
  p.errors = diag.errorCount();
  std::ostringstream out;
  diag.render(out);
  p.diagnostics = out.str();
  return p;
}

TEST(YamlReader, BlockMappingsSequencesAndLocations) {
  const Parsed p = parseText(
      "family: bq769x2   # a comment\n"
      "commands:\n"
      "  - name: Cell 1 Voltage\n"
      "    addr: 0x14\n"
      "\n"
      "  - name: 'It''s quoted'\n"
      "    tags: [a, \"b c\", [d]]\n");
  ASSERT_EQ(p.errors, 0u) << p.diagnostics;
  ASSERT_TRUE(p.root.isMap());
  EXPECT_EQ(p.root.find("family")->text, "bq769x2");
  const Node* cmds = p.root.find("commands");
  ASSERT_TRUE(cmds && cmds->isSeq());
  ASSERT_EQ(cmds->items.size(), 2u);
  const Node& first = cmds->items[0];
  EXPECT_EQ(first.find("name")->text, "Cell 1 Voltage");
  EXPECT_EQ(first.find("addr")->loc.line, 4);
  EXPECT_EQ(first.find("addr")->loc.col, 11);
  EXPECT_EQ(first.keys[0].loc.col, 5);  // "name" after "  - "
  const Node& second = cmds->items[1];
  EXPECT_EQ(second.find("name")->text, "It's quoted");
  EXPECT_TRUE(second.find("name")->quoted);
  const Node* tags = second.find("tags");
  ASSERT_TRUE(tags && tags->isSeq());
  ASSERT_EQ(tags->items.size(), 3u);
  EXPECT_EQ(tags->items[1].text, "b c");
  EXPECT_TRUE(tags->items[2].isSeq());
}

TEST(YamlReader, IndentlessSequenceUnderAKey) {
  const Parsed p = parseText("a:\n- 1\n- 2\nb: 3\n");
  ASSERT_EQ(p.errors, 0u) << p.diagnostics;
  EXPECT_EQ(p.root.find("a")->items.size(), 2u);
  EXPECT_EQ(p.root.find("b")->text, "3");
}

TEST(YamlReader, DoubleQuotedEscapesAndUtf8Columns) {
  const Parsed p = parseText("k: \"a\\\"b\\u00e9\\n\"\n名称: x\nz: \"\xE7\x94\xB5\xE5\x8E\x8B\"  # 电压\n");
  ASSERT_EQ(p.errors, 0u) << p.diagnostics;
  EXPECT_EQ(p.root.find("k")->text, "a\"b\xC3\xA9\n");
  // The key 名称 is two code points: its value starts in column 5, not byte column 9.
  EXPECT_EQ(p.root.find("\xE5\x90\x8D\xE7\xA7\xB0")->loc.col, 5);
}

TEST(YamlReader, TabInIndentationIsAnErrorAndParsingContinues) {
  const Parsed p = parseText("a:\n  b: 1\n\tc: 2\n  d: 3\n");
  EXPECT_EQ(p.errors, 1u);
  EXPECT_NE(p.diagnostics.find("x.yaml:3:1: error: tab in indentation"), std::string::npos) << p.diagnostics;
  // Recovery: the tab line is read at the indentation of its neighbours, nothing else is lost.
  const Node* a = p.root.find("a");
  ASSERT_TRUE(a && a->isMap());
  EXPECT_EQ(a->keys.size(), 3u);
}

TEST(YamlReader, UnterminatedQuotesAreReportedWhereTheyOpen) {
  const Parsed p = parseText("a: \"open\nb: 'also open\nc: fine\n");
  EXPECT_EQ(p.errors, 2u) << p.diagnostics;
  EXPECT_NE(p.diagnostics.find("x.yaml:1:4: error: unterminated double-quoted string"), std::string::npos);
  EXPECT_NE(p.diagnostics.find("x.yaml:2:4: error: unterminated single-quoted string"), std::string::npos);
  EXPECT_EQ(p.root.find("c")->text, "fine");
}

TEST(YamlReader, BadIndentationIsReportedWithTheExpectedColumn) {
  const Parsed p = parseText("a:\n  b: 1\n    c: 2\n  d: 3\n");
  EXPECT_EQ(p.errors, 1u) << p.diagnostics;
  EXPECT_NE(p.diagnostics.find("x.yaml:3:5: error: bad indentation: expected column 3"), std::string::npos)
      << p.diagnostics;
  EXPECT_EQ(p.root.find("a")->keys.size(), 2u);
}

TEST(YamlReader, UnsupportedSyntaxIsRejectedNotGuessed) {
  const Parsed p = parseText(
      "---\n"
      "a: {x: 1}\n"
      "b: |\n"
      "c: &anchor 1\n"
      "d: *anchor\n"
      "e: !tag v\n"
      "f: [1, 2\n"
      "g: x: y\n");
  EXPECT_EQ(p.errors, 8u) << p.diagnostics;
  for (const char* needle :
       {"1:1: error: document markers", "2:4: error: flow mappings", "3:4: error: block scalars",
        "4:4: error: anchors", "5:4: error: anchors", "6:4: error: anchors",
        "7:4: error: unterminated flow sequence", "8:5: error: plain scalar contains ': '"}) {
    EXPECT_NE(p.diagnostics.find(needle), std::string::npos) << needle << "\n" << p.diagnostics;
  }
}

TEST(YamlReader, DuplicateKeysAreErrors) {
  const Parsed p = parseText("a: 1\nb: 2\na: 3\n");
  EXPECT_EQ(p.errors, 1u);
  EXPECT_NE(p.diagnostics.find("x.yaml:3:1: error: duplicate key 'a' (first at line 1)"), std::string::npos)
      << p.diagnostics;
}

TEST(YamlReader, EveryErrorShowsTheLineAndACaret) {
  const Parsed p = parseText("a:\n  b: \"x\n");
  EXPECT_NE(p.diagnostics.find("    b: \"x\n       ^\n"), std::string::npos) << p.diagnostics;
}

TEST(YamlReader, EmptyFileIsNull) {
  EXPECT_TRUE(parseText("# only a comment\n\n").root.isNull());
}

}  // namespace
}  // namespace regmapgen::yaml
