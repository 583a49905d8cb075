#pragma once
// The point files of `validate samplers --points FILE`: one point a line, its coordinates
// separated by commas. Kept apart from the tests so that the fuzzer reaches it alone.
#include <cstddef>
#include <istream>
#include <string>
#include <vector>

namespace axg::validate {

struct PointRows {
  std::vector<double> x;  // n rows of d coordinates, row-major
  std::size_t n = 0;
  int d = -1;             // -1: no row
};

// Reads every line: blank lines and lines starting with '#' are skipped, and so are lines
// that are not numeric before the first numeric one (a header). A cell is read by strtod
// (leading blanks and trailing characters after the number are ignored). Throws InputError
// "<origin>: line L ..." for a later non-numeric line, a row whose column count differs
// from the first row's, or a non-finite value.
PointRows read_points_csv(std::istream& in, const std::string& origin);

}  // namespace axg::validate
