#pragma once
// Calibration of an arbour scene on morphometric data (issue 41; docs/methods.md §12.8):
// `axonguide fit DATA --scene S --out DIR` when DATA has the columns of
// ../shared/data/ramakers-culture/development.csv (statistic, age_days, n, mean, sd, se).
//
// The model at an age is the scene run to that age (steps = age / dt) for each seed, its
// arbours measured as the data were (morphology/morphometry.hpp; in xy projection for a
// culture on a disc). A statistic's residual is (model mean - data mean) / sqrt(se_data^2 +
// se_model^2). The statistics of one age are correlated (lengths, counts and their ratios;
// terminal segments - branch points is the stem count), so the chi^2 of an age is
// r^T R^-1 r over two blocks: the six per-neuron statistics (the axon's five and the number
// of dendrites) and the five per-dendrite ones, with R the correlation between those
// statistics over the model's neurons (dendrites) at the starting parameters, shrunk 5 %
// toward the identity; ages are independent cultures. Parameters are fitted in log space
// by Levenberg-Marquardt with forward differences on common random numbers (the same seeds
// for every parameter set); intervals are profiles (the other parameters refitted at each
// value) where asked, otherwise the curvature's.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "axonguide/scene/scene.hpp"

namespace axg::morphofit {

struct DataRow {
  std::string statistic;
  double age_days = 0;
  double n = 0, mean = 0, sd = 0, se = 0;
};

// True when the file's header is the morphometric data's.
bool is_morphometric_data(const std::string& path);
// Reads the rows; InputError (exit 2) naming the file and line for a malformed one, a
// statistic axonguide morphometry does not compute, or an se that is not positive.
std::vector<DataRow> load_data(const std::string& path);

// A fitted parameter: "axon.B", "axon.E", "axon.S", "axon.tau", "axon.v0", "axon.F",
// "axon.rate_cv", "axon.stem_rate", the same for "dendrites.", all > 0 (fitted in log).
struct Parameter {
  std::string name;
  double lo = 0, hi = 0;  // bounds (0: none beyond > 0)
};
const std::vector<std::string>& parameter_names();
double get_parameter(const Scene& s, const std::string& name);
void set_parameter(Scene& s, const std::string& name, double value);

struct Options {
  std::vector<Parameter> parameters;  // empty: the default eight
  std::vector<std::uint64_t> seeds{1, 2};
  int iterations = 12;                // Levenberg-Marquardt steps at most
  bool profile = false;               // profile intervals (else the curvature's)
  int profile_points = 3;             // values each side of the best, per parameter
  std::vector<double> predict_days{7, 14, 21};
  int predict_draws = 40;             // parameter sets drawn from the fit's covariance for the prediction CI
  std::function<void(const std::string&)> on_progress;
};

struct ModelRow {
  std::string statistic;
  double age_days = 0;
  double n = 0, mean = 0, se = 0;
};

struct Residual {
  DataRow data;
  ModelRow model;
  double z = 0;  // (model - data) / sqrt(se_d^2 + se_m^2)
};

struct Interval {
  std::string name;
  double start = 0, best = 0, lo = 0, hi = 0;
  std::string method;  // "profile" or "curvature"
};

struct Prediction {
  std::string statistic;
  double age_days = 0;
  double mean = 0, lo = 0, hi = 0;  // the best fit's mean; 2.5 and 97.5 percentiles over drawn parameter sets
};

struct Result {
  std::vector<Interval> parameters;
  std::vector<Residual> residuals;
  double chi2 = 0, chi2_diagonal = 0;  // correlated (the fit's), and ignoring correlations
  int dof = 0;
  int evaluations = 0;
  double seconds = 0;
  std::vector<Prediction> predictions;
  int refused_draws = 0;  // drawn parameter sets whose arbours would not fit in memory (left out)
  Scene best;
};

Result fit(const Scene& base, const std::vector<DataRow>& data, const Options& options);

// The model's population statistics at an age over the seeds (every statistic, in
// morphology::statistic_names() order): what the fit compares with the data.
std::vector<ModelRow> model_at(const Scene& base, double age_days, const std::vector<std::uint64_t>& seeds);

// Writes DIR/fit.json (parameters, chi^2, dof, how correlations were treated), residuals.csv,
// predictions.csv and scene.json (the fitted scene).
void write_result(const Result& r, const std::string& dir);

}  // namespace axg::morphofit
