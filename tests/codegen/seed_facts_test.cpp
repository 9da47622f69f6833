// The generated BQ769x2 table against the tables printed in TI's Chinese app notes (copies in seeds/): every
// command row's address names the entry the row names (after glossary translation), with the row's type and
// unit. The expected values come from the seed text itself, not from our YAML.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "import/import.hpp"
#include "model/names.hpp"
#include "regmap/bq769x2_table.hpp"

namespace {

using namespace fw::regmap;

struct SeedRow {
  int line = 0;
  std::uint32_t address = 0;
  bool subcommand = false;
  std::string name, unit, type;
};

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  const char sep = line.find('|') != std::string::npos ? '|' : '\t';
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, sep);) {
    const auto b = c.find_first_not_of(" \t");
    const auto e = c.find_last_not_of(" \t\r");
    out.push_back(b == std::string::npos ? "" : c.substr(b, e - b + 1));
  }
  return out;
}

// Rows of every table whose heading row starts with 命令 (command) and has 名称 (name).
std::vector<SeedRow> commandRows(const std::string& file) {
  std::ifstream in(std::string(REGMAP_TEST_DIR) + "/seeds/" + file);
  EXPECT_TRUE(in) << file;
  std::vector<SeedRow> rows;
  int nameCol = -1, unitCol = -1, typeCol = -1, number = 0;
  static const std::regex addr("0x([0-9A-Fa-f]{2}|[0-9A-Fa-f]{4})");
  for (std::string line; std::getline(in, line);) {
    ++number;
    const auto c = cells(line);
    if (c.size() < 2) {
      nameCol = -1;
      continue;
    }
    if (c[0] == "命令") {
      nameCol = unitCol = typeCol = -1;
      for (int i = 0; i < static_cast<int>(c.size()); ++i) {
        if (c[i] == "名称") nameCol = i;
        if (c[i] == "单位") unitCol = i;
        if (c[i].rfind("类型", 0) == 0) typeCol = i;
      }
      continue;
    }
    std::smatch m;
    if (nameCol < 0 || !std::regex_match(c[0], m, addr)) continue;
    SeedRow r;
    r.line = number;
    r.address = static_cast<std::uint32_t>(std::stoul(m[1].str(), nullptr, 16));
    r.subcommand = m[1].length() == 4;
    r.name = c[static_cast<std::size_t>(nameCol)];
    if (unitCol >= 0 && unitCol < static_cast<int>(c.size())) r.unit = c[static_cast<std::size_t>(unitCol)];
    if (typeCol >= 0 && typeCol < static_cast<int>(c.size())) r.type = c[static_cast<std::size_t>(typeCol)];
    rows.push_back(r);
  }
  return rows;
}

void expectUnit(const EntryInfo& e, const std::string& unit, int line) {
  if (unit == "mV") {
    EXPECT_EQ(e.unit, Unit::MilliVolt) << "line " << line;
  } else if (unit == "userA") {
    EXPECT_EQ(e.unit, Unit::UserAmp) << "line " << line;
  } else if (unit == "0.1K") {
    EXPECT_EQ(e.unit, Unit::Kelvin) << "line " << line;
    EXPECT_EQ(e.scale, (Ratio{1, 10})) << "line " << line;
  } else if (unit == "十六进制") {  // hex: a flag word, no physical unit
    EXPECT_EQ(e.unit, Unit::None) << "line " << line;
  }
}

