#include <algorithm>
#include <map>
#include <set>
#include <sstream>

#include "emit/emit.hpp"
#include "emit/lines.hpp"
#include "model/names.hpp"

namespace regmapgen {

namespace {

// One line of comment text: newlines folded, nothing that could end a comment early.
std::string oneLine(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  }
  return s;
}

std::string cppString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string provenance(const Sources& src, Loc loc) {
  return displayPath(src.path(loc.file)) + ":" + std::to_string(loc.line);
}

const char* rawType(int width) {
  return width <= 8 ? "std::uint8_t" : width <= 16 ? "std::uint16_t" : "std::uint32_t";
}

// A limit as Spec stores it (integers as they are, F4 as IEEE-754 bits), written as a C++ literal.
std::string limitLiteral(const Entry& e, const Number& n) {
  const bool isFloat = e.type->base == TypeInfo::Base::Float;
  const std::int64_t v = isFloat ? static_cast<std::int64_t>(f4Bits(n.real, n.text)) : n.integer;
  if (v < 0) return std::to_string(v);
  if (e.type->base == TypeInfo::Base::Hex || isFloat || e.fieldset.present) {
    return hexAddress(static_cast<std::uint32_t>(v), isFloat ? 8 : e.type->size() * 2);
  }
  return std::to_string(v);
}

// Underlying type of an enum: that of the entries holding it, else the narrowest that fits its fields.
std::string enumUnderlying(const Family& fam, const Enum& en) {
  for (const Entry& e : fam.entries) {
    if (e.enumRef.present && e.enumRef.value == en.name.value && e.type) {
      return cppIntType(e.type->size(), e.type->isSigned());
    }
  }
  int width = 8;
  for (const Fieldset& fs : fam.fieldsets) {
    for (const Field& f : fs.fields) {
      if (f.enumRef.present && f.enumRef.value == en.name.value) width = std::max(width, f.width());
    }
  }
  return rawType(width);
}

bool fieldsetWritable(const Family& fam, const Fieldset& fs) {
  for (const Entry& e : fam.entries) {
    if (e.fieldset.present && e.fieldset.value == fs.name.value && e.access && e.access->writable)
      return true;
  }
  return false;
}

std::string accessWord(const Entry& e) {
  switch (e.access->code) {
    case AccessCode::R:
      return "read-only";
    case AccessCode::W:
      return "write-only";
    case AccessCode::RW:
      return "read-write";
    case AccessCode::RW1C:
      return "read, write 1 to clear";
    case AccessCode::Cmd:
      return "command-only";
    case AccessCode::ConfigUpdate:
      return "read, write in CONFIG_UPDATE";
  }
  return "?";
}

class CodeEmitter {
 public:
  CodeEmitter(const Family& fam, const Sources& src) : fam_(fam), src_(src) {}

  std::string header() {
    std::ostringstream o;
    generatedNotice(o);
    writeComment(o, familyTitle(fam_) +
                        ": typed register-map descriptors (namespace fw::regmap::" + fam_.name +
                        "). Contract and helpers (decode, encode, Readable, Writable, ...): "
                        "regmap/descriptor.hpp. Tables with every fact and its source: regmaps/" +
                        fam_.name +
                        "/REFERENCE.md. Each descriptor comment gives: address, TRM name, type, "
                        "unit, access, meaning, [source] and the YAML line.");
    o << "#pragma once\n\n#include <array>\n#include <cstdint>\n\n#include \"regmap/descriptor.hpp\"\n\n"
      << "namespace fw::regmap::" << fam_.name << " {\n\n"
      << "// Tag type: keeps this family's descriptor types distinct from every other family's.\n"
      << "struct Family {};\n\n"
      << "// A descriptor of this family: the facts S of one entry and the type T its value decodes to.\n"
      << "template <::fw::regmap::Spec S, class T>\n"
      << "using Descriptor = ::fw::regmap::Descriptor<Family, S, T>;\n";
    enums(o);
    bits(o);
    for (const KindInfo& k : kinds())
      descriptors(o, k);
    blocks(o);
    o << "\n}  // namespace fw::regmap::" << fam_.name << "\n";
    return o.str();
  }

