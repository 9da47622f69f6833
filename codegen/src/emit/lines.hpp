// Line writers for generated C++: they lay text out as clang-format (the repository's .clang-format: Google
// style, 110 columns) would, so generated files pass `clang-format --dry-run -Werror` unchanged without the
// build running clang-format. Each helper covers one layout whose clang-format result is fixed:
//   - comments are word-wrapped at the column limit (clang-format leaves lines that fit alone);
//   - a braced list that does not fit on one line gets one member per line and a trailing comma (which
//     clang-format keeps one per line, indented by 4, the closing brace back at the opening line's indent);
//   - trailing comments of consecutive lines are aligned two spaces after the longest code, or, when an
//     aligned comment would pass the limit, each comment moves to its own line above its code.
#pragma once

#include <cstddef>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace regmapgen {

inline constexpr std::size_t kColumnLimit = 110;

// `text` as `//` comment lines indented by `indent` spaces, words wrapped at the column limit. A word longer
// than a line stays whole on a line of its own.
void writeComment(std::ostringstream& o, std::string_view text, std::size_t indent = 0);

// `head{m1, m2}tail` on one line when it fits in the column limit, else `head{`, one `m,` line per member
// indented by indent + 4, and `}tail` at `indent`. `head` starts at column `indent` (already indented).
void writeBraced(std::ostringstream& o, std::size_t indent, const std::string& head,
                 const std::vector<std::string>& members, const std::string& tail);

// A declaration `type name{};`: on one line when it fits, else the name on the next line indented by 4.
void writeDeclaration(std::ostringstream& o, const std::string& type, const std::string& name);

// Lines of code (each with its indent) and their trailing comments ("" for none), aligned as clang-format
// aligns a run of trailing comments.
void writeCommented(std::ostringstream& o, const std::vector<std::pair<std::string, std::string>>& lines);

}  // namespace regmapgen
