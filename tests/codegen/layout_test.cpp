// The pieces of the pdftotext -layout import: the table reader (columns, wrapped cells, page furniture,
// continued tables), TI's cell spellings, and `diff`.
#include <gtest/gtest.h>

#include "diff/diff.hpp"
#include "import/cells.hpp"
#include "import/furniture.hpp"
#include "import/table_reader.hpp"
#include "test_support.hpp"

namespace regmapgen {
namespace {

std::vector<const TableEvent*> rowsOf(const TableText& t) {
  std::vector<const TableEvent*> rows;
  for (const TableEvent& e : t.events) {
    if (e.kind == TableEvent::Kind::Row) rows.push_back(&e);
  }
  return rows;
}

TEST(LayoutReader, ColumnsFromTheHeadingAndWrappedCellsJoined) {
  const TableText t = readTables(
      "Class        Subclass   Address  Name                Type  Min Value Max Value Default Units\n"
      "Protections  CUV        0x9275   Threshold           U1    20        90        50      50.6\n"
      "                                                                                       mV\n"
      "                        0x9276   Delay between two   U2    1         2047      74      3.3 ms\n"
      "                                 checks\n");
  ASSERT_TRUE(t.errors.empty());
  ASSERT_EQ(t.events.front().kind, TableEvent::Kind::Heading);
  // "Min Value Max Value" is split into the two headings it is made of.
  EXPECT_EQ(t.events.front().roles,
            (std::vector<Role>{Role::Category, Role::Subcategory, Role::Address, Role::Name, Role::Type,
                               Role::Min, Role::Max, Role::Default, Role::Unit}));
  const auto rows = rowsOf(t);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]->cells[8].text, "50.6 mV");  // the unit wrapped onto the next line
  EXPECT_EQ(rows[1]->cells[3].text, "Delay between two checks");
  EXPECT_EQ(rows[1]->cells[0].text, "Protections");  // a merged class cell printed once
  EXPECT_EQ(rows[1]->cells[1].text, "CUV");
  EXPECT_EQ(rows[1]->cells[3].line, 4);
  EXPECT_EQ(rows[1]->cells[3].col, 34);
}

TEST(LayoutReader, NumbersLeftOfTheirHeadingStayInTheirColumn) {
  // Right-aligned numbers start left of "Min"; the blank column that runs through every line is the boundary.
  const TableText t = readTables(
      "Address  Name          Type      Min     Max\n"
      "0x9180   Cell 1 Gain   I2     -32767   32767\n"
      "0x9182   Cell 2 Gain   I2         -1       1\n");
  const auto rows = rowsOf(t);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]->cells[2].text, "I2");
  EXPECT_EQ(rows[0]->cells[3].text, "-32767");
  EXPECT_EQ(rows[1]->cells[3].text, "-1");
}

TEST(LayoutReader, PageFurnitureIsSkippedAndAContinuedTableIsOneTable) {
  const TableText t = readTables(
      "Command  Name            Type\n"
      "0x14     Cell 1 Voltage  I2\n"
      "\n"
      "Submit Document Feedback          Copyright \xC2\xA9 2022 Texas Instruments Incorporated\n"
      "108       BQ76952 Technical Reference Manual     SLUUBY2B \xE2\x80\x93 SEPTEMBER 2020 \xE2\x80\x93 "
      "REVISED MAY 2022\n"
      "\fwww.ti.com                                     Direct Commands\n"
      "\n"
      "             Table 12-1. Standard Commands (continued)\n"
      "Command  Name            Type\n"
      "0x16     Cell 2 Voltage  I2\n"
      "\n"
      "The next section describes the bits.\n");
  ASSERT_TRUE(t.errors.empty());
  std::vector<std::string> kinds;
  for (const TableEvent& e : t.events)
    kinds.push_back(e.kind == TableEvent::Kind::Heading ? (e.continued ? "H+" : "H")
                    : e.kind == TableEvent::Kind::Row   ? "R:" + e.cells[1].text
                                                        : "P:" + e.text);
  EXPECT_EQ(kinds, (std::vector<std::string>{"H", "R:Cell 1 Voltage", "H+", "R:Cell 2 Voltage",
                                             "P:The next section describes the bits."}));
}

TEST(LayoutReader, HeadingOverTwoLines) {
  const TableText t = readTables(
      "SBS    Name          Access          Type  Unit\n"
      "Cmd                  SE   US   FA\n"
      "0x09   Voltage()     R    R    R     U2    mV\n");
  ASSERT_FALSE(t.events.empty());
  const std::vector<Role>& roles = t.events[0].roles;
  EXPECT_EQ(roles.front(), Role::Address);  // "SBS" over "Cmd"
  const auto rows = rowsOf(t);
  ASSERT_EQ(rows.size(), 1u);
  const auto cellOf = [&](Role r) {
    std::string text;
    for (std::size_t k = 0; k < roles.size(); ++k) {
      if (roles[k] == r) text = rows[0]->cells[k].text;  // the last of the role: FA for access
    }
    return text;
  };
  EXPECT_EQ(cellOf(Role::Address), "0x09");
  EXPECT_EQ(cellOf(Role::Name), "Voltage()");
  EXPECT_EQ(cellOf(Role::Access), "R");
  EXPECT_EQ(cellOf(Role::Type), "U2");
  EXPECT_EQ(cellOf(Role::Unit), "mV");
}

TEST(LayoutReader, ProseAndOtherCaptionsEndATable) {
  const TableText t = readTables(
      "Address  Name        Type\n"
      "0x14     Cell 1      I2\n"
      "This paragraph runs from the left margin across all the columns of the table above it.\n"
      "0x16     Cell 2      I2\n");
  EXPECT_EQ(rowsOf(t).size(), 1u);
  const TableText c =
      readTables("Address  Name        Type\n0x14     Cell 1      I2\nTable 4-2. Next\n0x16 Cell 2 I2\n");
  EXPECT_EQ(rowsOf(c).size(), 1u);
}

