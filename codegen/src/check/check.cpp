#include "check/check.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <set>

#include "model/names.hpp"

namespace regmapgen {

std::string describeEntry(const Entry& e) {
  std::string s = std::string(e.kind->listName) + " '" + (e.name.present ? e.name.value : "?") + "'";
  if (e.category.present || e.subcategory.present) {
    s += " (" + e.category.value + ":" + e.subcategory.value + ")";
  }
  return s;
}

namespace {

std::string at(const Sources& src, Loc l) {
  return src.path(l.file) + ":" + std::to_string(l.line);
}

// Members every generated bit-field type has; a field accessor must not take these names.
bool reservedMember(const std::string& n) {
  return n == "raw" || n == "fromRaw" || n == "bits" || n == "raw_type" || n.rfind("with_", 0) == 0;
}

class Checker {
 public:
  Checker(const Sources& src, Diagnostics& diag) : src_(src), diag_(diag) {}

  void family(const Family& fam) {
    fam_ = &fam;
    // Lookups by name, built once: every step below is linear in the entries (issue 24).
    fieldsets_.clear();
    enums_.clear();
    byName_.clear();
    for (const Fieldset& fs : fam.fieldsets)
      fieldsets_.emplace(fs.name.value, &fs);
    for (const Enum& en : fam.enums)
      enums_.emplace(en.name.value, &en);
    for (const Entry& e : fam.entries)
      byName_.emplace(e.name.value, &e);
    for (const Entry& e : fam.entries)
      entry(e);
    uniqueness(fam);
    overlaps(fam);
    values(fam);
    for (const Fieldset& fs : fam.fieldsets)
      fieldset(fs);
    for (const Enum& en : fam.enums)
      enumeration(en);
    definitions(fam);
    blocks(fam);
  }

 private:
  void entry(const Entry& e) {
    const std::string what = describeEntry(e);
    if (e.name.present && !isAscii(e.name.value)) {
      diag_.error(e.name.loc,
                  what +
                      ": the name is not ASCII; give the English TRM name (regmapgen import keeps "
                      "names it cannot translate as they were)");
    }
    if (e.name.present || e.id.present) {
      const Loc l = e.id.present ? e.id.loc : e.name.loc;
      if (!isIdentifier(e.cppName) || isCppKeyword(e.cppName)) {
        diag_.error(
            l, what + ": '" + e.cppName + "' " +
                   (e.id.present ? "is not a usable C++ identifier"
                                 : "(derived from the name) is not a usable C++ identifier; add an 'id:'"));
      }
    }
    if (e.type && e.access) {
      const bool none = e.type->base == TypeInfo::Base::None;
      const bool cmd = e.access->code == AccessCode::Cmd;
      if (none && !cmd)
        diag_.error(e.accessLoc, what + ": type 'none' carries no data, so access must be 'cmd'");
      if (cmd && !none) diag_.error(e.typeLoc, what + ": access 'cmd' has no data, so type must be 'none'");
    }
    if (e.access && e.access->code == AccessCode::Cmd && e.kind->kind != EntryKind::Subcommand &&
        e.kind->kind != EntryKind::Mac) {
      diag_.error(e.accessLoc, what + ": access 'cmd' is only for subcommand and mac entries");
    }
    if (e.access && e.access->code == AccessCode::ConfigUpdate && e.kind->kind != EntryKind::DataMemory) {
      diag_.error(e.accessLoc, what + ": access 'config_update' is only for datamem entries");
    }
    if (e.type && e.kind->memory && (e.type->variable || e.type->base == TypeInfo::Base::None)) {
      diag_.error(e.typeLoc, what + ": " + std::string(e.kind->listName) +
                                 " entries occupy addresses, so their size must be fixed (not '" +
                                 e.type->code + "')");
    }
    if (e.kind->kind == EntryKind::Register && e.type && e.type->size() != 1) {
      diag_.error(e.typeLoc, what + ": registers are one byte; describe wider readings as 'values'");
    }
    if (e.fieldset.present && e.enumRef.present) {
      diag_.error(e.enumRef.loc, what + ": give either 'fieldset' or 'enum', not both");
    }
    if (e.fieldset.present) {
      const Fieldset* fs = findFieldset(e.fieldset.value);
      if (!fs) {
        diag_.error(e.fieldset.loc,
                    what + ": no fieldset named '" + e.fieldset.value + "' in family '" + fam_->name + "'");
      } else if (e.type && (!e.type->integer() || (fs->width != 0 && fs->width != e.type->size() * 8))) {
        diag_.error(e.fieldset.loc, what + ": fieldset '" + fs->name.value + "' is " +
                                        std::to_string(fs->width) + " bits wide but the entry's type is " +
                                        e.type->code);
      }
    }
    if (e.enumRef.present) {
      const Enum* en = findEnum(e.enumRef.value);
      if (!en) {
        diag_.error(e.enumRef.loc,
                    what + ": no enum named '" + e.enumRef.value + "' in family '" + fam_->name + "'");
      } else if (e.type && !e.type->integer()) {
        diag_.error(e.enumRef.loc,
                    what + ": only integer types can hold an enum (type is " + e.type->code + ")");
      } else if (e.type) {
        for (const EnumValue& v : en->values) {
          if (v.value && (*v.value < e.type->minValue() || *v.value > e.type->maxValue())) {
            diag_.error(v.valueLoc, "enum '" + en->name.value + "' value '" + v.name.value +
                                        "' = " + std::to_string(*v.value) + " does not fit " + what +
                                        " of type " + e.type->code);
          }
        }
      }
    }
    limits(e, what);
  }

