#include "tune/text_edit.hpp"

#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace tiller::tune {

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> out;
  std::string line;
  std::istringstream in(text);
  while (std::getline(in, line)) out.push_back(line);
  return out;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

namespace {

// "  key: rest" -> indent 2, key "key"; false for blank, comment or sequence lines.
bool key_of(const std::string& line, int& indent, std::string& key) {
  std::size_t i = line.find_first_not_of(' ');
  if (i == std::string::npos || line[i] == '#' || line[i] == '-') return false;
  const std::size_t colon = line.find(':', i);
  if (colon == std::string::npos) return false;
  key = line.substr(i, colon - i);
  if (key.find_first_of(" {[\"'") != std::string::npos) return false;
  indent = static_cast<int>(i);
  return true;
}

// The position of a trailing comment (" #" outside brackets and quotes), or npos.
std::size_t comment_at(const std::string& s, std::size_t from) {
  bool quote = false;
  for (std::size_t i = from; i < s.size(); ++i) {
    if (s[i] == '"' || s[i] == '\'') quote = !quote;
    if (!quote && s[i] == '#' && i > 0 && s[i - 1] == ' ') return i;
  }
  return std::string::npos;
}

std::string path_text(const std::vector<std::string>& path) {
  std::string s;
  for (const auto& p : path) s += (s.empty() ? "" : ".") + p;
  return s;
}

}  // namespace

int find_key_line(const std::vector<std::string>& lines, const std::vector<std::string>& path) {
  std::vector<std::pair<int, std::string>> stack;  // (indent, key) of the open maps
  for (std::size_t n = 0; n < lines.size(); ++n) {
    int indent = 0;
    std::string key;
    if (!key_of(lines[n], indent, key)) continue;
    while (!stack.empty() && stack.back().first >= indent) stack.pop_back();
    stack.emplace_back(indent, key);
    if (stack.size() != path.size()) continue;
    bool same = true;
    for (std::size_t k = 0; k < path.size(); ++k) same &= stack[k].second == path[k];
    if (same) return static_cast<int>(n);
  }
  return -1;
}

void set_value(std::vector<std::string>& lines, const std::vector<std::string>& path,
               const std::string& value, const std::string& flow_key) {
  const int n = find_key_line(lines, path);
  if (n < 0) throw std::runtime_error("no key " + path_text(path) + " in the file");
  std::string& line = lines[static_cast<std::size_t>(n)];
  const std::size_t colon = line.find(':', line.find_first_not_of(' '));
  if (flow_key.empty()) {
    std::size_t start = line.find_first_not_of(' ', colon + 1);
    if (start == std::string::npos) start = line.size();
    const std::size_t end = comment_at(line, start);
    if (end == std::string::npos) {
      line = line.substr(0, start) + value;
    } else {  // the comment stays in its column when the new value leaves room
      const std::string comment = line.substr(end);
      line = line.substr(0, start) + value;
      line += std::string(line.size() + 1 < end ? end - line.size() : 1, ' ') + comment;
    }
    return;
  }
  const std::regex re("([{,]\\s*" + flow_key + ":\\s*)([^,}\\s]+)");
  std::smatch m;
  const std::string rest = line.substr(colon);
  if (!std::regex_search(rest, m, re))
    throw std::runtime_error("no key " + flow_key + " in " + path_text(path) + "'s flow map");
  const std::size_t at = colon + static_cast<std::size_t>(m.position(2));
  line.replace(at, static_cast<std::size_t>(m.length(2)), value);
}

std::string unified_diff(const std::string& name, const std::vector<std::string>& before,
                         const std::vector<std::string>& after) {
  const std::size_t n = std::min(before.size(), after.size());
  std::vector<std::size_t> changed;
  for (std::size_t i = 0; i < n; ++i)
    if (before[i] != after[i]) changed.push_back(i);
  if (changed.empty()) return "";
  std::string out = "--- a/" + name + "\n+++ b/" + name + "\n";
  constexpr std::size_t kContext = 3;
  std::size_t k = 0;
  while (k < changed.size()) {
    // A hunk: changes closer than twice the context join.
    std::size_t last = k;
    while (last + 1 < changed.size() && changed[last + 1] - changed[last] <= 2 * kContext) ++last;
    const std::size_t from = changed[k] >= kContext ? changed[k] - kContext : 0;
    const std::size_t to = std::min(n, changed[last] + kContext + 1);
    const std::size_t len = to - from;
    out += "@@ -" + std::to_string(from + 1) + "," + std::to_string(len) + " +" +
           std::to_string(from + 1) + "," + std::to_string(len) + " @@\n";
    for (std::size_t i = from; i < to; ++i) {
      if (before[i] == after[i]) {
        out += " " + before[i] + "\n";
      } else {
        out += "-" + before[i] + "\n";
      }
      // Removed and added lines of one change together.
      if (before[i] != after[i]) out += "+" + after[i] + "\n";
    }
    k = last + 1;
  }
  return out;
}

std::string format_number(double v) {
  char buf[32];
  if (v == 0) return "0";
  const double a = std::fabs(v);
  if (a >= 1e-3 && a < 1e6) {
    const int digits = std::max(0, 3 - static_cast<int>(std::floor(std::log10(a))));
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    std::string s = buf;
    if (s.find('.') != std::string::npos) {
      s.erase(s.find_last_not_of('0') + 1);
      if (s.back() == '.') s.pop_back();
    }
    return s;
  }
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace tiller::tune
