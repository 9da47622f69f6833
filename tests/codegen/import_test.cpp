// `regmapgen import`: glossary translation, table detection, repairs, and output that `check` accepts.
#include <gtest/gtest.h>

#include <sstream>

#include "import/import.hpp"
#include "test_support.hpp"

namespace regmapgen {
namespace {

struct Imported {
  int rc = 0;
  std::string yaml;
  std::string warnings;
};

Imported runOn(const std::string& text, ImportOptions opts = {}) {
  std::ostringstream out, err;
  Imported r;
  r.rc = runImport("in.txt", text, opts, out, err);
  r.yaml = out.str();
  r.warnings = err.str();
  return r;
}

TEST(Glossary, TranslatesTiTermsAndKeepsAsciiWords) {
  std::string out;
  ASSERT_TRUE(translateName("警报启用", out));
  EXPECT_EQ(out, "Alarm Enable");
  ASSERT_TRUE(translateName("Cell 1 电压", out));
  EXPECT_EQ(out, "Cell 1 Voltage");
  ASSERT_TRUE(translateName("VCell模式", out));
  EXPECT_EQ(out, "VCell Mode");
  ASSERT_TRUE(translateName("启用保护功能A", out));
  EXPECT_EQ(out, "Enabled Protections A");
  ASSERT_TRUE(translateName("内部温度", out));
  EXPECT_EQ(out, "Int Temperature");  // the TRM's abbreviation, not "Internal Temperature"
  ASSERT_TRUE(translateName("CC2电流", out));
  EXPECT_EQ(out, "CC2 Current");
  EXPECT_FALSE(translateName("未知寄存器", out));  // not in the glossary: never guessed
}

TEST(Import, PipeTableBecomesCheckedYaml) {
  const auto r = runOn(
      "prose without separators is ignored\n"
      "命令 | 名称 | 单位 | 类型 | 说明 |\n"
      "---|---|---|---|---|\n"
      "0x14 | Cell 1 电压 | mV | I2 | 电池 1 上的 16 位电压 |\n"
      "0x68 | 内部温度 | 0.1K | I2 | 温度 |\n");
  ASSERT_EQ(r.rc, 0) << r.warnings;
  EXPECT_NE(
      r.yaml.find("  - name: Cell 1 Voltage\n    addr: 0x14\n    type: I2\n    access: r\n    unit: mV\n"),
      std::string::npos)
      << r.yaml;
  EXPECT_NE(r.yaml.find("    unit: K\n    scale: 0.1\n"), std::string::npos) << r.yaml;
  const auto c = test::checkText(r.yaml);
  EXPECT_EQ(c.errors, 0u) << c.text;
}

TEST(Import, TabTableWithOcrDamage) {
  const auto r = runOn(
      "命令\t名称\t单位\t类型 类型\t说明\n"
      "0x62\tAlarm Status\t十六进制\tl H2\t锁存\n"
      "0x70\tTS1 Temperature\t0.1K\t12\t温度\n"
      "0x14\tCell 1 电压\tmV\tI1\t电池 1 上的 16 位电压\n");
  ASSERT_EQ(r.rc, 0);
  EXPECT_NE(r.warnings.find("in.txt:2:24: warning: type 'l H2' read as H2"), std::string::npos) << r.warnings;
  EXPECT_NE(r.warnings.find("type '12' read as I2"), std::string::npos) << r.warnings;
  EXPECT_NE(r.warnings.find("type I1 has 8 bits but the description says 16 位; using I2"), std::string::npos)
      << r.warnings;
  EXPECT_EQ(test::checkText(r.yaml).errors, 0u) << r.yaml;
}

TEST(Import, SubcommandsAndCommandOnlyRows) {
  const auto r = runOn(
      "命令 | 名称 | 说明 |\n---|---|---|\n0x0022 | FET_ENABLE | 切换 |\n"
      "命令 | 名称 | 数据 | 单位 | 类型 | 说明 |\n---|---|---|---|---|---|\n0x0001 | DEVICE_NUMBER | "
      "器件型号 | 十六进制 | U2 | 型号 |\n");
  ASSERT_EQ(r.rc, 0);
  EXPECT_NE(r.yaml.find("subcommands:\n"), std::string::npos);
  EXPECT_NE(r.yaml.find("  - name: FET_ENABLE\n    addr: 0x0022\n    type: none\n    access: cmd\n"),
            std::string::npos)
      << r.yaml;
  EXPECT_NE(r.yaml.find("description: \"Data: 器件型号. 型号\""), std::string::npos) << r.yaml;
  EXPECT_EQ(test::checkText(r.yaml).errors, 0u) << r.yaml;
}

TEST(Import, UntranslatableNamesAreKeptAndCheckRejectsThem) {
  const auto r = runOn("命令 | 名称 | 类型 |\n---|---|---|\n0x20 | 未知寄存器 | U1 |\n");
  ASSERT_EQ(r.rc, 0);
  EXPECT_NE(r.warnings.find("cannot translate name '未知寄存器'"), std::string::npos) << r.warnings;
  EXPECT_NE(r.yaml.find("name: \"未知寄存器\""), std::string::npos) << r.yaml;
  const auto c = test::checkText(r.yaml);
  EXPECT_GE(c.errors, 1u);
  EXPECT_NE(c.text.find("the name is not ASCII; give the English TRM name"), std::string::npos) << c.text;
}

TEST(Import, DataMemoryWithoutAddressIsTodo) {
  const auto r = runOn(
      "类别 | 子类别 | 名称 | 类型 | 最小值 | 最大值 | 默认值 | 单位 |\n---|---|---|---|---|---|---|---|\n"
      "设置 | 保护 | 启用保护功能A | U1 | 0x00 | 0xFF | 0x88 | 十六进制 |\n");
  ASSERT_EQ(r.rc, 0);
  EXPECT_NE(r.yaml.find("datamem:\n"), std::string::npos);
  EXPECT_NE(r.yaml.find("    addr: TODO\n"), std::string::npos) << r.yaml;
  EXPECT_NE(r.yaml.find("    category: Settings\n    subcategory: Protection\n"), std::string::npos)
      << r.yaml;
  EXPECT_NE(r.warnings.find("no address for 'Settings:Protection:Enabled Protections A' (pass --map"),
            std::string::npos)
      << r.warnings;
  const auto c = test::checkText(r.yaml);
  EXPECT_NE(c.text.find("'addr' of datamem 'Enabled Protections A': 'TODO' is not an integer"),
            std::string::npos)
      << c.text;
}

TEST(Import, DataMemoryAddressFromTheMap) {
  ImportOptions opts;
  opts.mapFiles = {std::string(REGMAP_MAPS_DIR) + "/bq769x2/data_memory.yaml",
                   std::string(REGMAP_MAPS_DIR) + "/bq769x2/fields.yaml"};
  const auto r = runOn(
      "类别 | 子类别 | 名称 | 类型 | 最小值 | 最大值 | 默认值 | 单位 |\n---|---|---|---|---|---|---|---|\n"
      "设置 | 保护 | 启用保护功能A | U1 | 0x00 | 0xFF | 0x88 | 十六进制 |\n",
      opts);
  ASSERT_EQ(r.rc, 0) << r.warnings;
  EXPECT_NE(r.yaml.find("    addr: 0x9261\n"), std::string::npos) << r.yaml;
  EXPECT_EQ(test::checkText(r.yaml).errors, 0u);
}

TEST(Import, NoTableHasItsOwnStatus) {
  // Not an error of the input: the text has no register table (a data sheet, prose). Status 3, nothing on
  // standard output, a line that says so.
  const auto r = runOn("just prose\nmore prose\n");
  EXPECT_EQ(r.rc, kImportFoundNoTable);
  EXPECT_EQ(r.yaml, "");
  EXPECT_NE(r.warnings.find("in.txt: no register table found; nothing imported"), std::string::npos)
      << r.warnings;
}

}  // namespace
}  // namespace regmapgen