  void limits(const Entry& e, const std::string& what) {
    const Number* all[] = {&e.min, &e.max, &e.dflt};
    const char* names[] = {"min", "max", "default"};
    if (!e.type) return;
    bool ok[3] = {false, false, false};
    for (int i = 0; i < 3; ++i) {
      const Number& n = *all[i];
      if (!n.present) continue;
      if (e.type->base == TypeInfo::Base::Float) {
        ok[i] = true;
        continue;
      }
      if (!e.type->integer()) {
        diag_.error(n.loc, what + ": '" + names[i] + "' is only meaningful for scalar types (type is " +
                               e.type->code + ")");
        continue;
      }
      if (!n.isInteger) {
        diag_.error(n.loc,
                    what + ": " + names[i] + " '" + n.text + "' must be an integer for type " + e.type->code);
        continue;
      }
      if (n.integer < e.type->minValue() || n.integer > e.type->maxValue()) {
        diag_.error(n.loc, what + ": " + names[i] + " " + n.text + " is too wide for type " + e.type->code +
                               " (" + std::to_string(e.type->minValue()) + ".." +
                               std::to_string(e.type->maxValue()) + ")");
        continue;
      }
      ok[i] = true;
    }
    auto value = [](const Number& n) { return n.real; };
    if (ok[0] && ok[1] && value(e.min) > value(e.max)) {
      diag_.error(e.max.loc, what + ": max " + e.max.text + " is below min " + e.min.text);
    }
    if (ok[2] && ok[0] && value(e.dflt) < value(e.min)) {
      diag_.error(e.dflt.loc, what + ": default " + e.dflt.text + " is below min " + e.min.text);
    }
    if (ok[2] && ok[1] && value(e.dflt) > value(e.max)) {
      diag_.error(e.dflt.loc, what + ": default " + e.dflt.text + " is above max " + e.max.text);
    }
  }

  void uniqueness(const Family& fam) {
    std::map<std::string, const Entry*> names;  // kind + category path + name
    std::map<std::string, const Entry*> ids;    // namespace + identifier
    for (const Entry& e : fam.entries) {
      if (e.name.present) {
        const std::string key = std::string(e.kind->yamlKey) + "\x1f" + e.category.value + "\x1f" +
                                e.subcategory.value + "\x1f" + e.name.value;
        auto [it, fresh] = names.emplace(key, &e);
        if (!fresh) {
          diag_.error(e.name.loc, "duplicate name: " + describeEntry(e) + " is already defined at " +
                                      at(src_, it->second->name.loc));
        }
      }
      if (!e.cppName.empty()) {
        auto [it, fresh] = ids.emplace(std::string(e.kind->ns) + "::" + e.cppName, &e);
        if (!fresh && it->second->name.value != e.name.value) {
          diag_.error(e.id.present ? e.id.loc : e.name.loc,
                      std::string("identifier ").append(e.kind->ns) + "::" + e.cppName + " of " +
                          describeEntry(e) + " is also used by " + describeEntry(*it->second) + " at " +
                          at(src_, it->second->loc) + "; give one of them an explicit 'id:'");
        }
      }
    }
  }

