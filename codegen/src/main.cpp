// regmapgen: validates register-map YAML, generates C++ and Markdown from it, lists entries, and imports TRM
// tables. See `regmapgen help` and regmaps/README.md.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "can/can_emit.hpp"
#include "can/can_model.hpp"
#include "check/check.hpp"
#include "diag/diag.hpp"
#include "diff/diff.hpp"
#include "emit/emit.hpp"
#include "import/headings.hpp"
#include "import/import.hpp"
#include "import/pdf.hpp"
#include "model/model.hpp"
#include "model/schema.hpp"
#include "pack/pack_emit.hpp"

namespace fs = std::filesystem;
using namespace regmapgen;

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  regmapgen check FILE...         validate; every error as file:line:col, exit 1 on any error\n"
    "  regmapgen list FILE...          one line per entry: <kind> <address> <identifier> <type>\n"
    "  regmapgen generate --out DIR [--docs DIR] [--docs-only] [--stamp FILE] FILE...\n"
    "                                  write DIR/regmap/<family>.hpp, <family>_table.hpp, "
    "<family>_selftest.cpp\n"
    "                                  and DOCS/<family>/REFERENCE.md (DOCS defaults to DIR/docs; "
    "--docs-only\n"
    "                                  writes just the references); files are only rewritten when their "
    "content\n"
    "                                  changes; --stamp is touched on success\n"
    "  regmapgen import [--family NAME] [--kind KIND] [--map FILE]... [--source SRC]\n"
    "                   [--pages A-B] [--against FILE|DIR]... FILE|-\n"
    "                                  turn TRM / app-note tables into YAML on stdout: '|' or tab separated\n"
    "                                  text, pdftotext -layout text, or a PDF (runs pdftotext; --pages\n"
    "                                  limits it); --against prints what the import changes instead, as "
    "diff\n"
    "  regmapgen diff OLD NEW          entries added (+), removed (-) and changed (~: address, type, range,\n"
    "                                  default, unit), one line each; OLD and NEW are YAML files or "
    "folders;\n"
    "                                  exit 0 if nothing differs, 1 if something does, 2 on errors\n"
    "  regmapgen can --out DIR [--dbc-dir DIR] FILE\n"
    "                                  CAN catalogue: DIR/can/<name>.hpp packers and unpackers,\n"
    "                                  DIR/can/<name>_table.hpp (host tools), <name>_<layout>.dbc and\n"
    "                                  REFERENCE.md (in --dbc-dir, default DIR/can); every error as\n"
    "                                  file:line:col\n"
    "  regmapgen pack --regmaps DIR [--out DIR] [--select DIR] FILE\n"
    "                                  a pack file (firmware/app/packs/*.yaml) checked against its device's\n"
    "                                  register map (DIR/<family>/*.yaml); with --out writes\n"
    "                                  DIR/packs/<name>.hpp, with --select SEL/packs/selected.hpp naming it\n"
    "                                  fw::pack; every error as file:line:col, exit 1 on any error\n"
    "  regmapgen schema                the YAML schema as Markdown (embedded in regmaps/README.md)\n"
    "  regmapgen glossary              the import glossary (Chinese TI terms -> English) as Markdown\n";

// A file's text, or standard input's for "-"; false after printing why not ("regmapgen: error: cannot read
// X: is a directory").
bool readInput(const std::string& path, std::string& text) {
  std::string why;
  if (path == "-" ? readStdin(text, &why) : readFile(path, text, &why)) return true;
  std::cerr << "regmapgen: error: cannot read " << (path == "-" ? "standard input" : path) << ": " << why
            << "\n";
  return false;
}

// Loads, builds and (unless `checked` is false) checks the files; prints diagnostics. Returns false on any
// error. Unchecked is for diff: one file of a family may name a fieldset another defines.
bool load(const std::vector<std::string>& files, Sources& sources, Model& model, bool checked = true) {
  for (const std::string& f : files) {
    std::string text;
    if (!readInput(f, text)) return false;
    sources.add(f, std::move(text));
  }
  Diagnostics diag(sources);
  model = build(sources, diag);
  if (checked) check(model, diag);
  diag.render(std::cerr);
  if (diag.errorCount() > 0 || diag.warningCount() > 0) {
    std::cerr << "regmapgen: " << diag.errorCount() << " error(s), " << diag.warningCount()
              << " warning(s)\n";
  }
  return diag.errorCount() == 0;
}

