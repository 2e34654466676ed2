// Lifetimes of transient states (level L3): escape rates from ensembles of copies and the crisis
// law that locates where a chaotic attractor ends.
//
// A chaotic attractor that collides with the boundary of its basin (a boundary crisis, Grebogi,
// Ott & Yorke 1983) leaves a chaotic saddle behind: past the critical parameter p_c a trajectory
// stays near it for a random time with an exponential distribution, P(t > T) = exp(−κ T), whose
// escape rate grows from zero as a power law, κ = A (p − p_c)^γ. An ensemble of perturbed copies at
// one parameter value (sweeps/ensemble.h) gives a sample of such times; copies still on the state
// at the end of the run are right-censored, and the times are known only to the stretch in which
// the copy was seen to arrive: the likelihood below is that of an exponential observed in
// intervals, with censoring. A speed at which every copy leaves in its first stretch bounds κ only
// from below; a speed at which none leaves, only from above; both still count in the crisis fit.
//
// What a fit cannot say is reported as a status (too few speeds; rates that rise without a
// critical point in range, where an exponential law in p fits as well), never a number.
#pragma once

#include <string>
#include <vector>

namespace rubcont {

// The copies of one ensemble at one parameter value. A copy that escaped was first seen out of the
// state in stretch j = 1, 2, …: its escape time lies in ((j − 1)·stretch, j·stretch].
struct EscapeObservations {
  double parameter = 0.0;
  double stretch = 0.0;             // > 0 [s]
  double duration = 0.0;            // ≥ stretch [s]: how long the copies that stayed were run
  std::vector<int> escape_stretch;  // j of each copy that escaped (1 … duration/stretch)
  int stayed = 0;                   // copies still in the state at `duration`
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const EscapeObservations& observations);

// The copies' time in the state, the exposure of the rate's likelihood [s]: `stayed` × duration
// plus (j − 1)·stretch for each copy that escaped in stretch j (its escape time's lower bound).
double Exposure(const EscapeObservations& observations);

// Log-likelihood of an escape rate κ ≥ 0 (κ = +∞ allowed: 0 when every copy left in stretch 1).
double EscapeLogLikelihood(const EscapeObservations& observations, double rate);

enum class EscapeRateStatus {
  kEstimated,      // 0 < κ < ∞, with both limits
  kNoEscape,       // no copy left: κ = 0, upper limit only
  kAllImmediate,   // every copy left in its first stretch: κ = ∞, lower limit only
};
const char* ToString(EscapeRateStatus status);

struct EscapeRate {
  EscapeRateStatus status = EscapeRateStatus::kEstimated;
  double rate = 0.0;    // maximum-likelihood κ [1/s]
  double lower = 0.0;   // likelihood-ratio 95 % interval (Wilks: a drop of 1.92)
  double upper = 0.0;
  int escapes = 0;
  int copies = 0;
};

// κ = ln(1 + d·Δ/E)/Δ, E = Σ (j − 1)·Δ + stayed·duration: the closed-form maximum of the
// interval-censored likelihood (d escapes, stretch Δ); its limits by bisection.
EscapeRate EstimateEscapeRate(const EscapeObservations& observations);
// The same for several groups of copies at one parameter value with one stretch (e.g. ensembles run
// for different durations): their likelihoods add, E and d are summed. Throws
// std::invalid_argument when the groups differ in parameter or stretch, or there are none.
EscapeRate EstimateEscapeRate(const std::vector<EscapeObservations>& groups);

// The direction in which the state ceases to exist: kAbove, κ = A (p − p_c)^γ for p > p_c and 0
// below (the end of a speed-up whip); kBelow, the mirror image.
enum class CrisisSide { kAbove, kBelow };

enum class CrisisStatus {
  kLocated,         // p_c inside the range, with its profile-likelihood interval
  kTooFewSpeeds,    // fewer than two parameter values with escapes, or none without κ = ∞
  kNotBracketed,    // the best p_c lies at the end of the search range: no critical point found
  kFailed,          // the optimizer failed (message)
};
const char* ToString(CrisisStatus status);

struct CrisisOptions {
  CrisisSide side = CrisisSide::kAbove;
  // p_c is searched within `search_range` × (the span of the parameter values) beyond the
  // escaping value nearest the state; reaching that end is kNotBracketed.
  double search_range = 2.0;
  double min_exponent = 0.05;
  double max_exponent = 20.0;
};

struct CrisisFit {
  CrisisStatus status = CrisisStatus::kFailed;
  std::string message;
  double critical = 0.0;        // p_c
  double critical_lower = 0.0;  // profile-likelihood 95 % interval of p_c (a drop of 1.92);
  double critical_upper = 0.0;  // an end that is not reached is the search range's, flagged below
  bool lower_bounded = false;
  bool upper_bounded = false;
  double exponent = 0.0;        // γ
  double amplitude = 0.0;       // A, in 1/s per (parameter unit)^γ
  double log_likelihood = 0.0;
  int evaluations = 0;
};

// Maximum likelihood over (p_c, γ, ln A), all observations together (NLopt BOBYQA from several
// starts), then the profile of p_c by bisection of the likelihood ratio.
CrisisFit FitCrisis(const std::vector<EscapeObservations>& observations, const CrisisOptions& options = {});

// κ at p by the fitted law (0 on the side where the state exists).
double CrisisRate(const CrisisFit& fit, CrisisSide side, double parameter);

// A sweep through `parameters` (in order) that stays `dwell` seconds at each, starting on the state:
// the probability that it leaves at each parameter value (the rest, 1 − Σ, it keeps the state to
// the end).
std::vector<double> SweepLeaveProbabilities(const CrisisFit& fit, CrisisSide side,
                                            const std::vector<double>& parameters, double dwell);

}  // namespace rubcont