  std::string table() {
    std::ostringstream o;
    generatedNotice(o);
    writeComment(o, familyTitle(fam_) +
                        ": runtime table of every entry (names, units, limits) for host "
                        "tools and emulators. Contract and lookup helpers: regmap/table.hpp. Firmware that "
                        "only needs descriptors should include regmap/" +
                        fam_.name + ".hpp instead, which carries no strings.");
    o << "#pragma once\n\n#include <array>\n#include <span>\n\n#include \"regmap/table.hpp\"\n\n"
      << "namespace fw::regmap::" << fam_.name << " {\n\nnamespace field_info {\n";
    for (const Fieldset& fs : fam_.fieldsets) {
      // Lowest bits first: the checked fields do not overlap, so this is the msb order reversed.
      std::vector<const Field*> fields = fieldsByMsb(fs);
      std::reverse(fields.begin(), fields.end());
      o << "inline constexpr std::array<::fw::regmap::FieldInfo, " << fields.size() << "> " << fs.name.value
        << "{{\n";
      for (const Field* f : fields) {
        writeBraced(o, 4, "    ",
                    {".name = " + cppString(f->cppName), ".title = " + cppString(f->name.value),
                     ".lsb = " + std::to_string(f->lsb), ".width = " + std::to_string(f->width())},
                    ",");
      }
      o << "}};\n";
    }
    o << "}  // namespace field_info\n\n"
      << "inline constexpr std::array<::fw::regmap::EntryInfo, " << fam_.entries.size() << "> kEntries{{\n";
    for (const Entry* ep : ordered())
      writeBraced(o, 4, "    ", entryInfoMembers(*ep), ",");
    o << "}};\n\ninline constexpr std::span<const ::fw::regmap::EntryInfo> entries{kEntries};\n\n"
      << "}  // namespace fw::regmap::" << fam_.name << "\n";
    return o.str();
  }

