// The model builder and checker: each rule reports at the right place, and good tables pass.
#include <gtest/gtest.h>

#include "emit/emit.hpp"
#include "test_support.hpp"

namespace regmapgen {
namespace {

using test::checkFiles;
using test::checkText;
using test::withHeader;

std::string command(const std::string& name, const std::string& addr, const std::string& type,
                    const std::string& extra = "") {
  return "  - name: " + name + "\n    addr: " + addr + "\n    type: " + type + "\n    access: r\n" + extra +
         "    description: d.\n    source: SLUUBY2B\n";
}

bool has(const test::Checked& c, const std::string& needle) {
  return c.text.find(needle) != std::string::npos;
}

TEST(Check, AValidFamilyPassesAndLists) {
  const auto c =
      checkText(withHeader("commands:\n" + command("Cell 1 Voltage", "0x14", "I2", "    unit: mV\n") +
                           command("Cell 2 Voltage", "0x16", "I2")));
  EXPECT_EQ(c.errors, 0u) << c.text;
  EXPECT_EQ(emitList(c.model), "command 0x14 Cell1Voltage I2\ncommand 0x16 Cell2Voltage I2\n");
}

TEST(Check, TwoByteCommandOverlapsTheNextAddress) {
  // A 2-byte entry at 0x14 occupies 0x15 too (issue 3's example).
  const auto c =
      checkText(withHeader("commands:\n" + command("A", "0x14", "I2") + command("B", "0x15", "U1")));
  EXPECT_EQ(c.errors, 1u) << c.text;
  EXPECT_TRUE(has(c, "t.yaml:10:11: error: command 'B' at 0x15..0x15 overlaps command 'A' at 0x14..0x15"))
      << c.text;
}

TEST(Check, SubcommandCodesDoNotOverlapByPayloadSize) {
  // Subcommand addresses are codes: a 6-byte payload at 0x0002 does not reach 0x0003.
  const auto c =
      checkText(withHeader("subcommands:\n"
                           "  - name: A\n    addr: 0x0002\n    type: B6\n    access: r\n    description: "
                           "d.\n    source: unverified\n"
                           "  - name: B\n    addr: 0x0003\n    type: U2\n    access: r\n    description: "
                           "d.\n    source: unverified\n"
                           "  - name: C\n    addr: 0x0003\n    type: none\n    access: cmd\n    description: "
                           "d.\n    source: unverified\n"));
  EXPECT_EQ(c.errors, 1u) << c.text;
  EXPECT_TRUE(has(c, "duplicate address 0x0003")) << c.text;
}

TEST(Check, ErrorsAcrossFilesOfOneFamily) {
  const auto c = checkFiles({{"a.yaml", withHeader("commands:\n" + command("A", "0x14", "I2"))},
                             {"b.yaml", withHeader("commands:\n" + command("A", "0x30", "I2"))}});
  EXPECT_EQ(c.errors, 1u) << c.text;
  EXPECT_TRUE(has(c, "b.yaml:3:11: error: duplicate name: command 'A' is already defined at a.yaml:3"))
      << c.text;
}

TEST(Check, IdentifierCollisionsNeedAnExplicitId) {
  const auto c = checkText(withHeader("commands:\n" + command("FET Status", "0x10", "H1") +
                                      command("FET_STATUS", "0x11", "H1") + command("2LVL", "0x12", "H1")));
  EXPECT_EQ(c.errors, 2u) << c.text;
  EXPECT_TRUE(
      has(c, "identifier cmd::FetStatus of command 'FET_STATUS' is also used by command 'FET Status'"));
  EXPECT_TRUE(has(c, "'2lvl' (derived from the name) is not a usable C++ identifier; add an 'id:'"))
      << c.text;
}

TEST(Check, TypeAccessAgreement) {
  const auto c =
      checkText(withHeader("subcommands:\n"
                           "  - name: A\n    addr: 0x0001\n    type: none\n    access: r\n    description: "
                           "d.\n    source: unverified\n"
                           "  - name: B\n    addr: 0x0002\n    type: U2\n    access: cmd\n    description: "
                           "d.\n    source: unverified\n"
                           "commands:\n"
                           "  - name: C\n    addr: 0x10\n    type: U1\n    access: config_update\n    "
                           "description: d.\n    source: unverified\n"));
  EXPECT_EQ(c.errors, 3u) << c.text;
  EXPECT_TRUE(has(c, "type 'none' carries no data, so access must be 'cmd'"));
  EXPECT_TRUE(has(c, "access 'cmd' has no data, so type must be 'none'"));
  EXPECT_TRUE(has(c, "access 'config_update' is only for datamem entries"));
}

TEST(Check, LimitsMustFitAndBeOrdered) {
  const auto c = checkText(
      withHeader("commands:\n" + command("A", "0x10", "I1", "    min: -129\n") +
                 command("B", "0x11", "U1", "    min: 10\n    max: 5\n") +
                 command("C", "0x12", "U2", "    min: 1\n    default: 0\n") +
                 command("D", "0x14", "B4", "    default: 1\n") +
                 command("E", "0x18", "F4", "    min: 1.00E-02\n    max: 1000\n    default: 7.4768\n")));
  EXPECT_EQ(c.errors, 4u) << c.text;
  EXPECT_TRUE(has(c, "min -129 is too wide for type I1 (-128..127)"));
  EXPECT_TRUE(has(c, "max 5 is below min 10"));
  EXPECT_TRUE(has(c, "default 0 is below min 1"));
  EXPECT_TRUE(has(c, "'default' is only meaningful for scalar types (type is B4)"));
}

TEST(Check, FieldsetsAndEnums) {
  const auto c = checkText(
      withHeader("commands:\n" + command("Status", "0x12", "H2", "    fieldset: Status\n") +
                 command("Flags", "0x14", "H1", "    fieldset: Status\n") +
                 "fieldsets:\n"
                 "  - name: Status\n    width: 16\n    description: d.\n    source: unverified\n    fields:\n"
                 "      - name: SEC[1:0]\n        bits: \"9:8\"\n        enum: Security\n"
                 "      - name: TRY\n        bits: 3\n"
                 "      - name: BIG\n        bits: \"17:16\"\n"
                 "enums:\n"
                 "  - name: Security\n    description: d.\n    values:\n"
                 "      - name: Sealed\n        value: 3\n      - name: Wide\n        value: 4\n"
                 "  - name: Unused\n    description: d.\n    values:\n      - name: X\n        value: 0\n"));
  EXPECT_EQ(c.errors, 4u) << c.text;
  EXPECT_TRUE(has(c, "fieldset 'Status' is 16 bits wide but the entry's type is H1"));
  EXPECT_TRUE(has(c, "accessor name 'try' (derived from the name) is not usable; add an 'id:'"));
  EXPECT_TRUE(has(c, "bits 17:16 exceed the 16-bit width"));
  EXPECT_TRUE(has(c, "value 'Wide' = 4 is too wide for fieldset 'Status' field 'SEC[1:0]' (2 bits)"));
  EXPECT_EQ(c.warnings, 1u);
  EXPECT_TRUE(has(c, "warning: enum 'Unused' is not used"));
}

TEST(Check, ValuesMustLieOnRegisters) {
  const auto c =
      checkText(withHeader("registers:\n"
                           "  - name: V_HI\n    addr: 0x0568\n    type: U1\n    access: r\n    description: "
                           "d.\n    source: SLUSE81E\n"
                           "values:\n"
                           "  - name: V\n    addr: 0x0568\n    type: I2\n    access: r\n    description: "
                           "d.\n    source: SLUSE81E\n"));
  EXPECT_EQ(c.errors, 1u) << c.text;
  EXPECT_TRUE(has(c, "value 'V': byte 0x0569 is not a register of family 't'"));
}

TEST(Check, SourcesAreLiteratureNumbersOrUnverified) {
  const auto c =
      checkText(withHeader("commands:\n"
                           "  - name: A\n    addr: 0x10\n    type: U1\n    access: r\n    description: d.\n  "
                           "  source: TRM page 4\n"
                           "  - name: B\n    addr: 0x11\n    type: U1\n    access: r\n    description: d.\n  "
                           "  source: SLUUBY2B unverified\n"
                           "  - name: C\n    addr: 0x12\n    type: U1\n    access: r\n    description: d.\n  "
                           "  source: SLUUBY2B SBS1.1\n"));
  EXPECT_EQ(c.errors, 4u) << c.text;  // TRM, page, 4; and the mixed unverified
  EXPECT_TRUE(has(c, "'unverified' stands alone"));
}

TEST(Check, StructuralMistakesAreNamed) {
  const auto c = checkText("family: t\ncommands:\n  name: A\nfieldsets: 3\nextra: 1\n");
  EXPECT_TRUE(has(c, "'commands' must be a list of entry mappings")) << c.text;
  EXPECT_TRUE(has(c, "'fieldsets' must be a list of fieldset mappings")) << c.text;
  EXPECT_TRUE(has(c, "t.yaml:5:1: error: unknown key 'extra' in the file")) << c.text;
}

TEST(Check, MissingFamilyAndEmptyFile) {
  const auto c = checkFiles({{"a.yaml", "commands: []\n"}, {"b.yaml", ""}});
  EXPECT_TRUE(has(c, "a.yaml:1:1: error: the file has no 'family' (required)")) << c.text;
  EXPECT_TRUE(has(c, "b.yaml:1:1: error: empty file")) << c.text;
}

}  // namespace
}  // namespace regmapgen