  // Duplicate and overlapping addresses, within each kind. One sweep in address order (issue 24: comparing
  // each entry with every entry before it took 20 s for 16 000 entries): each entry is compared with the one
  // before it in address order that reaches furthest, and the later of the two in the file is reported.
  void overlaps(const Family& fam) {
    // Bytes a memory-like entry occupies, codes an entry of the other kinds covers.
    auto extent = [](const Entry& x) -> std::uint64_t {
      return x.kind->memory ? static_cast<std::uint64_t>(std::max(x.size(), 1)) : x.span;
    };
    struct Placed {
      const Entry* e;
      std::size_t order;  // position in the file(s)
      std::uint64_t lo, hi;
    };
    std::vector<Placed> placed;
    for (const Entry& e : fam.entries) {
      if (!e.addr || !e.type) continue;
      const std::uint64_t lo = *e.addr;
      const std::uint64_t n = extent(e);
      const std::uint64_t hi = lo + n - 1;
      if (hi > e.kind->maxAddress && e.kind->memory) {
        diag_.error(e.addrLoc, describeEntry(e) + ": its " + std::to_string(n) + " bytes run past address " +
                                   hexAddress(e.kind->maxAddress));
      }
      placed.push_back({&e, placed.size(), lo, hi});
    }
    std::stable_sort(placed.begin(), placed.end(), [](const Placed& a, const Placed& b) {
      return a.e->kind != b.e->kind ? a.e->kind < b.e->kind : a.lo != b.lo ? a.lo < b.lo : a.order < b.order;
    });
    const Placed* reach = nullptr;  // of the entries of this kind so far, the one ending last
    for (const Placed& q : placed) {
      if (reach && reach->e->kind != q.e->kind) reach = nullptr;
      if (reach && q.lo <= reach->hi) {
        const Placed& later = q.order > reach->order ? q : *reach;
        const Placed& earlier = q.order > reach->order ? *reach : q;
        const int d = q.e->kind->addrDigits;
        if (later.lo == earlier.lo) {
          diag_.error(later.e->addrLoc, "duplicate address " + hexAddress(later.lo, d) + ": " +
                                            describeEntry(*later.e) + " and " + describeEntry(*earlier.e) +
                                            " (" + at(src_, earlier.e->addrLoc) + ")");
        } else {
          diag_.error(later.e->addrLoc, describeEntry(*later.e) + " at " + hexAddress(later.lo, d) + ".." +
                                            hexAddress(later.hi, d) + " overlaps " +
                                            describeEntry(*earlier.e) + " at " + hexAddress(earlier.lo, d) +
                                            ".." + hexAddress(earlier.hi, d) + " (" +
                                            at(src_, earlier.e->addrLoc) + ")");
        }
      }
      if (!reach || q.hi > reach->hi) reach = &q;
    }
  }

  // Every byte of a multi-byte value must be a register of the family.
  void values(const Family& fam) {
    std::set<std::uint32_t> regs;
    for (const Entry& e : fam.entries) {
      if (e.kind->kind == EntryKind::Register && e.addr) regs.insert(*e.addr);
    }
    for (const Entry& e : fam.entries) {
      if (e.kind->kind != EntryKind::Value || !e.addr || !e.type) continue;
      for (int i = 0; i < e.size(); ++i) {
        if (!regs.count(*e.addr + static_cast<std::uint32_t>(i))) {
          diag_.error(e.addrLoc, describeEntry(e) + ": byte " + hexAddress(*e.addr + i, 4) +
                                     " is not a register of family '" + fam.name + "'");
        }
      }
    }
  }

