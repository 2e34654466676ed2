// Identification (NLopt): fit uncertain parameters of the two-point rub model so that the jump
// speeds and whip frequencies it predicts match given targets.
//
// A target is one feature of the L1 branch set: at the event labelled `event_label` (a substring
// of the special point's name, e.g. "stick to slip+") on a branch of the closed-form family
// `pattern` ("mode1", "mode2", ...), the running speed [rpm] or the precession [Hz]. The model's
// prediction for a target is the matching event nearest to the target value. Residuals are
// r_i = (predicted_i − target_i) / scale_i, with scale_i the target's uncertainty (same unit), and
// the objective is J(θ) = Σ r_i². A target without any matching event at θ (the event disappeared:
// e.g. the branch no longer switches in the speed range) gives a residual of kMissingResidual, so
// the optimizers steer away from it, and is reported.
//
// Method: a derivative-free global search over the box of the parameters (normalized to [0, 1]ᵈ),
// then a local refinement (NLopt LN_BOBYQA; Nelder–Mead for one parameter). Every evaluation
// computes a branch set (~30–80 ms for the thesis cases). The global search is one of
//   - NLopt GN_DIRECT_L (the default) or GN_CRS2_LM: one evaluation at a time, each chosen from the
//     ones before, so they cannot be shared out; one local refinement from their best point;
//   - multistart: a population of global_evaluations points of a shifted Halton sequence (a
//     low-discrepancy design: the box covered evenly at every size; the shift from random_seed),
//     all evaluated at once, then local refinements from the local_starts best points that lie
//     apart (normalized distance ≥ 0.1), the best refinement kept. The population and the
//     refinements are independent jobs: they are shared out over threads and MPI ranks.
// The sensitivities below are a batch of independent evaluations for every method.
// Decision: a population method of our own rather than NLopt's MLSL or ISRES, whose evaluations,
// though of a population, are requested one at a time through the objective callback. The answer
// does not depend on how many threads or ranks share the work (each job's result depends on its
// index alone, and the reductions run in index order).
//
// How well each parameter is determined: the Gauss–Newton covariance (JᵣᵀJᵣ)⁻¹ of the fitted
// parameters, Jᵣ = ∂r/∂θ by central differences at the fit (a standard deviation per parameter in
// its own unit when the scales are 1-σ uncertainties), the correlation between them, and the
// relative rise of the objective for a ±1 % change of each parameter.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "waves/rotating_wave_branches.h"
#include "waves/rotating_wave_parameters.h"

