#include "import/row_parts.hpp"

#include <algorithm>

#include "import/cells.hpp"
#include "model/names.hpp"
#include "text/scan.hpp"

namespace regmapgen::rows {

// The kind a `--kind` value names (its `list` word or YAML key), or nullptr.
const KindInfo* findKind(const std::string& k) {
  for (const KindInfo& info : kinds()) {
    if (info.listName == k || info.yamlKey == k) return &info;
  }
  return nullptr;
}

// Which kinds a family's tables hold: 8-bit codes, 16-bit codes, and tables with a class column.
const FamilyKinds& kindsOf(const std::string& family) {
  static const FamilyKinds table[] = {
      {"bq79616", "registers", "registers", "registers"},
      {"bq4050", "sbs", "mac", "dataflash"},
      {"", "commands", "subcommands", "datamem"},  // BQ769x2, BQ7690x and anything else
  };
  for (const FamilyKinds& f : table) {
    if (f.family == family) return f;
  }
  return table[std::size(table) - 1];
}

// "Address 0x9261", "地址 0x9261", "写入 0x9304", "write to 0x9304", and in a sentence that writes something
// ("writes 0x04 to 0x901B") the address after "to": the 4-digit address after the keyword.
std::vector<std::string> addressMentions(const std::string& line) {
  static const std::string_view keywords[] = {"地址", "写入", "Address", "address", "Write to", "write to"};
  const std::size_t writes = std::min(line.find("write"), line.find("Write"));
  std::vector<std::pair<std::size_t, std::string>> found;
  std::vector<std::string_view> words(std::begin(keywords), std::end(keywords));
  if (writes != std::string::npos) words.push_back(" to ");
  for (std::string_view k : words) {
    for (std::size_t p = line.find(k); p != std::string::npos; p = line.find(k, p + 1)) {
      if (k == " to " && p < writes) continue;
      std::size_t q = p + k.size();
      while (q < line.size() && (line[q] == ' ' || line[q] == '\t'))
        ++q;
      const std::string_view rest = std::string_view(line).substr(q);
      const bool wordAfter =
          rest.size() > 6 && (scan::isAlpha(rest[6]) || scan::isDigit(rest[6]) || rest[6] == '_');
      if (rest.size() >= 6 && scan::isHexLiteral(rest.substr(0, 6)) && !wordAfter)
        found.emplace_back(p, "0x" + upperCase(rest.substr(2, 4)));
    }
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  std::size_t last = std::string::npos;
  for (const auto& [at, address] : found) {
    // "write to 0x9304" is found as "write to" and as " to ": one mention.
    if (!(last != std::string::npos && at - last <= 6 && !out.empty() && out.back() == address))
      out.push_back(address);
    last = at;
  }
  return out;
}

// "16 位", "16-bit", "32 bit" in a description: the width it states and the words that state it.
StatedWidth statedWidth(const std::string& description) {
  for (std::size_t p = 0; p < description.size(); ++p) {
    std::size_t unit = 0, end = p;
    if (description.compare(p, 3, "位") == 0) {
      unit = 3;
    } else if (description.compare(p, 3, "bit") == 0) {
      unit = 3;
      if (p > 0 && description[p - 1] == '-') --end;
    } else {
      continue;
    }
    while (end > 0 && (description[end - 1] == ' ' || description[end - 1] == '\t'))
      --end;
    for (const std::string width : {"16", "32", "8"}) {
      if (end >= width.size() && description.compare(end - width.size(), width.size(), width) == 0) {
        const std::size_t from = end - width.size();
        return {std::stoi(width), description.substr(from, p + unit - from)};
      }
    }
  }
  return {};
}

// An address cell: "0x14", "0x0022 (R)", or a range of codes "0x4000–0x5FFF", "0x4000...0x5FFF",
// "0x4000 to 0x5FFF". The hex digits of the first and (for a range) the last code.
std::optional<AddressCell> addressCell(const std::string& cell) {
  std::string t;
  for (std::size_t i = 0; i < cell.size(); ++i) {
    const std::string_view rest = std::string_view(cell).substr(i);
    if (rest.starts_with("\xE2\x80\x93") || rest.starts_with("\xE2\x80\x94") || rest.starts_with("...") ||
        rest.starts_with("\xE2\x80\xA6")) {
      t += '-';
      i += 2;  // every one of these separators is three bytes
    } else if (rest.starts_with(" to ")) {
      t += '-';
      i += 3;
    } else if (cell[i] != ' ') {
      t += cell[i];
    }
  }
  const std::size_t end = std::min(t.find_first_not_of("0123456789abcdefABCDEFxX-"), t.size());
  const std::string range = t.substr(0, end);
  const std::string a = range.substr(0, range.find('-'));
  if (!scan::isHexLiteral(a)) return std::nullopt;
  const std::string b = range.find('-') == std::string::npos ? "" : range.substr(range.find('-') + 1);
  return AddressCell{a.substr(2), scan::isHexLiteral(b) ? b.substr(2) : ""};
}

// Hex digits as an address of `digits` digits ("14" -> "0x14", "22" -> "0x0022"); a value too wide for any
// kind is kept as written, for check to report.
std::string addressText(const std::string& hex, int digits) {
  const std::size_t significant = std::min(hex.find_first_not_of('0'), hex.size());
  if (hex.size() - significant > 8) return "0x" + upperCase(hex);
  return hexAddress(std::stoull(hex, nullptr, 16), digits);
}

// "CB_CELL16_CTRL through CB_CELL1_CTRL", "OTP_PROG_UNLOCK1A through OTP_PROG_UNLOCK1D": the names of a run
// of registers, in the order of their rows (TI names the first row of a run with both ends and leaves the
// name of the others empty). Empty unless the ends differ in one number or one letter.
std::vector<std::string> runNames(const std::string& name) {
  const std::size_t at = name.find(" through ");
  if (at == std::string::npos) return {};
  const std::string a = name.substr(0, at), b = name.substr(at + 9);
  std::size_t pre = 0;
  while (pre < a.size() && pre < b.size() && a[pre] == b[pre])
    ++pre;
  std::size_t post = 0;
  while (post < a.size() - pre && post < b.size() - pre && a[a.size() - 1 - post] == b[b.size() - 1 - post])
    ++post;
  std::vector<std::string> out;
  const auto middle = [&](const std::string& s) { return s.substr(pre, s.size() - pre - post); };
  if (middle(a).size() == 1 && middle(b).size() == 1 && scan::isAlpha(middle(a)[0]) &&
      scan::isAlpha(middle(b)[0])) {
    const char from = middle(a)[0], to = middle(b)[0];
    for (char c = from;; c = static_cast<char>(c + (from <= to ? 1 : -1))) {
      out.push_back(a.substr(0, pre) + c + a.substr(a.size() - post));
      if (c == to) break;
    }
    return out;
  }
  // A number: widen the differing part to whole numbers ("CELL16" / "CELL1" differ in "6" / "").
  while (pre > 0 && scan::isDigit(a[pre - 1]))
    --pre;
  while (post > 0 && scan::isDigit(a[a.size() - post]))
    --post;
  const std::string ma = middle(a), mb = middle(b);
  if (ma.empty() || mb.empty() || ma.size() > 3 || mb.size() > 3 || !scan::all(ma, scan::isDigit) ||
      !scan::all(mb, scan::isDigit)) {
    return {};
  }
  const int from = std::stoi(ma), to = std::stoi(mb);
  for (int n = from;; n += from <= to ? 1 : -1) {
    out.push_back(a.substr(0, pre) + std::to_string(n) + a.substr(a.size() - post));
    if (n == to) break;
  }
  return out;
}

RowCells::RowCells(const TableEvent& row, const std::vector<Role>& roles,
                   const std::vector<TableCell>& headings)
    : row_(row) {
  for (std::size_t i = 0; i < row.cells.size(); ++i) {
    const Role role = i < roles.size() ? roles[i] : Role::Unknown;
    const TableCell& c = row.cells[i];
    if (role == Role::Unknown) {
      if (c.text.empty()) continue;
      const std::string label = i < headings.size() ? headings[i].text : "column " + std::to_string(i + 1);
      extra.append(extra.empty() ? "" : " ").append(label).append(": ").append(c.text);
      if (i >= roles.size()) beyondHeadings.push_back(&c);
      continue;
    }
    if (role == Role::Description || role == Role::Data) {
      std::string& joined = role == Role::Data ? data_ : description_;
      if (!c.text.empty()) joined.append(joined.empty() ? "" : " ").append(c.text);
      if (cells_.count(role)) continue;
    }
    if (role == Role::Access && cells_.count(role) && !cells::access(c.text)) continue;
    if (!cells_.count(role) || !c.text.empty()) cells_[role] = &c;
  }
}

std::string RowCells::get(Role r) const {
  if (r == Role::Description) return description_;
  if (r == Role::Data) return data_;
  auto it = cells_.find(r);
  return it == cells_.end() ? std::string() : it->second->text;
}

int RowCells::col(Role r) const {
  auto it = cells_.find(r);
  return it == cells_.end() ? 1 : it->second->col;
}

int RowCells::line(Role r) const {
  auto it = cells_.find(r);
  return it == cells_.end() || it->second->line == 0 ? row_.line : it->second->line;
}

std::string capped(const std::string& v) {
  if (v.size() <= kMaxValueBytes) return v;
  std::size_t cut = kMaxValueBytes;
  while (cut > 0 && (static_cast<unsigned char>(v[cut]) & 0xC0) == 0x80)
    --cut;
  return v.substr(0, cut) + "...";
}

}  // namespace regmapgen::rows