  void fieldset(const Fieldset& fs) {
    const std::string what = "fieldset '" + fs.name.value + "'";
    std::uint64_t used = 0;
    std::vector<const Field*> placed;
    std::set<std::string> ids;
    for (const Field& f : fs.fields) {
      const std::string fwhat = what + " field '" + f.name.value + "'";
      if (f.name.present && !isAscii(f.name.value))
        diag_.error(f.name.loc, fwhat + ": the name is not ASCII");
      const Loc idLoc = f.id.present ? f.id.loc : f.name.loc;
      if (!isIdentifier(f.cppName) || isCppKeyword(f.cppName) || reservedMember(f.cppName)) {
        diag_.error(idLoc, fwhat + ": accessor name '" + f.cppName + "' " +
                               (f.id.present ? "is not usable"
                                             : "(derived from the name) is not usable; add an 'id:'"));
      } else if (!ids.insert(f.cppName).second) {
        diag_.error(idLoc, fwhat + ": accessor name '" + f.cppName + "' is used twice in " + what);
      }
      if (f.msb < 0) continue;
      if (fs.width && f.msb >= fs.width) {
        diag_.error(f.bitsLoc, fwhat + ": bits " + f.bitsText() + " exceed the " + std::to_string(fs.width) +
                                   "-bit width");
        continue;
      }
      const std::uint64_t mask = f.mask();
      if (used & mask) {
        for (const Field* p : placed) {
          if (p->mask() & mask) {
            diag_.error(f.bitsLoc, fwhat + ": bits " + f.bitsText() + " overlap field '" + p->name.value +
                                       "' (bits " + p->bitsText() + ")");
            break;
          }
        }
      }
      used |= mask;
      placed.push_back(&f);
      if (f.enumRef.present) {
        const Enum* en = findEnum(f.enumRef.value);
        if (!en) {
          diag_.error(f.enumRef.loc, fwhat + ": no enum named '" + f.enumRef.value + "'");
        } else {
          for (const EnumValue& v : en->values) {
            if (v.value && (*v.value < 0 || *v.value >= (std::int64_t{1} << f.width()))) {
              diag_.error(v.valueLoc, "enum '" + en->name.value + "' value '" + v.name.value +
                                          "' = " + std::to_string(*v.value) + " is too wide for " + fwhat +
                                          " (" + std::to_string(f.width()) + " bits)");
            }
          }
        }
      }
    }
  }

  void enumeration(const Enum& en) {
    std::map<std::string, const EnumValue*> names;
    std::map<std::int64_t, const EnumValue*> values;
    for (const EnumValue& v : en.values) {
      if (v.name.present && !names.emplace(v.name.value, &v).second) {
        diag_.error(v.name.loc, "enum '" + en.name.value + "': duplicate value name '" + v.name.value + "'");
      }
      if (v.value && !values.emplace(*v.value, &v).second) {
        diag_.error(v.valueLoc, "enum '" + en.name.value + "': value " + std::to_string(*v.value) + " of '" +
                                    v.name.value + "' is already '" + values[*v.value]->name.value + "'");
      }
    }
  }

  // Fieldset and enum names unique; unused definitions are warnings.
  void definitions(const Family& fam) {
    std::set<std::string> usedFieldsets, usedEnums;
    for (const Entry& e : fam.entries) {
      if (e.fieldset.present) usedFieldsets.insert(e.fieldset.value);
      if (e.enumRef.present) usedEnums.insert(e.enumRef.value);
    }
    for (const Fieldset& fs : fam.fieldsets) {
      for (const Field& f : fs.fields) {
        if (f.enumRef.present) usedEnums.insert(f.enumRef.value);
      }
    }
    std::map<std::string, Loc> types;
    for (const Fieldset& fs : fam.fieldsets) {
      if (!fs.name.present) continue;
      auto [it, fresh] = types.emplace(fs.name.value, fs.name.loc);
      if (!fresh)
        diag_.error(fs.name.loc, "fieldset '" + fs.name.value + "' is defined twice (first at " +
                                     at(src_, it->second) + ")");
      if (!usedFieldsets.count(fs.name.value))
        diag_.warning(fs.name.loc, "fieldset '" + fs.name.value + "' is not used by any entry");
    }
    std::map<std::string, Loc> enums;
    for (const Enum& en : fam.enums) {
      if (!en.name.present) continue;
      auto [it, fresh] = enums.emplace(en.name.value, en.name.loc);
      if (!fresh)
        diag_.error(en.name.loc,
                    "enum '" + en.name.value + "' is defined twice (first at " + at(src_, it->second) + ")");
      if (!usedEnums.count(en.name.value))
        diag_.warning(en.name.loc, "enum '" + en.name.value + "' is not used by any entry or field");
    }
  }