  std::string selftest() {
    std::ostringstream o;
    generatedNotice(o);
    writeComment(o, "Compile-time self-test of regmap/" + fam_.name + ".hpp and regmap/" + fam_.name +
                        "_table.hpp, compiled on every target: the descriptors carry the YAML's facts, the "
                        "runtime table mirrors the descriptors, defaults lie within min..max, codecs "
                        "round-trip, bit-field masks are disjoint, and the unit list agrees with "
                        "regmap/descriptor.hpp.");
    o << "#include <cstdint>\n#include <string_view>\n\n"
      << "#include \"regmap/" << fam_.name << ".hpp\"\n#include \"regmap/" << fam_.name << "_table.hpp\"\n\n"
      << "namespace fw::regmap::" << fam_.name << " {\nnamespace {\n\n"
      << "// The runtime table row repeats the descriptor's facts.\n"
      << "template <class D>\n"
      << "constexpr bool mirrors(const EntryInfo& row, D d) {\n"
      << "  return row.address == d.address && row.size == d.size && row.access == d.access && "
         "row.kind == d.kind;\n}\n\n"
      << "// The default lies within min..max.\n"
      << "template <class D>\n"
      << "constexpr bool defaultInRange(D d) {\n  return inRange(d, d.defaultValue());\n}\n\n"
      << "// The default survives encode then decode.\n"
      << "template <class D>\n"
      << "constexpr bool roundTrips(D d) {\n"
      << "  return decode(d, encode(d, d.defaultValue())) == d.defaultValue();\n}\n\n";
    o << "// The generator's unit spellings are the runtime header's.\n";
    for (const UnitInfo& u : units()) {
      o << "static_assert(std::string_view{unitSymbol(Unit::" << u.cpp
        << ")} == " << cppString(std::string(u.symbol)) << ");\n";
    }
    o << "\n// Bit-field masks are disjoint and within the register width.\n";
    for (const Fieldset& fs : fam_.fieldsets) {
      if (fs.fields.empty()) continue;
      const std::string t = "bits::" + fs.name.value;
      // Each field against the union of the fields before it (the generator's own sum).
      std::uint64_t before = 0;
      for (const Field& f : fs.fields) {
        o << "static_assert((" << t << "::" << f.cppName << "_mask & " << hexAddress(before, fs.width / 4)
          << ") == 0);\n";
        before |= f.mask();
      }
      o << "static_assert(sizeof(" << t << "::raw_type) * 8 == " << fs.width << ");\n";
    }
    if (!fam_.blocks.empty()) {
      o << "\n// Every block member's offset is its descriptor's address less the block's.\n";
      for (const Block& b : fam_.blocks) {
        o << "struct " << b.name.value << "Offsets {\n  using B = blocks::" << b.name.value << ";\n";
        for (const Entry* e : blockMembers(fam_, b)) {
          o << "  static_assert(B::offset" << e->cppName << " == cmd::" << e->cppName
            << ".address - B::address);\n";
        }
        o << "};\n";
      }
    }
    o << "\n// Every descriptor: address, size, access and limits as in the YAML; the table mirrors it.\n";
    std::size_t index = 0;
    for (const Entry* ep : ordered()) {
      const Entry& e = *ep;
      const std::string d = std::string(e.kind->ns) + "::" + e.cppName;
      const std::string dt = "decltype(" + d + ")";
      const std::string row = "kEntries[" + std::to_string(index) + "]";
      o << "// " << provenance(src_, e.loc) << "\n"
        << "static_assert(" << d << ".address == " << hexAddress(*e.addr, e.kind->addrDigits) << ");\n"
        << "static_assert(" << d << ".size == " << e.size() << ");\n"
        << "static_assert(" << d << ".kind == Kind::" << e.kind->cppKind << ");\n"
        << "static_assert(" << d << ".access == Access::" << e.access->cpp << ");\n"
        << "static_assert(" << (e.access->readable ? "" : "!") << "Readable<" << dt << ">);\n"
        << "static_assert(" << (e.access->writable ? "" : "!") << "Writable<" << dt << ">);\n"
        << "static_assert(mirrors(" << row << ", " << d << "));\n"
        << "static_assert(findByName(entries, \"" << d << "\") == &" << row << ");\n";
      const bool integral = e.type->integer() && !e.fieldset.present && !e.enumRef.present;
      if (e.dflt.present && (e.min.present || e.max.present) && integral) {
        o << "static_assert(defaultInRange(" << d << "));\n";
      }
      if (e.dflt.present && e.access->readable && e.access->writable && e.type->scalar()) {
        o << "static_assert(roundTrips(" << d << "));\n";
      }
      ++index;
    }
    o << "\n}  // namespace\n}  // namespace fw::regmap::" << fam_.name << "\n";
    return o.str();
  }

 private:
  // A one-statement member function at indent 2: on one line when it fits, else the body on its own line,
  // and a body too long for that split after `open` (a `Name{` or call) with `rest` indented by 8.
  static void writeFunction(std::ostringstream& o, const std::string& signature, const std::string& open,
                            const std::string& rest = "") {
    const std::string body = open + rest;
    if (2 + signature.size() + 3 + body.size() + 2 <= kColumnLimit) {
      o << "  " << signature << " { " << body << " }\n";
    } else if (4 + body.size() <= kColumnLimit || rest.empty()) {
      o << "  " << signature << " {\n    " << body << "\n  }\n";
    } else {
      o << "  " << signature << " {\n    " << open << "\n        " << rest << "\n  }\n";
    }
  }

  // The body of with_<field>() after `return Name{`: the shared helper of regmap/descriptor.hpp.
  static std::string withField(const std::string& id, int lsb, const std::string& value) {
    return "withField(bits, " + id + "_mask, " + std::to_string(lsb) + ", static_cast<raw_type>(" + value +
           "))};";
  }

