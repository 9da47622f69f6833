#include "diff/diff.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

#include "check/check.hpp"
#include "model/names.hpp"

namespace regmapgen {

namespace {

struct Ref {
  const Family* family;
  const Entry* entry;
};

std::string identity(const Ref& r) {
  const Entry& e = *r.entry;
  return r.family->name + '\x1f' + std::string(e.kind->yamlKey) + '\x1f' + lookupKey(e.category.value) +
         '\x1f' + lookupKey(e.subcategory.value) + '\x1f' + lookupKey(e.name.value);
}

std::string address(const Entry& e) {
  return e.addr ? hexAddress(*e.addr, e.kind->addrDigits) : "?";
}

std::string typeCode(const Entry& e) {
  return e.type ? e.type->code : "?";
}

bool sameNumber(const Number& a, const Number& b) {
  if (a.present != b.present) return false;
  if (!a.present) return true;
  if (a.isInteger && b.isInteger) return a.integer == b.integer;
  return a.real == b.real;
}

std::string numberText(const Number& n) {
  return n.present ? n.text : "(none)";
}

// "50.6 mV", "mV", "(none)".
std::string unitText(const Entry& e) {
  if (!e.unit) return "(none)";
  const bool scaled = e.scale.present && !(e.scale.num == 1 && e.scale.den == 1);
  return (scaled ? e.scale.text + " " : "") + std::string(e.unit->symbol);
}

bool sameUnit(const Entry& a, const Entry& b) {
  return a.unit == b.unit && a.scale.num * b.scale.den == b.scale.num * a.scale.den;
}

// A field's name for comparing: "SEC[1:0]" and "SEC1–SEC0" are both SEC; case, '_' and '-' ignored.
std::string fieldKey(const std::string& name) {
  return lookupKey(name.substr(0, name.find('[')));
}

// The fields of an entry's fieldset in both versions, when both have one: "fields: CUV 2 -> 3, + OCD3 7,
// - RSVD 1" (matched by name, then by bits for a renamed field).
std::string fieldChanges(const Family& fa, const Entry& a, const Family& fb, const Entry& b) {
  const Fieldset* x = a.fieldset.present ? fa.findFieldset(a.fieldset.value) : nullptr;
  const Fieldset* y = b.fieldset.present ? fb.findFieldset(b.fieldset.value) : nullptr;
  if (!x || !y) return "";
  std::map<std::string, const Field*> before, after;
  for (const Field& f : x->fields)
    before.emplace(fieldKey(f.name.value), &f);
  for (const Field& f : y->fields)
    after.emplace(fieldKey(f.name.value), &f);
  std::vector<std::string> parts;
  std::vector<const Field*> gone, added;
  for (const auto& [key, f] : before) {
    const auto it = after.find(key);
    if (it == after.end()) {
      gone.push_back(f);
    } else if (f->msb != it->second->msb || f->lsb != it->second->lsb) {
      parts.push_back(f->name.value + " " + f->bitsText() + " -> " + it->second->bitsText());
    }
  }
  for (const auto& [key, f] : after) {
    if (!before.count(key)) added.push_back(f);
  }
  for (const Field* g : gone) {
    const auto same = std::find_if(added.begin(), added.end(),
                                   [&](const Field* n) { return n->msb == g->msb && n->lsb == g->lsb; });
    if (same != added.end()) {
      parts.push_back(g->name.value + " -> " + (*same)->name.value + " (" + g->bitsText() + ")");
      added.erase(same);
    } else {
      parts.push_back("- " + g->name.value + " " + g->bitsText());
    }
  }
  for (const Field* n : added)
    parts.push_back("+ " + n->name.value + " " + n->bitsText());
  if (parts.empty()) return "";
  std::string out = "fields:";
  for (std::size_t i = 0; i < parts.size(); ++i)
    out += (i ? ", " : " ") + parts[i];
  return out;
}

// What differs between two versions of one entry, as "what old -> new" parts.
std::vector<std::string> changes(const Entry& a, const Entry& b) {
  std::vector<std::string> out;
  const auto change = [&](const std::string& what, const std::string& from, const std::string& to) {
    out.push_back(what + " " + from + " -> " + to);
  };
  if (a.name.value != b.name.value) change("name", "'" + a.name.value + "'", "'" + b.name.value + "'");
  if (a.addr != b.addr) change("address", address(a), address(b));
  if (a.span != b.span) change("span", std::to_string(a.span), std::to_string(b.span));
  if (typeCode(a) != typeCode(b)) change("type", typeCode(a), typeCode(b));
  const std::tuple<const char*, const Number&, const Number&> numbers[] = {
      {"min", a.min, b.min}, {"max", a.max, b.max}, {"default", a.dflt, b.dflt}};
  for (const auto& [what, x, y] : numbers) {
    if (!sameNumber(x, y)) change(what, numberText(x), numberText(y));
  }
  if (!sameUnit(a, b)) change("unit", unitText(a), unitText(b));
  return out;
}

std::vector<Ref> entriesOf(const Model& m) {
  std::vector<Ref> out;
  for (const Family& f : m.families) {
    for (const Entry& e : f.entries) {
      if (e.kind) out.push_back({&f, &e});
    }
  }
  return out;
}

std::size_t kindIndex(const Entry& e) {
  return static_cast<std::size_t>(e.kind - kinds().data());
}

}  // namespace

MapDiff diffModels(const Model& before, const Model& after, bool onlyKindsOfAfter) {
  std::vector<Ref> a = entriesOf(before);
  const std::vector<Ref> b = entriesOf(after);
  if (onlyKindsOfAfter) {
    std::set<const KindInfo*> present;
    for (const Ref& r : b)
      present.insert(r.entry->kind);
    std::erase_if(a, [&](const Ref& r) { return !present.count(r.entry->kind); });
  }

  std::multimap<std::string, std::size_t> byIdentity;
  for (std::size_t j = 0; j < b.size(); ++j)
    byIdentity.emplace(identity(b[j]), j);
  std::vector<int> partner(a.size(), -1);
  std::vector<bool> taken(b.size(), false);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto [lo, hi] = byIdentity.equal_range(identity(a[i]));
    for (auto it = lo; it != hi; ++it) {
      if (taken[it->second]) continue;
      partner[i] = static_cast<int>(it->second);
      taken[it->second] = true;
      break;
    }
  }
  // Renames: unmatched on both sides at the same family, kind and address.
  std::map<std::tuple<std::string, const KindInfo*, std::uint32_t>, std::vector<std::size_t>> unmatchedAt;
  for (std::size_t j = 0; j < b.size(); ++j) {
    if (!taken[j] && b[j].entry->addr)
      unmatchedAt[{b[j].family->name, b[j].entry->kind, *b[j].entry->addr}].push_back(j);
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (partner[i] >= 0 || !a[i].entry->addr) continue;
    auto it = unmatchedAt.find({a[i].family->name, a[i].entry->kind, *a[i].entry->addr});
    if (it == unmatchedAt.end() || it->second.empty()) continue;
    partner[i] = static_cast<int>(it->second.front());
    taken[it->second.front()] = true;
    it->second.erase(it->second.begin());
  }

