#pragma once
// Calibration (docs/methods.md §12.3): fit the SNR model's gain α and the sources' K_d
// (and, optionally, a scale on the nominal concentrations) to measured directional bias
// against concentration and steepness. Every evaluation is a deterministic sweep of the
// base scene (an imposed-gradient explant) over the data's (concentration, steepness)
// points; the search is a coarse logarithmic grid, then finer grids around the best.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/run.hpp"

namespace axg::fit {

struct DataPoint {
  double concentration;  // the scene's concentration unit
  double steepness;      // percent per cues.imposed.reference_length
  double bias, se;
  std::uint64_t count;   // explants behind the mean (reported)
  std::size_t line;      // in the file
};

// Reads DATA.csv: a header naming the columns concentration, steepness, bias, se, count
// (any order; '#' lines are comments). InputError names the line of any bad row.
std::vector<DataPoint> load_data(const std::string& path);
// The same from the text of such a file; `origin` names it in messages.
std::vector<DataPoint> parse_data(const std::string& text, const std::string& origin);

struct Params {
  double gain, kd, scale;
};

struct Options {
  int threads = 0;
  std::vector<std::uint64_t> seeds{1, 2, 3, 4};
  bool fit_scale = false;
  double gain_lo = 1, gain_hi = 1000;
  double kd_lo = 0, kd_hi = 0;  // 0: from the data (min C / 10 to max C x 10)
  int coarse = 7;               // grid points per parameter, coarse round
  int refine_rounds = 2;        // each a 5-point grid per parameter over ±1 previous step
  RunOptions run;
};

struct Evaluation {
  Params p;
  double chi2;
  std::vector<double> model, model_se;  // per data point
};

struct Result {
  Params best;
  double chi2 = 0;
  int dof = 0;
  double chi2_per_dof = 0;
  std::vector<Evaluation> evaluations;  // in the order evaluated
  std::vector<double> model, model_se;  // at the best parameters
  std::vector<bool> reachable;          // within 2 se of the range the model produced
  std::vector<double> model_min, model_max;
  std::size_t runs = 0;
};

Result fit(const nlohmann::json& base_scene, const std::string& origin, const std::vector<DataPoint>& data,
           const Options& options);

// The model's mean bias (and its SE over seeds) at the given points and parameters.
void predict(const nlohmann::json& base_scene, const std::vector<std::pair<double, double>>& points, const Params& p,
             const Options& options, std::vector<double>& mean, std::vector<double>& se);

}  // namespace axg::fit
