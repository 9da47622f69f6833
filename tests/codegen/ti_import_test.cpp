// `regmapgen import` of TI's own pages: tests/codegen/ti/*.txt are `pdftotext -layout` excerpts of SLUUBY2B
// (BQ76952 TRM, rev. B), SLUUAQ3A (BQ4050 TRM, rev. A), SLUAAM4 (BQ7690x software guide) and SLUSE13B
// (BQ76952 data sheet, rev. B). Each table kind is imported and its row count and a sample of its values
// compared with the PDF page (the page is named beside each value).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "diag/diag.hpp"
#include "import/import.hpp"
#include "model/model.hpp"

namespace regmapgen {
namespace {

std::string fixture(const std::string& name) {
  std::ifstream in(std::string(REGMAP_TEST_DIR) + "/ti/" + name, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  EXPECT_FALSE(s.str().empty()) << name;
  return s.str();
}

// An import and the model its YAML builds into.
struct Import {
  int rc = -1;
  std::string yaml, err;
  Sources sources;
  Model model;
  std::size_t yamlErrors = 0;

  std::size_t count(std::string_view kind) const {
    std::size_t n = 0;
    for (const Family& f : model.families) {
      for (const Entry& e : f.entries)
        n += e.kind->yamlKey == kind ? 1 : 0;
    }
    return n;
  }
  const Entry* at(std::string_view kind, std::uint32_t addr) const {
    for (const Family& f : model.families) {
      for (const Entry& e : f.entries) {
        if (e.kind->yamlKey == kind && e.addr == addr) return &e;
      }
    }
    return nullptr;
  }
  const Fieldset* fieldset(const std::string& name) const {
    for (const Family& f : model.families) {
      if (const Fieldset* fs = f.findFieldset(name)) return fs;
    }
    return nullptr;
  }
};

Import importText(const std::string& family, const std::string& text, const std::string& path = "in.txt") {
  Import r;
  ImportOptions opts;
  opts.family = family;
  std::ostringstream out, err;
  r.rc = runImport(path, text, opts, out, err);
  r.yaml = out.str();
  r.err = err.str();
  r.sources.add("imported.yaml", r.yaml);
  Diagnostics diag(r.sources);
  r.model = build(r.sources, diag);
  r.yamlErrors = diag.errorCount();
  return r;
}

std::string typeOf(const Entry* e) {
  return e && e->type ? e->type->code : "?";
}
std::string unitOf(const Entry* e) {
  if (!e || !e->unit) return "";
  return (e->scale.present ? e->scale.text + " " : "") + std::string(e->unit->symbol);
}
std::string accessOf(const Entry* e) {
  return e && e->access ? std::string(e->access->spelling) : "?";
}

// ---- SLUUBY2B ----

TEST(TiImport, DirectCommandsTableWithItsKeyInTheMiddleOfEachRow) {
  // SLUUBY2B Table 12-1 (pp. 91-93): 50 commands; each row's command, name, units and type sit on the middle
  // line of its block, between "Sealed: .." and "Full Access: ..".
  const Import r = importText("bq769x2", fixture("sluuby2b_p91-117.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.yamlErrors, 0u);
  EXPECT_EQ(r.count("commands"), 50u);
  const Entry* control = r.at("commands", 0x00);  // p91: Control Status, Hex, H2, Sealed/Unsealed/Full: R/W
  ASSERT_TRUE(control);
  EXPECT_EQ(control->name.value, "Control Status");
  EXPECT_EQ(typeOf(control), "H2");
  EXPECT_EQ(accessOf(control), "rw");
  EXPECT_EQ(typeOf(r.at("commands", 0x14)), "I2");  // p92: Cell 1 Voltage, mV, I2
  EXPECT_EQ(unitOf(r.at("commands", 0x14)), "mV");
  EXPECT_EQ(r.at("commands", 0x34)->name.value, "Stack Voltage");  // p92: userV
  EXPECT_EQ(unitOf(r.at("commands", 0x34)), "userV");
  EXPECT_EQ(accessOf(r.at("commands", 0x62)), "rw");            // p93: Alarm Status, R/W
  EXPECT_EQ(unitOf(r.at("commands", 0x68)), "0.1 K");           // p93: Int Temperature, 0.1 K, I2
  EXPECT_EQ(r.at("commands", 0x7F)->name.value, "FET Status");  // p93, the last row
  // The description of a row centred on its key line keeps its lines in order (p93, 0x66).
  EXPECT_EQ(r.at("commands", 0x66)->description.value.rfind("Mask for Alarm Status(). Can be written", 0), 0u)
      << r.at("commands", 0x66)->description.value;
}

TEST(TiImport, SubcommandTablesWithWrappedNamesAndPayloadsOverPages) {
  // SLUUBY2B Tables 12-22 (pp. 106-108, 45 command-only subcommands) and 12-23 (pp. 108-117, 32 with data).
  const Import r = importText("bq769x2", fixture("sluuby2b_p91-117.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.count("subcommands"), 77u);
  EXPECT_EQ(typeOf(r.at("subcommands", 0x0022)), "none");  // p106: FET_ENABLE, command-only
  EXPECT_EQ(accessOf(r.at("subcommands", 0x0022)), "cmd");
  EXPECT_EQ(r.at("subcommands", 0x7C40)->name.value, "SWAP_TO_HDQ");  // p108, the last command-only row
  // p109: names running into the Access column ("PREV_MACWRITE Sealed: R"), or broken where the cell ends
  // ("SAVED_PF_STATU" over "S", "MANUFACTURING" over "STATUS").
  EXPECT_EQ(r.at("subcommands", 0x0007)->name.value, "PREV_MACWRITE");
  EXPECT_EQ(r.at("subcommands", 0x0053)->name.value, "SAVED_PF_STATUS");
  EXPECT_EQ(typeOf(r.at("subcommands", 0x0053)), "5xU1");  // offsets 0..4, after a blank line each
  EXPECT_EQ(r.at("subcommands", 0x0057)->name.value, "MANUFACTURINGSTATUS");
  EXPECT_EQ(typeOf(r.at("subcommands", 0x0035)), "4xU2");  // SECURITY_KEYS, 4 key words
  EXPECT_EQ(accessOf(r.at("subcommands", 0x0035)), "rw");  // Full Access: R/W
  // pp. 110-111: MANU_DATA's offsets 0..20 on one page and 21..31 on the next, one entry.
  EXPECT_EQ(typeOf(r.at("subcommands", 0x0070)), "32xU1");
  EXPECT_EQ(typeOf(r.at("subcommands", 0x0002)), "B6");   // FW_VERSION, three big-endian U2
  EXPECT_EQ(typeOf(r.at("subcommands", 0xF081)), "B12");  // READ_CAL1: I2 I4 I2 I2 I2
}

TEST(TiImport, BitFieldTablesBecomeFieldsetsOfTheirRegisters) {
  // SLUUBY2B Tables 12-2 to 12-21 (pp. 93-105) and 12-24 to 12-27 (pp. 117): Bit | Field | Description.
  const Import r = importText("bq769x2", fixture("sluuby2b_p91-117.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  const Fieldset* alertA = r.fieldset("SafetyAlertA");  // Table 12-3, p94
  ASSERT_TRUE(alertA) << r.yaml.substr(r.yaml.find("fieldsets:"));
  EXPECT_EQ(alertA->width, 8);
  ASSERT_EQ(alertA->fields.size(), 6u);  // SCD OCD2 OCD1 OCC COV CUV; bits 1:0 are RSVD_0
  EXPECT_EQ(alertA->fields.front().name.value, "SCD");
  EXPECT_EQ(alertA->fields.front().msb, 7);
  EXPECT_EQ(alertA->fields.back().name.value, "CUV");
  EXPECT_EQ(alertA->fields.back().msb, 2);
  EXPECT_EQ(r.at("commands", 0x02)->fieldset.value, "SafetyAlertA");
  // Table 12-17 (p100): bits 9-8 "SEC1–SEC0" are one field.
  const Fieldset* battery = r.fieldset("BatteryStatus");
  ASSERT_TRUE(battery);
  EXPECT_EQ(battery->width, 16);
  bool sec = false;
  for (const Field& f : battery->fields)
    sec = sec || (f.name.value == "SEC[1:0]" && f.msb == 9 && f.lsb == 8);
  EXPECT_TRUE(sec);
  // PF Status A..D are described twice (Tables 12-9..12-16 under the direct commands, 12-24..12-27 under
  // SAVED_PF_STATUS): the second tables agree, so there is one fieldset each and no warning at all.
  ASSERT_TRUE(r.fieldset("PfStatusA"));
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

TEST(TiImport, DataMemorySummaryWithWrappedNamesAndNumbers) {
  // SLUUBY2B Table 13-37 (pp. 197-204): 272 settings.
  const Import r = importText("bq769x2", fixture("sluuby2b_p197-204.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.yamlErrors, 0u);
  EXPECT_EQ(r.count("datamem"), 272u);
  const Entry* capacity = r.at("datamem", 0x91AC);  // p198: "4.193046E+" over "08", "2230042.46" over "3"
  ASSERT_TRUE(capacity);
  EXPECT_EQ(typeOf(capacity), "F4");
  EXPECT_EQ(capacity->max.text, "4.193046E+08");
  EXPECT_EQ(capacity->dflt.text, "2230042.463");
  EXPECT_EQ(r.at("datamem", 0x91A8)->max.text, "10.00E+02");  // CC Gain, the row above
  // p198: a name over the address line over its end.
  EXPECT_EQ(r.at("datamem", 0x91C6)->name.value, "Coulomb Counter Offset Samples");
  EXPECT_EQ(r.at("datamem", 0x91B2)->name.value, "Vdiv Offset");
  EXPECT_EQ(r.at("datamem", 0x91E2)->subcategory.value, "Internal Temp Model");
  EXPECT_EQ(r.at("datamem", 0x91EA)->dflt.integer, -15524);  // 18K Temperature Model Coeff a1
  EXPECT_EQ(unitOf(r.at("datamem", 0x922D)), "234 nV");      // p199: Coulomb Counter Deadband, 234nV
  EXPECT_EQ(r.at("datamem", 0x92B2)->dflt.integer, 60);      // p201: Protections:HWD:Delay
  EXPECT_EQ(r.at("datamem", 0x924E)->name.value, "Sleep Charger Voltage Threshold");   // p201
  EXPECT_EQ(r.at("datamem", 0x933B)->name.value, "Cell Balance Min Cell V (Charge)");  // p203
  EXPECT_EQ(r.at("datamem", 0x933B)->subcategory.value, "Cell Balancing Config");
  EXPECT_EQ(unitOf(r.at("datamem", 0x9275)), "50.6 mV");  // Protections:CUV:Threshold
}

TEST(TiImport, SettingTablesTakeTheirAddressFromTheSummaryAndNameWhereTheyDisagree) {
  // SLUUBY2B pp. 127 and 178-179: one table per setting (Class | Subclass | Name | Type | Min | Max | Default
  // | Unit, no address), then the summary (pp. 197-204). Each setting is one entry at the summary's address;
  // the CUV Threshold's own table gives max 80 where the summary gives 90.
  const std::string text =
      fixture("sluuby2b_p127.txt") + fixture("sluuby2b_p178-179.txt") + fixture("sluuby2b_p197-204.txt");
  const Import r = importText("bq769x2", text);
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.count("datamem"), 272u);
  EXPECT_EQ(r.yaml.find("TODO"), std::string::npos);
  EXPECT_NE(r.err.find("22 setting table(s)"), std::string::npos) << r.err;  // 6 + 12 + 4 (p197)
  EXPECT_NE(r.err.find("warning: 'Protections:CUV:Threshold': the table at line"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("gives max 80, Table 13-37"), std::string::npos) << r.err;
  EXPECT_EQ(r.at("datamem", 0x9275)->max.integer, 90);  // the summary's is kept
  // p179: "System" over the line with the type over "Data": one class.
  EXPECT_EQ(r.at("datamem", 0x91E0)->category.value, "System Data");
  EXPECT_EQ(r.err.find("no address"), std::string::npos) << r.err;
}

// ---- SLUUAQ3A ----

TEST(TiImport, Bq4050MacCommandList) {
  // SLUUAQ3A Table 13-1 (pp. 75-77): 47 MAC commands under a heading over three lines.
  const Import r = importText("bq4050", fixture("sluuaq3a_p75-77.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.yamlErrors, 0u);
  EXPECT_EQ(r.count("mac"), 47u);
  EXPECT_EQ(typeOf(r.at("mac", 0x0001)), "B");     // DeviceType: Block, Hex
  EXPECT_EQ(typeOf(r.at("mac", 0x0010)), "none");  // ShutdownMode: Format "—"
  EXPECT_EQ(accessOf(r.at("mac", 0x0010)), "cmd");
  // p75: "PermanentFailureData" over the code's line over "Reset".
  EXPECT_EQ(r.at("mac", 0x0029)->name.value, "PermanentFailureDataReset");
  EXPECT_EQ(r.at("mac", 0x002F)->name.value, "LifetimeDataSpeedUpMode");
  EXPECT_EQ(r.at("mac", 0xF081)->name.value, "OutputCCandADCforCalibration");
}

TEST(TiImport, Bq4050SbsCommandsOneTableEach) {
  // SLUUAQ3A section 13, pp. 99-115: one table per SBS command, headings over three lines ("SBS" / "Cmd",
  // "Proto-" / "col"), 57 commands.
  const Import r = importText("bq4050", fixture("sluuaq3a_p99-115.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.yamlErrors, 0u);
  EXPECT_EQ(r.count("sbs"), 57u);
  const Entry* alarm = r.at("sbs", 0x01);  // p100: "mAh" over the row over "10 mWh"
  ASSERT_TRUE(alarm);
  EXPECT_EQ(alarm->max.integer, 700);
  EXPECT_EQ(alarm->dflt.integer, 300);
  EXPECT_EQ(unitOf(alarm), "mAh|10mWh");
  EXPECT_EQ(r.at("sbs", 0x18)->dflt.integer, 4400);  // p107: DesignCapacity 4400 mAh over 6336 10 mWh
  const Entry* name = r.at("sbs", 0x20);             // p108: ManufacturerName, Block, S20+1, "Texas Inst."
  ASSERT_TRUE(name);
  EXPECT_EQ(typeOf(name), "S21");
  EXPECT_NE(name->notes.value.find("type 'S20+1' (a length byte and 20 characters) written S21"),
            std::string::npos);
  EXPECT_EQ(typeOf(r.at("sbs", 0x22)), "S5");  // DeviceChemistry, S4+1
  EXPECT_EQ(typeOf(r.at("sbs", 0x4A)), "I2");  // p109: BTPDischargeSet, Format "Signed Int", 2 bytes
  // p101: Current() -32767..32768 (TI's range does not fit I2): named, left out.
  EXPECT_NE(r.err.find("warning: max 32768 does not fit type I2 (-32768..32767); left out"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(r.at("sbs", 0x0A)->max.present);
}

TEST(TiImport, Bq4050DataFlashSummary) {
  // SLUUAQ3A Table 14-1 (pp. 185-198): 538 data-flash values.
  const Import r = importText("bq4050", fixture("sluuaq3a_p185-198.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.yamlErrors, 0u);
  EXPECT_EQ(r.count("dataflash"), 538u);
  EXPECT_EQ(r.at("dataflash", 0x4000)->dflt.integer, 12101);                           // p185: Cell Gain
  EXPECT_EQ(typeOf(r.at("dataflash", 0x4006)), "F4");                                  // CC Gain
  EXPECT_EQ(r.at("dataflash", 0x4010)->name.value, "Coulomb Counter Offset Samples");  // wrapped, p185
  EXPECT_EQ(r.at("dataflash", 0x4481)->subcategory.value, "CUV");  // Protections:CUV:Threshold at 0x4481
  EXPECT_EQ(r.at("dataflash", 0x4481)->dflt.integer, 2500);
  // p187: Min Blow Fuse Voltage, I2, 0..65535 (does not fit I2), default 3500: named, the range left out.
  EXPECT_NE(r.err.find("max 65535 does not fit type I2"), std::string::npos) << r.err;
}

// ---- SLUAAM4, SLUSE13B ----

TEST(TiImport, AppNoteTableWithoutAddressTakesTheOneItsOwnSectionWrites) {
  // SLUAAM4 section 3.4 (p9): Table 3-3 gives VCell Mode without an address; the sentence above it writes
  // 0x04 to 0x901B. Section 3.3's "RAM address 0x9024" (Enabled Protections A) is another section's.
  const Import r = importText("bq7690x", fixture("sluaam4_p7-9.txt"));
  ASSERT_EQ(r.rc, 0) << r.err;
  bool found = false;
  for (const Entry& e : r.model.families.front().entries) {
    if (e.name.value != "VCell Mode") continue;
    found = true;
    EXPECT_EQ(e.addr, 0x901Bu);
  }
  EXPECT_TRUE(found) << r.yaml;
}

TEST(TiImport, DataSheetWithoutRegisterTablesFindsNone) {
  // SLUSE13B pp. 4-6 (pin functions) and 41 (temperature calibration settings without addresses or types):
  // no register table. Status 3, nothing on standard output, one line saying so.
  const Import r = importText("bq769x2", fixture("sluse13b_p4-6_41.txt"), "sluse13b.txt");
  EXPECT_EQ(r.rc, kImportFoundNoTable);
  EXPECT_EQ(r.yaml, "");
  EXPECT_EQ(r.err.rfind("sluse13b.txt: no register table found; nothing imported.", 0), 0u) << r.err;
}

// ---- speed ----

// Seconds one import of `text` takes (the best of three), and its summary line.
double secondsToImport(const std::string& text) {
  double best = 1e9;
  for (int run = 0; run < 3; ++run) {
    ImportOptions opts;
    opts.family = "bq769x2";
    std::ostringstream out, err;
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(runImport("in.txt", text, opts, out, err), 0);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

TEST(TiImport, ImportIsLinearInTheText) {
  // Issue 26: the whole TRM's text (3.1 MB) must import in a time proportional to its size. SLUUBY2B's pages
  // 91-117 and 197-204 (0.2 MB), once and four times over (the tables repeat: each copy is one more part of
  // the same tables); the ratio of the best of three runs is compared, not a time (linear: 4, quadratic: 16).
  const std::string once = fixture("sluuby2b_p91-117.txt") + fixture("sluuby2b_p197-204.txt");
  std::string four;
  for (int i = 0; i < 4; ++i)
    four += once;
  const double t1 = secondsToImport(once), t4 = secondsToImport(four);
  const double mb = static_cast<double>(four.size()) / 1e6;
  std::printf(
      "REPORT regmapgen.import_ms_per_mb=%.0f (%.2f MB of SLUUBY2B tables in %.0f ms, %.1fx the time of a "
      "quarter; "
      "measured, host build)\n",
      t4 * 1e3 / mb, mb, t4 * 1e3, t4 / std::max(t1, 1e-6));
  EXPECT_LT(t4 / std::max(t1, 1e-6), 10.0);
}

}  // namespace
}  // namespace regmapgen