  void generatedNotice(std::ostringstream& o) const {
    o << "// GENERATED by regmapgen from regmaps/" << fam_.name
      << "/*.yaml. Do not edit: change the YAML and rebuild.\n//\n";
  }

  // The runtime table's row of one entry. Every member is spelled out: the table is an aggregate without
  // defaults.
  static std::vector<std::string> entryInfoMembers(const Entry& e) {
    const TypeInfo& t = *e.type;
    auto flag = [](bool b) { return std::string(b ? "true" : "false"); };
    auto limit = [&e](const Number& n) { return n.present ? limitLiteral(e, n) : std::string("0"); };
    return {".kind = ::fw::regmap::Kind::" + std::string(e.kind->cppKind),
            ".address = " + hexAddress(*e.addr, e.kind->addrDigits),
            ".span = " + std::to_string(e.span),
            ".size = " + std::to_string(t.size()),
            ".variable = " + flag(t.variable),
            ".scalar = " + flag(t.scalar()),
            ".isSigned = " + flag(t.isSigned()),
            ".isFloat = " + flag(t.base == TypeInfo::Base::Float),
            ".order = ::fw::regmap::ByteOrder::" + std::string(e.kind->bigEndian ? "Big" : "Little"),
            ".access = ::fw::regmap::Access::" + std::string(e.access->cpp),
            ".name = " + cppString(e.cppName),
            ".title = " + cppString(e.name.value),
            ".type = " + cppString(t.code),
            ".unit = ::fw::regmap::Unit::" + std::string(e.unit ? e.unit->cpp : "None"),
            ".scale = {" + std::to_string(e.scale.num) + ", " + std::to_string(e.scale.den) + "}",
            ".hasMin = " + flag(e.min.present),
            ".hasMax = " + flag(e.max.present),
            ".hasDefault = " + flag(e.dflt.present),
            ".min = " + limit(e.min),
            ".max = " + limit(e.max),
            ".dflt = " + limit(e.dflt),
            ".fields = " + (e.fieldset.present ? "field_info::" + e.fieldset.value : std::string("{}"))};
  }

  // Entries grouped by kind (in kinds() order), file order within a kind: the table order.
  std::vector<const Entry*> ordered() const {
    std::vector<const Entry*> out;
    for (const KindInfo& k : kinds()) {
      for (const Entry& e : fam_.entries) {
        if (e.kind->kind == k.kind) out.push_back(&e);
      }
    }
    return out;
  }

  void enums(std::ostringstream& o) {
    if (fam_.enums.empty()) return;
    o << "\n// Coded values. Entries and fields that hold them decode to these types.\nnamespace enums {\n";
    for (const Enum& en : fam_.enums) {
      o << "\n";
      writeComment(o, oneLine(en.description.value) +
                          (en.source.present ? " [" + en.source.value + "]" : std::string()) + " (" +
                          provenance(src_, en.loc) + ")");
      o << "enum class " << en.name.value << " : " << enumUnderlying(fam_, en) << " {\n";
      std::vector<std::pair<std::string, std::string>> lines;
      for (const EnumValue& v : en.values) {
        lines.emplace_back("  " + v.name.value + " = " + std::to_string(*v.value) + ",",
                           v.description.present ? oneLine(v.description.value) : "");
      }
      writeCommented(o, lines);
      o << "};\n";
    }
    o << "\n}  // namespace enums\n";
  }

