// Dumping the configuration as commented YAML by walking the key tables of config_schema.hpp.
// Numbers are written in shortest round-trip form, so dump -> load gives the same values.
#include <cctype>
#include <charconv>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/io/config_schema.hpp"
#include "dloam/io/config_yaml.hpp"

namespace dloam::io {

namespace {
using detail::visit;
constexpr std::size_t kCommentColumn = 44;
constexpr std::size_t kMaxWidth = 110;

std::string number(double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v);
  std::string s(buf, res.ptr);
  if (s.find_first_of(".enai") == std::string::npos) s += ".0";  // keep it a float in YAML
  return s;
}

/// True when `s` can be written unquoted: a word that YAML reads back as the same string.
bool is_plain(const std::string& s) {
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
  for (const char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) &&
        std::string_view("_./+-").find(c) == std::string_view::npos)
      return false;
  std::string lower;
  for (const char c : s) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* special : {"true", "false", "yes", "no", "on", "off", "null", "y", "n"})
    if (lower == special) return false;
  return true;
}

/// A string as YAML reads it back unchanged: plain when it can be, else double-quoted with `"`, `\\`
/// and control characters escaped (bytes from 0x80 up are written as they are).
std::string text(const std::string& s) {
  if (is_plain(s)) return s;
  std::string quoted = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (u < 0x20 || u == 0x7f) {
      static constexpr char kHex[] = "0123456789abcdef";
      quoted += "\\x";
      quoted += kHex[u >> 4];
      quoted += kHex[u & 0xf];
    } else {
      quoted += c;
    }
  }
  return quoted + '"';
}

std::string value(bool v) { return v ? "true" : "false"; }
std::string value(int v) { return std::to_string(v); }
std::string value(double v) { return number(v); }
std::string value(const std::string& v) { return text(v); }
template <class E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
std::string value(E v) {
  return std::string(name_of(v));
}
std::string value(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + number(v[i]);
  return s + "]";
}

/// Writes `key: value  # doc` lines, indented inside groups.
struct Dumper {
  std::ostringstream& out;
  std::string indent;
  std::string only_section;  ///< empty: every group
  bool found = false;

  /// One `key: value  # doc` line. A line too long for the comment beside it gets the comment
  /// above; a list (`wrap`) is then also wrapped after its commas, anything else stays one line.
  void line(const std::string& body, const char* doc, bool wrap = false) {
    std::string l = indent + body;
    if (l.size() + 2 < kCommentColumn + 40) {
      l += std::string(l.size() < kCommentColumn ? kCommentColumn - l.size() : 1, ' ');
      out << l << "# " << doc << '\n';
      return;
    }
    out << indent << "# " << doc << '\n';
    std::size_t start = 0;
    while (wrap && l.size() - start > kMaxWidth) {
      const std::size_t cut = l.rfind(", ", start + kMaxWidth - 1);
      if (cut == std::string::npos || cut <= start) break;  // one item longer than a line
      out << l.substr(start, cut + 1 - start) << '\n';
      start = cut + 2;
      l.insert(start, indent + "    ");
    }
    out << l.substr(start) << '\n';
  }
  template <class T, class Constraint>
  void operator()(const char* key, T& field, const char* doc, const Constraint&) {
    if (!only_section.empty() && indent.empty()) return;
    if (indent.empty() && !out.str().empty()) out << '\n';
    line(std::string(key) + ": " + value(field), doc, std::is_same_v<T, std::vector<double>>);
  }
  template <class S>
  void group(const char* key, S& s, const char* doc) {
    if (!only_section.empty() && only_section != key) return;
    found = true;
    if (!out.str().empty()) out << '\n';
    line(std::string(key) + ":", doc);
    Dumper sub{out, indent + "  ", "", false};
    visit(s, sub);
  }
};
}  // namespace

std::string dump_config(const PipelineConfig& config, const std::string& section) {
  std::ostringstream out;
  if (section.empty()) {
    out << "# dloam configuration: every parameter of the DLOAM pipeline, named as in the paper.\n"
           "# `sensor: {preset: NAME}` starts the sensor section from a built-in model (`dloam config\n"
           "# presets` lists them) or from the model estimated from the data (`auto`); keys given beside it\n"
           "# override. Keys left out keep these defaults; unknown keys are errors. Print the effective\n"
           "# configuration with `dloam config dump`.\n";
  }
  PipelineConfig c = config;  // visit() takes non-const references
  Dumper dumper{out, "", section, false};
  visit(c, dumper);
  if (!section.empty() && !dumper.found) throw InputError("config: unknown section '" + section + "'");
  return out.str();
}

}  // namespace dloam::io