// Checks each row; `trustType` says which type cells are clean text (the PDF extraction of seed 000 damaged
// some: "I1" for 16-bit cells, "12" for I2, "l H2").
int checkRows(const std::vector<SeedRow>& rows, bool (*trustType)(const std::string&), bool checkUnits) {
  int checked = 0;
  for (const SeedRow& r : rows) {
    const EntryInfo* e =
        findByAddress(bq769x2::entries, r.subcommand ? Kind::Subcommand : Kind::Command, r.address);
    if (e == nullptr) {
      ADD_FAILURE() << "seed line " << r.line << ": no entry at 0x" << std::hex << r.address;
      continue;
    }
    std::string english = r.name;
    if (!regmapgen::isAscii(r.name) && !regmapgen::translateName(r.name, english)) {
      ADD_FAILURE() << "seed line " << r.line << ": '" << r.name << "' is not in the import glossary";
      continue;
    }
    EXPECT_EQ(regmapgen::lookupKey(e->title), regmapgen::lookupKey(english))
        << "seed line " << r.line << ": " << r.name << " vs " << e->title;
    if (!r.type.empty() && trustType(r.type)) {
      EXPECT_EQ(std::string(e->type), r.type) << "seed line " << r.line;
    }
    if (r.type.empty()) {
      EXPECT_STREQ(e->type, "none") << "seed line " << r.line;  // command-only tables
    }
    if (checkUnits) expectUnit(*e, r.unit, r.line);
    ++checked;
  }
  return checked;
}

TEST(SeedFacts, Seed002CommandAndSubcommandTables) {
  const auto rows = commandRows("seed002_tables.txt");
  EXPECT_EQ(checkRows(
                rows, [](const std::string&) { return true; }, true),
            10);
}

TEST(SeedFacts, Seed002DataMemoryRows) {
  // The data-memory rows carry no address; seed 002's prose gives them: "RAM 地址 0x9261 返回的值为 0x88" and
  // "将 0x037F 写入 0x9304". Type, min, max and default are read from the rows themselves.
  std::ifstream in(std::string(REGMAP_TEST_DIR) + "/seeds/seed002_tables.txt");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  struct Expect {
    std::uint32_t address;
    const char* rowStart;
  };
  for (const Expect& x :
       {Expect{0x9261, "设置 | 保护 | 启用保护功能A |"}, Expect{0x9304, "设置 | 配置 | VCell模式 |"}}) {
    const std::size_t at = text.find(x.rowStart);
    ASSERT_NE(at, std::string::npos) << x.rowStart;
    const auto c = cells(text.substr(at, text.find('\n', at) - at));
    ASSERT_GE(c.size(), 7u);
    const EntryInfo* e = findByAddress(bq769x2::entries, Kind::DataMemory, x.address);
    ASSERT_NE(e, nullptr);
    std::string english;
    ASSERT_TRUE(regmapgen::translateName(c[2], english));
    EXPECT_EQ(regmapgen::lookupKey(e->title), regmapgen::lookupKey(english));
    EXPECT_EQ(std::string(e->type), c[3]);
    ASSERT_TRUE(e->hasMin && e->hasMax && e->hasDefault);
    EXPECT_EQ(e->min, std::stoll(c[4], nullptr, 16));
    EXPECT_EQ(e->max, std::stoll(c[5], nullptr, 16));
    EXPECT_EQ(e->dflt, std::stoll(c[6], nullptr, 16));
  }
}

TEST(SeedFacts, Seed000Tables) {
  const auto table46 = commandRows("seed000_table4-6.txt");
  // Addresses and names of all 19 voltage rows. Not compared: the "I1" type cells are extraction damage (the
  // same rows say "16 位", 16-bit), and the table's "mV" for Stack/PACK/LD contradicts the note's own example
  // (0x0988 read as 24.4 V, i.e. 10 mV userV units); see the deviations log. The 16 cell rows are in mV.
  EXPECT_EQ(checkRows(
                table46, [](const std::string&) { return false; }, false),
            19);
  int cellsInMv = 0;
  for (const SeedRow& r : table46) {
    if (r.address > 0x32) continue;
    expectUnit(*findByAddress(bq769x2::entries, Kind::Command, r.address), r.unit, r.line);
    ++cellsInMv;
  }
  EXPECT_EQ(cellsInMv, 16);
  const auto tables41to45 = commandRows("seed000_tables4-1_to_4-5.txt");
  EXPECT_EQ(checkRows(
                tables41to45, [](const std::string& t) { return t == "H1" || t == "H2"; }, true),
            10);
}

}  // namespace