  void bits(std::ostringstream& o) {
    if (fam_.fieldsets.empty()) return;
    o << "\n// Bit-field value types: the raw register value with one accessor per named field (snake_case "
         "TRM name),\n"
         "// `<field>_mask` constants, and `with_<field>(v)` returning a modified copy where the register is "
         "writable.\nnamespace bits {\n";
    for (const Fieldset& fs : fam_.fieldsets) {
      const std::string name = fs.name.value;
      const char* raw = rawType(fs.width);
      const bool writable = fieldsetWritable(fam_, fs);
      o << "\n";
      writeComment(
          o, oneLine(fs.description.value) + " [" + fs.source.value + "] (" + provenance(src_, fs.loc) + ")");
      o << "struct " << name << " {\n  using raw_type = " << raw
        << ";\n  raw_type bits = 0;  // the raw value\n\n"
        << "  static constexpr " << name << " fromRaw(raw_type r) { return " << name << "{r}; }\n"
        << "  constexpr raw_type raw() const { return bits; }\n"
        << "  friend constexpr bool operator==(const " << name << "&, const " << name << "&) = default;\n";
      std::uint64_t all = 0;
      for (const Field* f : fieldsByMsb(fs)) {
        const std::uint64_t mask = f->mask();
        all |= mask;
        const std::string id = f->cppName;
        std::string about =
            std::string(f->msb == f->lsb ? "bit " : "bits ") + f->bitsText() + " " + f->name.value;
        if (f->description.present) about += ": " + oneLine(f->description.value);
        if (f->source.present) about += " [" + f->source.value + "]";
        o << "\n";
        writeComment(o, about, 2);
        o << "  static constexpr raw_type " << id << "_mask = " << hexAddress(mask, fs.width / 4) << ";\n";
        if (f->width() == 1 && !f->enumRef.present) {
          writeFunction(o, "constexpr bool " + id + "() const", "return (bits & " + id + "_mask) != 0;");
          if (writable) {
            writeFunction(o, "constexpr " + name + " with_" + id + "(bool on) const", "return " + name + "{",
                          withField(id, f->lsb, "on"));
          }
        } else {
          const std::string vt = f->enumRef.present ? "enums::" + f->enumRef.value : rawType(f->width());
          writeFunction(
              o, "constexpr " + vt + " " + id + "() const",
              "return static_cast<" + vt + ">((bits & " + id + "_mask) >> " + std::to_string(f->lsb) + ");");
          if (writable) {
            writeFunction(o, "constexpr " + name + " with_" + id + "(" + vt + " v) const",
                          "return " + name + "{", withField(id, f->lsb, "v"));
          }
        }
      }
      o << "\n  // Every named field; other bits are reserved.\n  static constexpr raw_type fields_mask = "
        << hexAddress(all, fs.width / 4) << ";\n};\n";
    }
    // Each entry's own name as an alias of its layout (bits::SafetyStatusA = bits::SafetyA), where
    // unambiguous.
    std::map<std::string, std::set<std::string>> aliases;
    std::set<std::string> fieldsetNames;
    for (const Fieldset& fs : fam_.fieldsets)
      fieldsetNames.insert(fs.name.value);
    for (const Entry& e : fam_.entries) {
      if (e.fieldset.present) aliases[e.cppName].insert(e.fieldset.value);
    }
    std::ostringstream a;
    for (const auto& [alias, targets] : aliases) {
      if (targets.size() != 1 || fieldsetNames.count(alias)) continue;
      a << "using " << alias << " = " << *targets.begin() << ";\n";
    }
    if (!a.str().empty()) o << "\n// Entry names of the layouts above.\n" << a.str();
    o << "\n}  // namespace bits\n";
  }

