#include "axonguide/validate/points_csv.hpp"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "axonguide/error.hpp"

namespace axg::validate {

PointRows read_points_csv(std::istream& in, const std::string& origin) {
  PointRows p;
  std::vector<double> row;
  std::string line, cell;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    // The cells as std::getline(..., ',') splits them: a trailing comma opens no cell.
    row.clear();
    bool numeric = true;
    for (std::size_t start = 0; start < line.size();) {
      const std::size_t comma = line.find(',', start);
      const std::size_t end = comma == std::string::npos ? line.size() : comma;
      cell.assign(line, start, end - start);
      char* stop = nullptr;
      const double v = std::strtod(cell.c_str(), &stop);
      if (stop == cell.c_str()) numeric = false;
      row.push_back(v);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (!numeric) {
      if (p.n == 0 && p.x.empty()) continue;  // a header line
      throw InputError(fmt::format("{}: line {} is not numeric", origin, line_no));
    }
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
