// `validate samplers --points FILE.csv`: a point set made elsewhere passes when uniform
// and fails (exit 1, naming the test) when not; malformed files are refused (exit 2).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "axonguide/support/error.hpp"
#include "axonguide/validate/points_csv.hpp"

#include "axonguide/core/random.hpp"
#include "axonguide/core/sampler.hpp"
#include "support.hpp"

namespace axg {
namespace {

int run(const std::string& args, std::string* err) {
  test::TempDir tmp;
  const auto e = tmp.path() / "err.txt";
  const int status = std::system(fmt::format("{} {} > /dev/null 2> {}", test::binary(), args, e.string()).c_str());
  *err = test::read_file(e);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(points, UniformPassesNaiveFailsGarbageIsRefused) {
  test::TempDir tmp;
  {
    std::ofstream uniform(tmp.path() / "uniform.csv"), naive(tmp.path() / "naive.csv"), ball(tmp.path() / "ball.csv");
    uniform << "x,y,z\n";
    for (std::uint64_t i = 0; i < 3000; ++i) {
      core::Rng rng(77, core::Stream::kValidation, i, 900);
      const core::Vec3 v = core::direction_normal(rng);
      uniform << fmt::format("{},{},{}\n", v.x, v.y, v.z);
      const core::Vec3 b = 2.0 * core::unit_ball_rejection(rng);
      ball << fmt::format("{},{},{}\n", b.x, b.y, b.z);
      const double theta = 3.141592653589793 * rng.uniform(), phi = 6.283185307179586 * rng.uniform();
      naive << fmt::format("{},{},{}\n", std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
    std::ofstream(tmp.path() / "ragged.csv") << "1,0,0\n0,1\n";
  }
  const std::string report = (tmp.path() / "r").string();
  std::string err;
  EXPECT_EQ(run(fmt::format("validate samplers --points {}/uniform.csv --report {}", tmp.path().string(), report), &err), 0)
      << err;
  EXPECT_EQ(run(fmt::format("validate samplers --points {}/ball.csv --radius 2 --report {}", tmp.path().string(), report),
                &err),
            0)
      << err;
  EXPECT_EQ(run(fmt::format("validate samplers --points {}/naive.csv --report {}", tmp.path().string(), report), &err), 1);
  EXPECT_NE(err.find("FAILED"), std::string::npos) << err;
  EXPECT_EQ(run(fmt::format("validate samplers --points {}/ragged.csv --report {}", tmp.path().string(), report), &err), 2);
  EXPECT_NE(err.find("line 2 has 2 columns"), std::string::npos) << err;
  EXPECT_EQ(run(fmt::format("validate samplers --points {}/ball.csv --report {}", tmp.path().string(), report), &err), 2);
  EXPECT_NE(err.find("beyond --radius 1"), std::string::npos) << err;
}

// The reader alone (what the fuzzer drives): one header line at most (the first, with no
// number in it), comments, blank lines (CRLF ones too), a trailing comma (no empty cell), and
// every cell a whole number: "1.0junk" and "9abc" were read as 1 and 9 before, and a second
// non-numeric line was dropped as another header.
TEST(points, ReaderKeepsItsRules) {
  auto read = [](const std::string& text) {
    std::istringstream in(text);
    return validate::read_points_csv(in, "--points f.csv");
  };
  auto refusal = [&](const std::string& text) {
    try {
      read(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const validate::PointRows p = read("x,y,z\n# comment\n\r\n1,2,3\r\n4, 5,6,\n 7e0,0x8,9\n");
  EXPECT_EQ(p.n, 3u);
  EXPECT_EQ(p.d, 3);
  EXPECT_EQ(p.x, (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(read("").d, -1);
  EXPECT_EQ(read("a\n").n, 0u);
  const std::string numeric = " is not numeric (every cell a number)";
  EXPECT_EQ(refusal("a\nb\n"), "--points f.csv: line 2" + numeric);
  EXPECT_EQ(refusal("x,y,z\nname,,\n1,2,3\n"), "--points f.csv: line 2" + numeric);
  EXPECT_EQ(refusal("1,2\n3,x\n"), "--points f.csv: line 2" + numeric);
  EXPECT_EQ(refusal("1,2\n3,,4\n"), "--points f.csv: line 2" + numeric);
  EXPECT_EQ(refusal("1.0junk,0\n"), "--points f.csv: line 1" + numeric);
  EXPECT_EQ(refusal("1,2\n3,9abc\n"), "--points f.csv: line 2" + numeric);
  EXPECT_EQ(refusal("5,,7\n1,2,3\n"), "--points f.csv: line 1" + numeric);
  EXPECT_EQ(refusal("1,2\n\n3\n"), "--points f.csv: line 3 has 1 columns, the first row had 2");
  EXPECT_EQ(refusal("1,2\n3,nan\n"), "--points f.csv: line 2 has a non-finite value");
  EXPECT_EQ(refusal("1,1e999\n"), "--points f.csv: line 1 has a non-finite value");
  EXPECT_EQ(refusal(std::string("1,2\n3\0x,4\n", 10)), "--points f.csv: line 2" + numeric);  // not cut at the NUL
}

}  // namespace
}  // namespace axg
