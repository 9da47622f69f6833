// Identifier derivation and value syntax (type codes, numbers, scales).
#include <gtest/gtest.h>

#include "model/model.hpp"
#include "model/names.hpp"
#include "model/schema.hpp"

namespace regmapgen {
namespace {

TEST(Names, PascalCaseFollowsTheContractExamples) {
  // The identifiers the driver engineers were promised (issue 3).
  EXPECT_EQ(pascalCase("Cell 1 Voltage"), "Cell1Voltage");
  EXPECT_EQ(pascalCase("Enabled Protections A"), "EnabledProtectionsA");
  EXPECT_EQ(pascalCase("FET_ENABLE"), "FetEnable");
  EXPECT_EQ(pascalCase("DEVICE_NUMBER"), "DeviceNumber");
  EXPECT_EQ(pascalCase("VCell Mode"), "VCellMode");
  EXPECT_EQ(pascalCase("CONTROL1"), "Control1");
  EXPECT_EQ(pascalCase("VCELL16_HI"), "Vcell16Hi");
  EXPECT_EQ(pascalCase("Voltage"), "Voltage");
  EXPECT_EQ(pascalCase("ManufacturerBlockAccess"), "ManufacturerBlockAccess");
  EXPECT_EQ(pascalCase("DeviceType"), "DeviceType");
  EXPECT_EQ(pascalCase("Cell Balance Min Cell V (Charge)"), "CellBalanceMinCellVCharge");
}

TEST(Names, SnakeCaseForFieldAccessors) {
  EXPECT_EQ(snakeCase("CUV"), "cuv");
  EXPECT_EQ(snakeCase("MSK_SFALERT"), "msk_sfalert");
  EXPECT_EQ(snakeCase("SEC[1:0]"), "sec");
  EXPECT_EQ(snakeCase("USER_AMPS[1:0]"), "user_amps");
  EXPECT_EQ(snakeCase("OTCB_THR_LOCK?"), "otcb_thr_lock");
  EXPECT_EQ(snakeCase("2LVL"), "2lvl");  // not an identifier: the YAML must give an id
  EXPECT_FALSE(isIdentifier(snakeCase("2LVL")));
}

TEST(Names, KeywordsAndLookupKeys) {
  EXPECT_TRUE(isCppKeyword("try"));
  EXPECT_TRUE(isCppKeyword("and"));
  EXPECT_FALSE(isCppKeyword("cuv"));
  EXPECT_EQ(lookupKey("Cell 1_Voltage-x"), "cell1voltagex");
}

TEST(TypeCodes, ScalarsArraysBlocksAndNone) {
  auto i2 = parseType("I2");
  ASSERT_TRUE(i2);
  EXPECT_EQ(i2->size(), 2);
  EXPECT_TRUE(i2->isSigned());
  EXPECT_EQ(i2->minValue(), -32768);
  EXPECT_EQ(i2->maxValue(), 32767);
  EXPECT_EQ(parseType("H4")->maxValue(), 0xFFFFFFFFLL);
  auto arr = parseType("16xI2");
  ASSERT_TRUE(arr);
  EXPECT_EQ(arr->size(), 32);
  EXPECT_TRUE(arr->array);
  EXPECT_EQ(parseType("B6")->size(), 6);
  EXPECT_TRUE(parseType("B")->variable);
  EXPECT_EQ(parseType("S21")->size(), 21);
  EXPECT_EQ(parseType("none")->size(), 0);
  for (const char* bad : {"I3", "U8", "F2", "X1", "B0", "B33", "17xI2", "4xF4", "i2", ""}) {
    EXPECT_FALSE(parseType(bad)) << bad;
  }
}

TEST(Numbers, IntegersRealsAndScales) {
  EXPECT_EQ(parseNumber("0x88")->integer, 0x88);
  EXPECT_EQ(parseNumber("-32768")->integer, -32768);
  EXPECT_EQ(parseNumber("0b101")->integer, 5);
  EXPECT_FALSE(parseNumber("0x1G"));
  EXPECT_FALSE(parseNumber("99999999999999999999"));
  auto real = parseNumber("4.193046E+08");
  ASSERT_TRUE(real);
  EXPECT_FALSE(real->isInteger);
  EXPECT_DOUBLE_EQ(real->real, 4.193046e8);
  auto s = parseScale("190.73");
  ASSERT_TRUE(s);
  EXPECT_EQ(s->num, 19073);
  EXPECT_EQ(s->den, 100);
  auto tenth = parseScale("0.1");
  EXPECT_EQ(tenth->num, 1);
  EXPECT_EQ(tenth->den, 10);
  auto fifty = parseScale("50.6");
  EXPECT_EQ(fifty->num, 253);
  EXPECT_EQ(fifty->den, 5);
  EXPECT_EQ(parseScale("1/3")->den, 3);
  EXPECT_FALSE(parseScale("0"));
  EXPECT_FALSE(parseScale("-1"));
}

TEST(Schema, EveryObjectKeyIsDocumented) {
  for (const ObjectSpec& o : objects()) {
    for (const KeySpec& k : o.keys)
      EXPECT_FALSE(k.doc.empty()) << o.name << "." << k.key;
  }
  const std::string md = schemaMarkdown();
  EXPECT_NE(md.find("| `addr` | yes | integer |"), std::string::npos);
  EXPECT_NE(md.find("`config_update`"), std::string::npos);
}

}  // namespace
}  // namespace regmapgen