TEST(Furniture, HeadersFootersAndPageNumbers) {
  for (const char* line :
       {"www.ti.com                    Data Memory Summary", "  212",
        "Copyright \xC2\xA9 2022, Texas Instruments Incorporated", "Submit Document Feedback",
        "SLUUAQ3A \xE2\x80\x93 April 2016 \xE2\x80\x93 Revised October 2022",
        "BQ76952 TRM     SLUUBY2B - SEPTEMBER 2020"}) {
    EXPECT_TRUE(isPageFurniture(line)) << line;
  }
  for (const char* line : {"0x9180   Cell 1 Gain", "Calibration  Voltage", "12345", "BQ76952 reads 0x0E74"}) {
    EXPECT_FALSE(isPageFurniture(line)) << line;
  }
  EXPECT_TRUE(isContinuedCaption("      Table 13-1. Data Memory Table (continued)"));
  EXPECT_FALSE(isContinuedCaption("Table 13-1. Data Memory Table"));
}

TEST(Cells, TiSpellings) {
  EXPECT_EQ(cells::number("\xE2\x80\x93"
                          "32767"),
            "-32767");
  EXPECT_EQ(cells::number("1.00E\xE2\x80\x93"
                          "01"),
            "1.00E-01");
  EXPECT_EQ(cells::number("\xE2\x80\x94"), "");
  EXPECT_EQ(cells::number("HW Reset Default = 0x00 Factory Configuration Default = 0x01"), "0x01");
  const auto unit = [](const char* s) {
    const cells::Unit u = cells::unit(s);
    return u.understood ? u.unit + (u.scale.empty() ? "" : "*" + u.scale) : "?";
  };
  EXPECT_EQ(unit("50.6 mV"), "mV*50.6");
  EXPECT_EQ(unit("0.1\xC2\xB0"
                 "C"),
            "degC*0.1");
  EXPECT_EQ(unit("190.73 \xC2\xB5V"), "uV*190.73");
  EXPECT_EQ(unit("m\xCE\xA9"), "mOhm");
  EXPECT_EQ(unit("%"), "percent");
  EXPECT_EQ(unit("mAh 10 mWh"), "mAh|10mWh");
  EXPECT_EQ(unit("mA 10 mW"), "mA|10mW");
  EXPECT_EQ(unit("Hex Hex Hex"), "");
  EXPECT_EQ(unit("furlongs"), "?");
  EXPECT_EQ(cells::access("Sealed: R Unsealed: R/W Full Access: R/W"), "rw");
  EXPECT_EQ(cells::access("\xE2\x80\x94 R R"), "r");
  EXPECT_EQ(cells::access("NVM"), "rw");
  EXPECT_EQ(cells::access("Hex"), std::nullopt);
  EXPECT_EQ(cells::name("Voltage()"), "Voltage");
  EXPECT_EQ(cells::fieldsType("U2 U2 U2", true), "B6");
  EXPECT_EQ(cells::fieldsType("U2 U2 U2 U2", false), "4xU2");
  EXPECT_EQ(cells::fieldsType("U4 I4", false), "B8");
  EXPECT_EQ(cells::fieldsType("U2", false), std::nullopt);
  EXPECT_EQ(cells::typeFromWords("Hex", "Block", ""), "B");
  EXPECT_EQ(cells::typeFromWords("Hex", "", "2"), "H2");
  EXPECT_EQ(cells::typeFromWords("Unsigned Int", "Word", ""), "U2");
  EXPECT_EQ(cells::typeFromWords("String", "", "21"), "S21");
  EXPECT_EQ(cells::blockForWideHex("H6"), "B6");
  EXPECT_EQ(cells::blockForWideHex("H2"), std::nullopt);
}

Model modelOf(const std::string& text) {
  return test::checkText(text).model;
}

TEST(Diff, OneLinePerEntryAddedRemovedOrChanged) {
  const std::string head = "family: t\ncommands:\n";
  const auto entry = [](const char* name, const char* addr, const char* extra) {
    return std::string("  - name: ") + name + "\n    addr: " + addr + "\n    type: U2\n    access: r\n" +
           extra + "    description: x\n    source: unverified\n";
  };
  const Model before = modelOf(head + entry("A", "0x10", "    default: 10\n") + entry("B", "0x12", "") +
                               entry("C", "0x14", "    unit: mV\n"));
  const Model after = modelOf(head + entry("A", "0x10", "    default: 0x0A\n") + entry("B2", "0x12", "") +
                              entry("C", "0x14", "    unit: mV\n    scale: 2\n") + entry("D", "0x16", ""));
  const MapDiff d = diffModels(before, after);
  EXPECT_EQ(d.lines,
            (std::vector<std::string>{"~ command 'B' 0x12: name 'B' -> 'B2'",
                                      "~ command 'C' 0x14: unit mV -> 2 mV", "+ command 'D' 0x16 U2"}));
  EXPECT_EQ(d.unchanged, 1);  // default 10 and 0x0A are the same number
  EXPECT_TRUE(d.differs());
  EXPECT_FALSE(diffModels(before, before).differs());
  // Compared with a table holding only subcommands, the commands of the map are not "removed".
  const Model subs = modelOf(
      "family: t\nsubcommands:\n  - name: S\n    addr: 0x0001\n    type: none\n    access: cmd\n"
      "    description: x\n    source: unverified\n");
  EXPECT_EQ(diffModels(before, subs, true).lines, (std::vector<std::string>{"+ subcommand 'S' 0x0001 none"}));
}

}  // namespace
}  // namespace regmapgen
