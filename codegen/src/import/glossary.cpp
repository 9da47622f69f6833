// The Chinese -> English glossary of TI battery-monitor terms used by `regmapgen import`.
//
// Why a glossary and not a transliteration: identifiers must be the English TRM names that drivers and the
// other maps use (警报启用 is the TRM's "Alarm Enable", not "JingBaoQiYong"). Each entry is a term as TI's
// Chinese documents print it (SLUAA11B-ZH, the MSPM0 + BQ769x2 app notes) and its spelling in the English
// TRM. Longer terms win over their parts ("内部温度" is the TRM's "Int Temperature", not "Internal
// Temperature"), so whole register names that TI abbreviates are listed before the words they contain.
#include <algorithm>
#include <cctype>
#include <sstream>

#include "import/import.hpp"

namespace regmapgen {

const std::vector<std::pair<std::string, std::string>>& glossary() {
  static const std::vector<std::pair<std::string, std::string>> table = [] {
    std::vector<std::pair<std::string, std::string>> t = {
        // Whole register / parameter names.
        {"警报启用", "Alarm Enable"},
        {"警报状态", "Alarm Status"},
        {"警报原始状态", "Alarm Raw Status"},
        {"内部温度", "Int Temperature"},
        {"生产状态", "Manufacturing Status"},
        {"启用保护功能", "Enabled Protections"},
        {"启用的保护", "Enabled Protections"},
        {"安全警报", "Safety Alert"},
        {"安全状态", "Safety Status"},
        {"电池状态", "Battery Status"},
        {"控制状态", "Control Status"},
        {"器件型号", "Device Number"},
        {"固件版本", "FW Version"},
        {"硬件版本", "HW Version"},
        {"电池组电压", "Stack Voltage"},
        {"堆栈电压", "Stack Voltage"},
        {"默认警报掩码", "Default Alarm Mask"},
        {"永久失效", "PF"},
        {"永久故障", "PF"},
        // Classes and subclasses of data memory.
        {"设置", "Settings"},
        {"配置", "Configuration"},
        {"保护", "Protection"},
        {"校准", "Calibration"},
        {"电源", "Power"},
        {"安全", "Security"},
        {"制造", "Manufacturing"},
        // Words.
        {"警报", "Alarm"},
        {"启用", "Enable"},
        {"禁用", "Disable"},
        {"电压", "Voltage"},
        {"电流", "Current"},
        {"温度", "Temperature"},
        {"电池", "Cell"},
        {"电芯", "Cell"},
        {"模式", "Mode"},
        {"状态", "Status"},
        {"控制", "Control"},
        {"重置", "Reset"},
        {"复位", "Reset"},
        {"阈值", "Threshold"},
        {"延迟", "Delay"},
        {"恢复", "Recovery"},
        {"增益", "Gain"},
        {"偏移", "Offset"},
        {"引脚", "Pin"},
        {"睡眠", "Sleep"},
        {"关断", "Shutdown"},
        {"均衡", "Balancing"},
        {"充电", "Charge"},
        {"放电", "Discharge"},
        {"掩码", "Mask"},
        {"数据", "Data"},
        {"内部", "Internal"},
        {"选项", "Options"},
        {"时间", "Time"},
        {"最小", "Min"},
        {"最大", "Max"},
    };
    // Longest first, so greedy matching prefers whole names over their words.
    std::stable_sort(t.begin(), t.end(),
                     [](const auto& a, const auto& b) { return a.first.size() > b.first.size(); });
    return t;
  }();
  return table;
}

namespace {

bool asciiWordChar(unsigned char c) {
  return c < 0x80 && (std::isalnum(c) || c == '_' || c == '.');
}

}  // namespace

bool translateName(const std::string& name, std::string& out) {
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < name.size()) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (asciiWordChar(c)) {
      std::size_t j = i;
      while (j < name.size() && asciiWordChar(static_cast<unsigned char>(name[j])))
        ++j;
      words.push_back(name.substr(i, j - i));
      i = j;
      continue;
    }
    if (c < 0x80) {  // spaces and ASCII punctuation separate words
      ++i;
      continue;
    }
    bool matched = false;
    for (const auto& [zh, en] : glossary()) {
      if (name.compare(i, zh.size(), zh) == 0) {
        words.push_back(en);
        i += zh.size();
        matched = true;
        break;
      }
    }
    if (!matched) {
      // Full-width spaces and brackets are separators, anything else is an unknown term.
      static const std::string separators[] = {"\xE3\x80\x80", "\xEF\xBC\x88",
                                               "\xEF\xBC\x89"};  // U+3000 （ ）
      bool sep = false;
      for (const std::string& s : separators) {
        if (name.compare(i, s.size(), s) == 0) {
          i += s.size();
          sep = true;
        }
      }
      if (!sep) return false;
    }
  }
  out.clear();
  for (const std::string& w : words)
    out.append(out.empty() ? "" : " ").append(w);
  return !out.empty();
}

std::string glossaryMarkdown() {
  std::ostringstream md;
  md << "| Chinese | English TRM term |\n|---|---|\n";
  for (const auto& [zh, en] : glossary())
    md << "| " << zh << " | " << en << " |\n";
  return md.str();
}

}  // namespace regmapgen