  struct Line {
    std::size_t kind;
    std::uint32_t addr;
    std::string text;
  };
  std::vector<Line> lines;
  MapDiff d;
  const auto sortKey = [](const Entry& e) { return e.addr.value_or(0); };
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Entry& e = *a[i].entry;
    if (partner[i] < 0) {
      ++d.removed;
      lines.push_back(
          {kindIndex(e), sortKey(e), "- " + describeEntry(e) + " " + address(e) + " " + typeCode(e)});
      continue;
    }
    const Entry& n = *b[static_cast<std::size_t>(partner[i])].entry;
    std::vector<std::string> what = changes(e, n);
    if (std::string fields =
            fieldChanges(*a[i].family, e, *b[static_cast<std::size_t>(partner[i])].family, n);
        !fields.empty())
      what.push_back(std::move(fields));
    if (what.empty()) {
      ++d.unchanged;
      continue;
    }
    ++d.changed;
    std::string text = "~ " + describeEntry(e) + " " + address(e) + ":";
    for (std::size_t k = 0; k < what.size(); ++k)
      text += (k ? "; " : " ") + what[k];
    lines.push_back({kindIndex(e), sortKey(e), text});
  }
  for (std::size_t j = 0; j < b.size(); ++j) {
    if (taken[j]) continue;
    const Entry& e = *b[j].entry;
    ++d.added;
    lines.push_back(
        {kindIndex(e), sortKey(e), "+ " + describeEntry(e) + " " + address(e) + " " + typeCode(e)});
  }
  std::stable_sort(lines.begin(), lines.end(), [](const Line& x, const Line& y) {
    return std::tie(x.kind, x.addr) < std::tie(y.kind, y.addr);
  });
  for (Line& l : lines)
    d.lines.push_back(std::move(l.text));
  return d;
}

}  // namespace regmapgen
