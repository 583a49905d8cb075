#pragma once
// Splitting one line of the CSV files the study commands read (neurons.csv, fit data), and
// reading a number from one cell.
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace axg {

// The whole of `text` as a number (strtod's syntax, nothing after it), or nothing. Not
// std::stod: it throws on a subnormal (ERANGE), which is a number.
inline std::optional<double> parse_number(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return v;
}

// s without leading and trailing spaces, tabs and CRs.
inline std::string trim_cell(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t' || s[a] == '\r')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '\r')) --b;
  return s.substr(a, b - a);
}

// The cells of one comma-separated line, each trimmed. No quoting: the files read this way
// hold numbers and plain names only.
inline std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',') {
      out.push_back(trim_cell(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(trim_cell(cur));
  return out;
}

}  // namespace axg
