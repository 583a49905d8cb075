#include "axonguide/validate/points_csv.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "axonguide/io/csv.hpp"
#include "axonguide/support/error.hpp"

namespace axg::validate {

PointRows read_points_csv(std::istream& in, const std::string& origin) {
  PointRows p;
  std::vector<double> row;
  std::string line;
  std::size_t line_no = 0;
  bool first = true;  // the first line that is not blank or a comment: it may be a header
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF
    if (line.empty() || line[0] == '#') continue;
    // The cells as std::getline(..., ',') splits them: a trailing comma opens no cell. Each
    // is a whole number (spaces around it allowed), or the line is not numeric.
    row.clear();
    std::size_t numbers = 0, cells = 0;
    for (std::size_t start = 0; start < line.size();) {
      const std::size_t comma = line.find(',', start);
      const std::size_t end = comma == std::string::npos ? line.size() : comma;
      const std::string cell = trim_cell(line.substr(start, end - start));
      ++cells;
      if (const std::optional<double> v = parse_number(cell)) {
        row.push_back(*v);
        ++numbers;
      }
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    const bool header = first && numbers == 0;
    first = false;
    if (header) continue;
    if (numbers != cells) throw InputError(fmt::format("{}: line {} is not numeric (every cell a number)", origin, line_no));
    if (p.d < 0) p.d = static_cast<int>(row.size());
    if (static_cast<int>(row.size()) != p.d)
      throw InputError(
          fmt::format("{}: line {} has {} columns, the first row had {}", origin, line_no, row.size(), p.d));
    for (double v : row)
      if (!std::isfinite(v)) throw InputError(fmt::format("{}: line {} has a non-finite value", origin, line_no));
    p.x.insert(p.x.end(), row.begin(), row.end());
    ++p.n;
  }
  return p;
}

}  // namespace axg::validate