// Writes `content` to `path` unless it already holds exactly that (keeps timestamps, so the build does not
// recompile what did not change).
bool writeIfChanged(const fs::path& path, const std::string& content) {
  std::string old;
  if (readFile(path.string(), old) && old == content) return true;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
  if (!out) {
    std::cerr << "regmapgen: error: cannot write " << path.string() << "\n";
    return false;
  }
  return true;
}

int cmdCheck(const std::vector<std::string>& files) {
  Sources sources;
  Model model;
  return load(files, sources, model) ? 0 : 1;
}

int cmdList(const std::vector<std::string>& files) {
  Sources sources;
  Model model;
  if (!load(files, sources, model)) return 1;
  std::cout << emitList(model);
  return 0;
}

int cmdGenerate(const std::vector<std::string>& args) {
  std::string out, docs, stamp;
  bool docsOnly = false;
  std::vector<std::string> files;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--docs-only") {
      docsOnly = true;
    } else if ((a == "--out" || a == "--docs" || a == "--stamp") && i + 1 < args.size()) {
      (a == "--out" ? out : a == "--docs" ? docs : stamp) = args[++i];
    } else if (a.rfind("--", 0) == 0) {
      std::cerr << "regmapgen: error: unknown option " << a << "\n" << kUsage;
      return 2;
    } else {
      files.push_back(a);
    }
  }
  if ((out.empty() && !(docsOnly && !docs.empty())) || files.empty()) {
    std::cerr
        << "regmapgen: error: generate needs --out DIR (or --docs-only --docs DIR) and at least one FILE\n"
        << kUsage;
    return 2;
  }
  if (docs.empty()) docs = (fs::path(out) / "docs").string();
  Sources sources;
  Model model;
  if (!load(files, sources, model)) return 1;
  bool ok = true;
  for (const Family& fam : model.families) {
    if (!docsOnly) {
      for (const OutputFile& f : emitCode(fam, sources))
        ok = writeIfChanged(fs::path(out) / f.relativePath, f.content) && ok;
    }
    ok = writeIfChanged(fs::path(docs) / fam.name / "REFERENCE.md", emitMarkdown(fam, sources)) && ok;
  }
  if (ok && !stamp.empty()) {
    std::ofstream s(stamp, std::ios::trunc);
    s << "generated\n";
  }
  return ok ? 0 : 1;
}

