#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "emit/emit.hpp"

namespace regmapgen {

std::string displayPath(const std::string& path) {
  const std::size_t last = path.find_last_of("/\\");
  if (last == std::string::npos) return path;
  const std::size_t prev = last == 0 ? std::string::npos : path.find_last_of("/\\", last - 1);
  return prev == std::string::npos ? path : path.substr(prev + 1);
}

std::string familyTitle(const Family& fam) {
  return fam.device && fam.device->title.present ? fam.device->title.value : upperCase(fam.name);
}

std::string cppIntType(int size, bool isSigned) {
  return std::string(isSigned ? "std::int" : "std::uint") + std::to_string(size * 8) + "_t";
}

std::vector<const Field*> fieldsByMsb(const Fieldset& fs) {
  std::vector<const Field*> fields;
  for (const Field& f : fs.fields)
    fields.push_back(&f);
  std::sort(fields.begin(), fields.end(), [](const Field* a, const Field* b) { return a->msb > b->msb; });
  return fields;
}

std::string cppValueType(const Entry& e) {
  if (e.fieldset.present) return "bits::" + e.fieldset.value;
  if (e.enumRef.present) return "enums::" + e.enumRef.value;
  const TypeInfo& t = *e.type;
  switch (t.base) {
    case TypeInfo::Base::None:
      return "::fw::regmap::NoData";
    case TypeInfo::Base::Float:
      return "::fw::regmap::F4";
    case TypeInfo::Base::Bytes:
    case TypeInfo::Base::String:
      if (t.variable) return "::fw::regmap::Block<" + std::to_string(t.count) + ">";
      return "std::array<std::uint8_t, " + std::to_string(t.count) + ">";
    default:
      break;
  }
  const std::string elem = cppIntType(t.elemSize, t.isSigned());
  if (t.array) return "std::array<" + elem + ", " + std::to_string(t.count) + ">";
  return elem;
}

std::uint32_t f4Bits(double value, const std::string& text) {
  // Parse the decimal text straight to the nearest float (no double rounding), then take its bit pattern.
  const float f = text.empty() ? static_cast<float>(value) : std::strtof(text.c_str(), nullptr);
  std::uint32_t bits = 0;
  static_assert(sizeof bits == sizeof f);
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}

std::string unitText(const Entry& e) {
  const std::string unit = e.unit ? std::string(e.unit->symbol) : "";
  if (!e.scale.present || (e.scale.num == 1 && e.scale.den == 1)) return unit;
  return e.scale.text + (unit.empty() ? "" : " " + unit);
}

std::string emitList(const Model& model) {
  std::ostringstream out;
  for (const Family& fam : model.families) {
    for (const Entry& e : fam.entries) {
      out << e.kind->listName << ' ' << hexAddress(*e.addr, e.kind->addrDigits) << ' ' << e.cppName << ' '
          << e.type->code << '\n';
    }
  }
  return out.str();
}

std::vector<const Entry*> blockMembers(const Family& fam, const Block& b) {
  std::vector<const Entry*> out;
  for (const Text& m : b.members) {
    for (const Entry& e : fam.entries) {
      if (e.kind->kind == EntryKind::Command && e.name.value == m.value) out.push_back(&e);
    }
  }
  return out;
}

int blockSize(const Family& fam, const Block& b) {
  const Entry& last = *blockMembers(fam, b).back();
  return static_cast<int>(*last.addr + static_cast<std::uint32_t>(last.size()) -
                          static_cast<std::uint32_t>(b.start.integer));
}

std::string blockRange(std::uint32_t start, int size) {
  if (size == 1) return hexAddress(start, 2);
  return hexAddress(start, 2) + ".." + hexAddress(start + static_cast<std::uint32_t>(size) - 1, 2);
}

}  // namespace regmapgen
