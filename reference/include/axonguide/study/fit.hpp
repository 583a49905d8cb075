#pragma once
// Calibration (docs/methods.md §12.3): fit a model's parameters to measured directional
// bias and/or radial outgrowth against concentration and steepness. Every evaluation is a
// deterministic sweep of the base scene (an explant in an imposed gradient) over the data's
// (concentration, steepness) points, every seed run with the gradient and with its mirror
// image (so that the explant's random asymmetry cancels), with the same seeds for every
// parameter set. The seed count is raised until the model's SE is below a third of the
// data's at every point. The search is a coarse logarithmic grid, then finer grids around
// the best, then Gauss-Newton steps from the grid's best; each parameter gets a
// profile-likelihood interval.
//
// Parameters by name: "gain" (guidance.gain), "kd" (every source's K_d), "scale" (a factor
// on the nominal concentrations), or a signalling parameter of kSignalTable (in its
// canonical unit: /min, /nM/min, um/min, or a count). Defaults: gain and K_d (and scale
// with fit_scale) for the SNR model; r0, kext and a1b for the signalling model.
#include <cstdint>
#include <filesystem>
#include <string>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/engine/run.hpp"

namespace axg::fit {

// What a data column measures: the directional bias (dimensionless) or the radial
// outgrowth (the scene's length unit).
enum Measure : int { kBias = 0, kOutgrowth = 1 };
inline constexpr int kMeasures = 2;
const char* measure_name(int m);  // "bias", "outgrowth"

struct DataPoint {
  double concentration;  // the scene's concentration unit (as written; corrections apply in fit)
  double steepness;      // percent per cues.imposed.reference_length
  double value[kMeasures];  // NaN where the file has no such column
  double se[kMeasures];
  std::uint64_t count;   // explants behind the mean (reported)
  std::size_t line;      // in the file
};

struct Data {
  std::vector<DataPoint> points;
  bool measured[kMeasures] = {false, false};
  int measure_count() const { return int(measured[0]) + int(measured[1]); }
};

// Reads DATA.csv: a header naming concentration, steepness, count and one or both of bias
// and outgrowth, with their SE as `se` (one measured column) or `bias_se` and
// `outgrowth_se` (both); any order; '#' lines are comments. InputError names an unknown or
// missing column and the line of any bad row.
Data load_data(const std::string& path);
// The same from the text of such a file; `origin` names it in messages.
Data parse_data(const std::string& text, const std::string& origin);

struct Parameter {
  std::string name;
  double lo = 0, hi = 0;  // the coarse grid's range (logarithmic); 0: the default range
};

// A point of parameter space: values in the order of Options::parameters (resolved).
using Params = std::vector<double>;

struct Options {
  int threads = 0;
  std::vector<std::uint64_t> seeds{1, 2, 3, 4};  // the first seeds; more are added as needed
  bool mirror = true;            // run every seed with the gradient and with its mirror image
  // The mirror image's decisions antithetic (guidance.antithetic): the pair's decision noise
  // cancels with the explant's asymmetry. Only with mirror; no effect on a model without
  // random decisions.
  bool antithetic = true;
  double target_se_ratio = 1.0 / 3.0;  // model SE / data SE to reach at every point
  std::size_t max_seeds = 64;    // the most seeds the target may ask for
  bool fit_scale = false;        // SNR default parameters: also a concentration scale
  double gain_lo = 1, gain_hi = 1000;
  double kd_lo = 0, kd_hi = 0;   // 0: from the data (min C / 10 to max C x 10)
  std::vector<Parameter> parameters;  // empty: the model's defaults
  // Concentration corrections: rows of steepness s are modelled at concentration x f.
  std::vector<std::pair<double, double>> corrections;
  std::string bias_metric;       // the assay metric a bias column is compared with; "": by model
  int coarse = 7;                // grid points per parameter, coarse round
  int refine_rounds = 2;         // each a 5-point grid per parameter over ±1 previous step
  int polish_iterations = 4;     // Gauss-Newton steps from the grid's best (0: none)
  bool profile = true;           // find each interval's ends on the profile (needs the polish)
  RunOptions run;
  // Called after every batch of parameter sets (for a progress line): the evaluations so far,
  // the lowest chi2 so far (HUGE_VAL before the first finite one). May be empty.
  std::function<void(std::size_t evaluations, double best_chi2)> on_evaluation;
};

struct Evaluation {
  Params p;
  double chi2;
  std::vector<double> model, model_se;  // per residual (point, measure)
};

// A profile-likelihood interval, cut at the minimum + delta (delta = 3.84 for 95 %, scaled
// by chi2/dof where that is above 1): each end found on the profile itself (the others
// re-fitted at each trial value, from the linearised guess of Gauss-Newton's J'WJ), or,
// without the polish, by the parabola through the grid profile's lowest value and its
// neighbours. open_low/high: the interval reaches the searched range's edge.
struct Interval {
  double best = 0;          // the grid's best value
  double lo = 0, hi = 0;    // the interval
  bool open_low = false, open_high = false;
  bool profiled = false;    // each side found on the profile itself (re-fitting the others)
};

// One residual: data point `point`'s measure `measure`.
struct Residual {
  std::size_t point;
  int measure;
};

struct Result {
  std::vector<Parameter> parameters;  // resolved ranges
  Params best;
  double chi2 = 0;
  int dof = 0;
  double chi2_per_dof = 0;
  std::string bias_metric;
  std::vector<Residual> residuals;
  std::vector<Evaluation> evaluations;  // in the order evaluated
  std::vector<double> model, model_se;  // at the best parameters, per residual
  std::vector<bool> reachable;          // within 2 se of the range the model produced
  std::vector<double> model_min, model_max;
  std::vector<Interval> intervals;      // per parameter
  double interval_delta = 0;
  std::vector<std::uint64_t> seeds;     // used for every parameter set
  double se_ratio_max = 0;              // max over residuals of model SE / data SE, at the best
  std::size_t runs = 0;
  bool polished = false;                // the Gauss-Newton polish lowered chi2
};

Result fit(const nlohmann::json& base_scene, const std::string& origin, const Data& data, const Options& options);

// The factor on the concentration of a data row of this steepness (Options::corrections;
// the last one given for it, 1 without one).
double correction_factor(const Options& options, double steepness);

// The model's mean of every measure (and its SE over seeds), mirrored as the fit runs it,
// at (concentration, steepness) points (concentrations already corrected): out[m][i].
void predict(const nlohmann::json& base_scene, const std::vector<std::pair<double, double>>& points,
             const std::vector<Parameter>& parameters, const Params& p, const Options& options,
             std::vector<double> (&mean)[kMeasures], std::vector<double> (&se)[kMeasures]);

// The parameters fit() uses for this base scene and data (Options::parameters, or the
// model's defaults), with their ranges resolved; InputError for an unknown name.
std::vector<Parameter> resolve_parameters(const nlohmann::json& base_scene, const std::string& origin,
                                          const Data& data, const Options& options);

}  // namespace axg::fit