// The YAML files a diff side names: the file, or every *.yaml in the folder (sorted).
std::vector<std::string> yamlFiles(const std::string& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return {path};
  std::vector<std::string> files;
  for (const auto& f : fs::directory_iterator(path, ec)) {
    if (f.path().extension() == ".yaml") files.push_back(f.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Prints a diff; the exit status: 0 same, 1 different.
int printDiff(const MapDiff& d) {
  for (const std::string& l : d.lines)
    std::cout << l << "\n";
  std::cerr << "regmapgen: " << d.added << " added, " << d.removed << " removed, " << d.changed
            << " changed, " << d.unchanged << " unchanged\n";
  return d.differs() ? 1 : 0;
}

int cmdDiff(const std::vector<std::string>& args) {
  if (args.size() != 2 || args[0].rfind("--", 0) == 0 || args[1].rfind("--", 0) == 0) {
    std::cerr << "regmapgen: error: diff takes two arguments, OLD and NEW (YAML files or folders)\n"
              << kUsage;
    return 2;
  }
  Sources oldSources, newSources;
  Model oldModel, newModel;
  if (!load(yamlFiles(args[0]), oldSources, oldModel, false) ||
      !load(yamlFiles(args[1]), newSources, newModel, false)) {
    return 2;
  }
  return printDiff(diffModels(oldModel, newModel));
}

// "--pages 3-5" or "--pages 7": first and last page, 1-based; false if malformed.
bool parsePages(const std::string& s, int& first, int& last) {
  const std::size_t dash = s.find('-');
  const std::string a = s.substr(0, dash), b = dash == std::string::npos ? a : s.substr(dash + 1);
  const auto page = [](const std::string& t, int& v) {
    if (t.empty() || t.size() > 6 || t.find_first_not_of("0123456789") != std::string::npos) return false;
    v = std::stoi(t);
    return v >= 1;
  };
  return page(a, first) && page(b, last) && first <= last;
}

int cmdImport(const std::vector<std::string>& args) {
  ImportOptions opts;
  std::string file, pages;
  std::vector<std::string> against;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const bool hasValue = i + 1 < args.size();
    if (a == "--family" && hasValue) {
      opts.family = args[++i];
    } else if (a == "--kind" && hasValue) {
      opts.kind = args[++i];
    } else if (a == "--map" && hasValue) {
      opts.mapFiles.push_back(args[++i]);
    } else if (a == "--source" && hasValue) {
      opts.source = args[++i];
    } else if (a == "--pages" && hasValue) {
      pages = args[++i];
    } else if (a == "--against" && hasValue) {
      for (const std::string& f : yamlFiles(args[++i]))
        against.push_back(f);
    } else if (a == "--help") {
      std::cout << kUsage << "\nRecognised column headings:\n" << headingHelp();
      return 0;
    } else if (a.rfind("--", 0) == 0 || !file.empty()) {
      std::cerr << "regmapgen: error: unexpected argument " << a << "\n" << kUsage;
      return 2;
    } else {
      file = a;
    }
  }
  if (file.empty()) {
    std::cerr << "regmapgen: error: import needs a FILE (or - for stdin)\n" << kUsage;
    return 2;
  }
  int first = 0, last = 0;
  if (!pages.empty() && !parsePages(pages, first, last)) {
    std::cerr << "regmapgen: error: --pages takes A-B or A (page numbers from 1, A <= B), not '" << pages
              << "'\n";
    return 2;
  }
  const int failed = against.empty() ? 1 : 2;  // with --against, 1 means "differs"
  std::string text;
  if (!readInput(file, text)) return failed;
  if (looksLikePdf(text)) {
    if (file == "-") {
      std::cerr << "regmapgen: error: a PDF must be given as a file, not on standard input\n";
      return 2;
    }
    PdfText pdf = pdfToText(file, first, last);
    if (!pdf.ok) {
      std::cerr << "regmapgen: error: " << file << ": " << pdf.error << "\n";
      return failed;
    }
    text = std::move(pdf.text);
    opts.firstPage = first > 0 ? first : 1;
  } else if (!pages.empty()) {
    std::cerr << "regmapgen: error: --pages applies to PDF input; " << file << " is text\n";
    return 2;
  }
  if (against.empty()) return runImport(file, text, opts, std::cout, std::cerr);

  std::ostringstream yaml;
  if (const int rc = runImport(file, text, opts, yaml, std::cerr); rc != 0)
    return rc == kImportFoundNoTable ? rc : 2;
  Sources oldSources, newSources;
  Model oldModel, newModel;
  if (!load(against, oldSources, oldModel, false)) return 2;
  newSources.add("(import of " + file + ")", yaml.str());
  Diagnostics diag(newSources);
  newModel = build(newSources, diag);
  if (diag.errorCount() > 0) {
    std::cerr
        << "regmapgen: the imported YAML has " << diag.errorCount()
        << " error(s) (run without --against to see it); entries with errors are compared as far as they "
           "go\n";
  }
  return printDiff(diffModels(oldModel, newModel, true));
}

int cmdCan(const std::vector<std::string>& args) {
  std::string out, dbcDir, file;
  for (size_t i = 0; i < args.size(); ++i) {
    if ((args[i] == "--out" || args[i] == "--dbc-dir") && i + 1 < args.size()) {
      (args[i] == "--out" ? out : dbcDir) = args[i + 1];
      ++i;
    } else if (!args[i].empty() && args[i][0] == '-') {
      std::cerr << "regmapgen: error: can: unknown option " << args[i] << "\n" << kUsage;
      return 2;
    } else if (file.empty()) {
      file = args[i];
    } else {
      std::cerr << "regmapgen: error: can takes one catalogue FILE\n";
      return 2;
    }
  }
  if (file.empty() || (out.empty() && dbcDir.empty())) {
    std::cerr << "regmapgen: error: can needs --out DIR (or --dbc-dir DIR) and a FILE\n" << kUsage;
    return 2;
  }
  std::string text;
  if (!readInput(file, text)) return 1;
  Sources sources;
  const int id = sources.add(file, std::move(text));
  Diagnostics diag(sources);
  const can::Catalogue cat = can::buildCatalogue(sources, id, diag);
  diag.render(std::cerr);
  if (diag.errorCount() > 0) {
    std::cerr << "regmapgen: " << diag.errorCount() << " error(s)\n";
    return 1;
  }
  const std::string source = fs::path(file).filename().string();
  bool ok = true;
  if (!out.empty()) {
    ok = writeIfChanged(fs::path(out) / "can" / (cat.name + ".hpp"), can::emitCpp(cat, source));
    ok = writeIfChanged(fs::path(out) / "can" / (cat.name + "_table.hpp"), can::emitCppTable(cat, source)) &&
         ok;
  }
  const fs::path dbc = dbcDir.empty() ? fs::path(out) / "can" : fs::path(dbcDir);
  for (const std::string& layout : cat.layouts()) {
    ok = writeIfChanged(dbc / (cat.name + "_" + layout + ".dbc"), can::emitDbc(cat, layout, source)) && ok;
  }
  ok = writeIfChanged(dbc / "REFERENCE.md", can::emitMarkdown(cat, source)) && ok;
  return ok ? 0 : 1;
}

int cmdPack(const std::vector<std::string>& args) {
  std::string regmaps, out, select, file;
  for (size_t i = 0; i < args.size(); ++i) {
    if ((args[i] == "--regmaps" || args[i] == "--out" || args[i] == "--select") && i + 1 < args.size()) {
      (args[i] == "--regmaps" ? regmaps : args[i] == "--out" ? out : select) = args[i + 1];
      ++i;
    } else if (!args[i].empty() && args[i][0] == '-') {
      std::cerr << "regmapgen: error: pack: unknown option " << args[i] << "\n" << kUsage;
      return 2;
    } else if (file.empty()) {
      file = args[i];
    } else {
      std::cerr << "regmapgen: error: pack takes one pack FILE\n";
      return 2;
    }
  }
  if (file.empty() || regmaps.empty()) {
    std::cerr << "regmapgen: error: pack needs --regmaps DIR and a FILE\n" << kUsage;
    return 2;
  }
  std::string text;
  if (!readInput(file, text)) {
    std::cerr << "regmapgen: error: cannot read " << file << "\n";
    return 1;
  }
  Sources sources;
  const int id = sources.add(file, std::move(text));
  Diagnostics diag(sources);
  const pack::PackFile p = pack::readPack(sources, id, diag);
  if (!p.name.empty() && fs::path(file).stem().string() != p.name)
    diag.error(p.nameLoc, "pack '" + p.name + "' is in " + fs::path(file).filename().string() +
                              ": the file is named after the pack (" + p.name + ".yaml)");
  // The device's register map: every YAML file of its family, built and checked as `regmapgen check` does.
  Sources mapSources;
  Model model;
  const Family* family = nullptr;
  if (const pack::DeviceSpec* dev = pack::findDevice(p.device); dev != nullptr && dev->settings) {
    std::vector<std::string> maps = yamlFiles((fs::path(regmaps) / dev->family).string());
    if (maps.size() == 1 && maps[0] == (fs::path(regmaps) / dev->family).string()) maps.clear();
    if (maps.empty()) {
      std::cerr << "regmapgen: error: no register map in " << (fs::path(regmaps) / dev->family).string()
                << "\n";
      return 1;
    }
    if (!load(maps, mapSources, model)) return 1;
    for (const Family& f : model.families) {
      if (f.name == dev->family) family = &f;
    }
  }
  pack::Resolved resolved;
  const bool ok = pack::resolvePack(p, family, resolved, diag) && diag.errorCount() == 0;
  diag.render(std::cerr);
  if (!ok) {
    std::cerr << "regmapgen: " << diag.errorCount() << " error(s)\n";
    return 1;
  }
  bool written = true;
  const std::string source = fs::path(file).filename().string();
  if (!out.empty()) {
    written = writeIfChanged(fs::path(out) / "packs" / (resolved.name + ".hpp"),
                             pack::emitPackHeader(resolved, source));
  }
  if (!select.empty()) {
    written =
        writeIfChanged(fs::path(select) / "packs" / "selected.hpp", pack::emitSelectedHeader(resolved)) &&
        written;
  }
  return written ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "help" || args[0] == "--help" || args[0] == "-h") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  const std::string cmd = args[0];
  args.erase(args.begin());
  if (cmd == "check" || cmd == "list") {
    if (args.empty()) {
      std::cerr << "regmapgen: error: " << cmd << " needs at least one FILE\n" << kUsage;
      return 2;
    }
    return cmd == "check" ? cmdCheck(args) : cmdList(args);
  }
  if (cmd == "generate") return cmdGenerate(args);
  if (cmd == "import") return cmdImport(args);
  if (cmd == "diff") return cmdDiff(args);
  if (cmd == "can") return cmdCan(args);
  if (cmd == "pack") return cmdPack(args);
  if (cmd == "schema") {
    std::cout << schemaMarkdown();
    return 0;
  }
  if (cmd == "glossary") {
    std::cout << glossaryMarkdown();
    return 0;
  }
  std::cerr << "regmapgen: error: unknown command '" << cmd << "'\n" << kUsage;
  return 2;
}