namespace rubcont {

enum class TargetQuantity {
  kSpeedRpm,     // running speed of the event [rpm]
  kPrecessionHz, // precession (whirl / whip frequency) at the event [Hz]
};
const char* ToString(TargetQuantity quantity);

struct IdentificationTarget {
  std::string pattern = "mode1";       // branch family (PatternName)
  std::string event_label;             // substring of the event's label, e.g. "stick to slip+"
  TargetQuantity quantity = TargetQuantity::kSpeedRpm;
  double value = 0.0;                  // target [rpm or Hz], finite
  double scale = 1.0;                  // its uncertainty [same unit] > 0
  // "mode1 stick to slip+ speed_rpm" (for reports).
  std::string Name() const;
};

struct FitParameter {
  DesignParameter parameter = DesignParameter::kFriction;
  double lower = 0.0;  // search box, inside the physical range, lower < upper
  double upper = 0.0;
};

enum class GlobalMethod { kDirectL, kCrs2, kMultiStart };
const char* ToString(GlobalMethod method);  // "direct_l", "crs2", "multistart"

struct IdentificationOptions {
  RotatingWaveBranchOptions branches;  // speed range of the branch sets (search.speed_min/max)
  GlobalMethod global = GlobalMethod::kDirectL;
  int global_evaluations = 120;        // NLopt maxeval of the global stage, or the population (≥ 1)
  int local_evaluations = 200;         // maxeval of each local refinement (≥ 1)
  int local_starts = 4;                // multistart: refinements from the best points (≥ 1)
  double local_xtol = 1e-9;            // LN_BOBYQA xtol_rel on the normalized parameters (> 0)
  // The fit reproduces the targets when every |r_i| ≤ this (> 0): with 1-σ scales, 3 means
  // "within three uncertainties". Otherwise the status is kTargetsNotReproduced.
  double residual_tolerance = 3.0;
  // Relative step of the central differences for the sensitivities (of the box width, > 0).
  double sensitivity_step = 1e-4;
  unsigned random_seed = 1;            // NLopt's seed (CRS2 is stochastic)
};

// Residual given to a target whose event is missing at θ.
constexpr double kMissingResidual = 1e3;

enum class IdentificationStatus {
  kFitted,                // converged, every residual within residual_tolerance
  kTargetsNotReproduced,  // converged, but some residual is larger: no parameters in the box
                          // reproduce the targets (inconsistent or infeasible targets)
  kFeatureMissing,        // at the best point some target has no matching event
  kFailed,                // NLopt failed (the message says how)
};
const char* ToString(IdentificationStatus status);

struct IdentificationResult {
  IdentificationStatus status = IdentificationStatus::kFailed;
  std::vector<double> parameters;         // θ at the fit (parameter units)
  std::vector<double> global_parameters;  // θ after the global stage
  double objective = 0.0;                 // J(θ) = Σ r_i²
  double global_objective = 0.0;
  std::vector<double> predicted;          // per target, NaN where missing
  std::vector<double> residuals;          // r_i
  std::vector<bool> missing;
  int global_evaluations = 0;
  int local_evaluations = 0;              // over all refinements
  int local_runs = 0;                     // refinements run (1 unless multistart)
  int global_nlopt_result = 0;            // nlopt::result codes (global: 0 for multistart, not NLopt)
  int local_nlopt_result = 0;
  double seconds = 0.0;
  // Sensitivity at the fit.
  std::vector<double> standard_deviation;   // sqrt(diag((JᵣᵀJᵣ)⁻¹)) [parameter units]; ∞ if singular
  std::vector<std::vector<double>> correlation;
  std::vector<double> objective_rise;       // J(θ ± 1 % θ_k) − J(θ), the larger of the two
  std::string message;                      // one sentence with numbers

  bool Fitted() const { return status == IdentificationStatus::kFitted; }
};

// Throws std::invalid_argument naming the field, value and rule: no targets or parameters, a box
// outside the physical range or inverted, a non-finite target, a non-positive scale, invalid
// options, an unknown pattern name.
void Validate(const std::vector<IdentificationTarget>& targets,
              const std::vector<FitParameter>& parameters, const IdentificationOptions& options);

// The model's prediction of each target at `params` (NaN where no event matches).
std::vector<double> PredictTargets(const TwoPointParams& params,
                                   const std::vector<IdentificationTarget>& targets,
                                   const RotatingWaveBranchOptions& options);

// Runs job(i) for i = 0 … n − 1 and returns every result, in index order, to every caller. The
// fit's batches of independent evaluations go through one.
using BatchRunner = std::function<std::vector<std::vector<double>>(
    int n, const std::function<std::vector<double>(int)>& job)>;

// The batches run over `threads` threads of this process (ParallelFor).
BatchRunner ThreadBatchRunner(int threads);

// Fits `parameters` of `params` (the other values stay as given) to the targets; the batches of
// independent evaluations run through `batches` (empty: in this thread). Progress: one line per
// stage ("population of 120 evaluated: best J = 3.2", ...), from the calling thread.
IdentificationResult Identify(const TwoPointParams& params,
                              const std::vector<IdentificationTarget>& targets,
                              const std::vector<FitParameter>& parameters,
                              const IdentificationOptions& options = {},
                              const BatchRunner& batches = {},
                              const std::function<void(const std::string&)>& progress = {});

}  // namespace rubcont