  void descriptors(std::ostringstream& o, const KindInfo& k) {
    bool any = false;
    for (const Entry& e : fam_.entries) {
      if (e.kind->kind != k.kind) continue;
      if (!any) {
        o << "\n// " << k.title << ".\nnamespace " << k.ns << " {\n";
        any = true;
      }
      const std::string unit = unitText(e);
      std::string about = hexAddress(*e.addr, k.addrDigits);
      if (e.span > 1) about += ".." + hexAddress(*e.addr + e.span - 1, k.addrDigits);
      about += " " + e.name.value;
      if (e.category.present || e.subcategory.present)
        about += " (" + e.category.value + ":" + e.subcategory.value + ")";
      about += ": " + e.type->code + (unit.empty() ? "" : ", " + unit) + ", " + accessWord(e) + ". " +
               oneLine(e.description.value) + " [" + e.source.value + "] (" + provenance(src_, e.loc) + ")";
      o << "\n";
      writeComment(o, about);
      std::vector<std::string> spec{".kind = ::fw::regmap::Kind::" + std::string(k.cppKind),
                                    ".address = " + hexAddress(*e.addr, k.addrDigits),
                                    ".size = " + std::to_string(e.size())};
      if (e.type->variable) spec.push_back(".variable = true");
      if (k.bigEndian) spec.push_back(".order = ::fw::regmap::ByteOrder::Big");
      spec.push_back(".access = ::fw::regmap::Access::" + std::string(e.access->cpp));
      if (e.unit) spec.push_back(".unit = ::fw::regmap::Unit::" + std::string(e.unit->cpp));
      if (e.scale.num != 1 || e.scale.den != 1)
        spec.push_back(".scale = {" + std::to_string(e.scale.num) + ", " + std::to_string(e.scale.den) + "}");
      if (e.min.present) spec.push_back(".hasMin = true");
      if (e.max.present) spec.push_back(".hasMax = true");
      if (e.dflt.present) spec.push_back(".hasDefault = true");
      if (e.min.present) spec.push_back(".min = " + limitLiteral(e, e.min));
      if (e.max.present) spec.push_back(".max = " + limitLiteral(e, e.max));
      if (e.dflt.present) spec.push_back(".dflt = " + limitLiteral(e, e.dflt));
      writeBraced(o, 0, "inline constexpr ::fw::regmap::Spec " + e.cppName + "Spec", spec, ";");
      writeDeclaration(o, "inline constexpr Descriptor<" + e.cppName + "Spec, " + cppValueType(e) + ">",
                       e.cppName);
    }
    if (any) o << "\n}  // namespace " << k.ns << "\n";
  }

  void blocks(std::ostringstream& o) {
    if (fam_.blocks.empty()) return;
    o << "\n// Blocks: consecutive direct commands read in one transaction. `record` is the block's first "
         "byte in "
         "the\n// record of every block in the order below; `offset<Member>` a member's first byte in the "
         "block.\nnamespace blocks {\n";
    int record = 0;
    int largest = 0;
    for (const Block& b : fam_.blocks) {
      const std::uint32_t start = static_cast<std::uint32_t>(b.start.integer);
      const int size = blockSize(fam_, b);
      o << "\n";
      const std::string bytes = std::to_string(size) + (size == 1 ? " byte" : " bytes");
      writeComment(o, blockRange(start, size) + " (" + bytes + "): " + oneLine(b.description.value) + " (" +
                          provenance(src_, b.loc) + ")");
      o << "struct " << b.name.value << " {\n"
        << "  static constexpr std::uint8_t address = " << hexAddress(start, 2) << ";\n"
        << "  static constexpr std::uint8_t size = " << size << ";\n"
        << "  static constexpr std::uint8_t record = " << record << ";\n";
      for (const Entry* e : blockMembers(fam_, b)) {
        o << "  static constexpr std::uint8_t offset" << e->cppName << " = " << (*e->addr - start) << ";\n";
      }
      o << "};\n";
      record += size;
      largest = std::max(largest, size);
    }
    o << "\n// Bytes of all blocks together (the record) and of the largest (the longest read).\n"
      << "inline constexpr std::uint16_t kRecordSize = " << record << ";\n"
      << "inline constexpr std::uint8_t kLargestSize = " << largest << ";\n"
      << "\n}  // namespace blocks\n";
  }

  const Family& fam_;
  const Sources& src_;
};

}  // namespace

std::vector<OutputFile> emitCode(const Family& fam, const Sources& src) {
  CodeEmitter c(fam, src);
  return {{"regmap/" + fam.name + ".hpp", c.header()},
          {"regmap/" + fam.name + "_table.hpp", c.table()},
          {"regmap/" + fam.name + "_selftest.cpp", c.selftest()}};
}

}  // namespace regmapgen