  // Each block's members are direct commands in address order, each beginning where the one before it ends
  // (or later, where gaps are allowed), and the block fits one read.
  void blocks(const Family& fam) {
    std::map<std::string, Loc> names;
    for (const Block& b : fam.blocks) {
      const std::string what = "block '" + b.name.value + "'";
      if (b.name.present) {
        auto [it, fresh] = names.emplace(b.name.value, b.name.loc);
        if (!fresh)
          diag_.error(b.name.loc, what + " is defined twice (first at " + at(src_, it->second) + ")");
      }
      // The address after the previous member, when there is one (a flag, not std::optional: GCC 12 at -O2
      // reports std::optional<uint32_t> here as maybe used uninitialised, which -Werror makes fatal).
      std::uint32_t next = 0;
      bool haveNext = false;
      const Entry* previous = nullptr;
      for (const Text& m : b.members) {
        const Entry* e = blockMember(fam, m, what);
        if (!e || !e->addr || !e->type) {
          haveNext = false;
          continue;
        }
        if (!previous && b.start.present && static_cast<std::int64_t>(*e->addr) != b.start.integer) {
          diag_.error(m.loc, what + " starts at " + b.start.text + " but its first member '" + m.value +
                                 "' is at " + hexAddress(*e->addr, 2));
        }
        if (haveNext && *e->addr < next) {
          diag_.error(m.loc, what + ": '" + m.value + "' at " + hexAddress(*e->addr, 2) +
                                 " overlaps or precedes '" + previous->name.value +
                                 "' (members are in address order, each after the last)");
        } else if (haveNext && *e->addr > next && !b.gapsAllowed) {
          diag_.error(m.loc, what + ": '" + m.value + "' at " + hexAddress(*e->addr, 2) + " leaves " +
                                 hexAddress(next, 2) + ".." + hexAddress(*e->addr - 1, 2) +
                                 " unread after '" + previous->name.value +
                                 "' (write 'gaps: allowed' if the scan reads them)");
        }
        previous = e;
        next = *e->addr + static_cast<std::uint32_t>(e->size());
        haveNext = true;
        if (b.start.present && b.start.integer >= 0 &&
            static_cast<std::int64_t>(next) - b.start.integer > kMaxBlockBytes) {
          diag_.error(m.loc, what + ": '" + m.value + "' ends " +
                                 std::to_string(static_cast<std::int64_t>(next) - b.start.integer) +
                                 " bytes after the start, beyond the " + std::to_string(kMaxBlockBytes) +
                                 " bytes one read may carry");
        }
      }
    }
  }

  // The commands entry a block member names, or nothing (reported).
  const Entry* blockMember(const Family& fam, const Text& m, const std::string& what) {
    const Entry* other = nullptr;
    for (auto [it, end] = byName_.equal_range(m.value); it != end; ++it) {
      if (it->second->kind->kind == EntryKind::Command) return it->second;
      other = it->second;
    }
    if (other) {
      diag_.error(m.loc, what + ": '" + m.value + "' is a " + std::string(other->kind->listName) + " (" +
                             at(src_, other->loc) + "), not a direct command");
    } else {
      diag_.error(m.loc, what + ": no command named '" + m.value + "' in family '" + fam.name + "'");
    }
    return nullptr;
  }

  // The first definition of a name (a second one is reported by definitions()).
  const Fieldset* findFieldset(const std::string& name) const {
    const auto it = fieldsets_.find(name);
    return it == fieldsets_.end() ? nullptr : it->second;
  }
  const Enum* findEnum(const std::string& name) const {
    const auto it = enums_.find(name);
    return it == enums_.end() ? nullptr : it->second;
  }

  const Sources& src_;
  Diagnostics& diag_;
  const Family* fam_ = nullptr;
  std::map<std::string, const Fieldset*> fieldsets_;
  std::map<std::string, const Enum*> enums_;
  std::multimap<std::string, const Entry*> byName_;  // in file order within a name
};

}  // namespace

void check(const Model& model, Diagnostics& diag) {
  Checker c(diag.sources(), diag);
  for (const Family& fam : model.families)
    c.family(fam);
}

}  // namespace regmapgen
