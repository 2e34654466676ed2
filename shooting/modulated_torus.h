// A whip modulated at two frequencies, of the rub model at one running speed (level L2): a relative
// 2-torus. In the frame co-rotating with the whip the motion is quasi-periodic with two modulation
// frequencies (case C(a) at 60 rpm: the left contact's slip modulated at 121 Hz, the right's at
// 325 Hz, which no one period fits: SolveModulatedOrbit does not converge there), so it is found as
// an invariant circle of the map x ↦ R_{−φ} Φ_T(x) (shooting/invariant_circle.h, kRelative) from
// the end of a settled transient, and read as a sweep reads a precession.
//
// The start. The transient is integrated on for `approach` s first (a torus can attract slowly: C(a)
// at 60 rpm, "settled" by the sweeps' spectral test, still moved its modulation from 123.3 to
// 124.4 Hz over the next 0.8 s). Then, as SolveModulatedOrbit, the state is taken into the frame
// precessing at Ω_f and integrated over a stretch; T = 1 / the dominant frequency of contact 0's slip velocity.
// Then `iterates` more sections of m = `laps` periods, sampled 16 times per period: φ̄, the turn of
// contact 0's d = u_rotor − u_stator per section (the least-squares slope of its phase, unwrapped
// along the samples), and
// the points x_k = R_{−kφ̄} x(kmT), the orbit of P = R_{−φ̄} Φ_{mT}, near its invariant circle;
// CircleFromOrbit fits the first circle (K harmonics) and ρ. Newton then solves for the circle, ρ,
// the section's time and φ.
//
// Sections of m periods. Where the torus's first frequency is f₁ = 1/(mT) with T the slip's
// dominant period (the modulation's m-th harmonic the strongest line: C(a) at 60 rpm, f₁ = 24.874 Hz
// and T = 1/124.37 Hz, m = 5), the points one period apart visit m arcs of the torus in turn and are
// no circle; their sequence's strongest line is then near p/m per period. laps = 0 (automatic)
// tries m = 1, and where the points are no circle and that line names m (2 … 8), m. Decision: the
// line decides, not a search over m — it is what the points show, and the message says which m was
// used.
//
// The frequencies. On the torus, the co-rotating motion turns by φ per T and is otherwise
// quasi-periodic with f₁ = 1/T and f₂ = ρ/T (ρ ∈ (0, 1); 1 − ρ describes the same lattice of lines,
// the circle traversed the other way), so the fixed-frame motion is a sum of backward precessions
//     Ω_{k,l} = Ω_f − φ/T − 2π (k f₁ + l f₂),   k, l ∈ Z,
// the carrier (k = l = 0) at RubRotatingFrame::CarrierPrecession(T, φ).
#pragma once

#include <string>
#include <vector>

#include "models/rub_model.h"
#include "shooting/invariant_circle.h"
#include "solvers/constants.h"
#include "solvers/newton.h"

namespace rubcont {

struct ModulatedTorusOptions {
  // The integrator of the map (BDF ≤ 2 at 1e-7: the circle's residual is only as smooth as the
  // integration, so Newton's tolerances below are 100 times these).
  IntegratorOptions integrator = [] {
    IntegratorOptions o;
    o.max_order = 2;
    o.relative_tolerance = o.absolute_tolerance = 1e-7;
    o.max_steps = 2000000;
    // The STM as exact as the state's steps make it: with the sensitivities in the error test
    // BDF took 830 000 steps over one modulation period of C(a) at 49 rpm, against 12 000 without
    // (measured) — BDF ≤ 2 keeps the unexcited fast modes of Φ bounded (solvers/ode.h).
    o.sensitivity_error_control = false;
    return o;
  }();
  NewtonOptions newton = [] {
    NewtonOptions o;
    o.residual_tolerance = o.step_tolerance = 1e-5;
    o.max_iterations = 12;
    return o;
  }();
  int harmonics = 8;               // K ≥ 1
  int iterates = 0;                // points for the first circle, ≥ 2K + 2; 0: 4 (2K + 1)
  // As ModulatedOrbitOptions, but longer: T must be right to ~1e-3, or the first points smear
  // over the torus (0.05 s put C(a)'s 124.4 Hz at 122.2 Hz).
  double search_duration = 0.5;
  double approach = 1.0;           // [s] ≥ 0
  double search_rate = 20000.0;
  int lyapunov_iterates = 100;     // ≥ 0 (0: no stability)
  int laps = 0;                    // modulation periods per section, 1 … 64; 0: automatic (above)
  // The map's integrator (the circle's Newton solve and stability): `integrator` when 0, else
  // Gauss–Legendre collocation of order 8 on this many intervals per modulation period (as the
  // orbits stage). Decision: BDF by default — on C(a) at 60 rpm Gauss's Newton did not converge
  // on the first step from the circle's points with 400 intervals (20 µs) and failed at 2 of 33
  // with 1000, where BDF takes steps of ~0.6 µs (12 000 per period at 49 rpm).
  int collocation_intervals = 0;
  // The map the torus is reported and refined in K under, when the first circle's is `integrator`
  // (collocation_intervals = 0): > 0, the first circle, once solved, is solved again at the same K
  // with Gauss–Legendre collocation of order 8 on this many intervals per modulation period (the
  // map its families continue with), and every K after it under that map; 0: the first map
  // throughout. Decision, measured (one run each): C(a) at 49 rpm refined to K = 32 under BDF ≤ 2
  // at 1e-7 gave ρ 0.378634 (tail 4e-4), under Gauss on 800 intervals 0.376398, and K = 128
  // 0.375872 (results/bench/torus_in_k.txt): the BDF map's error, not K's, held ρ 2.7e-3 off, and
  // the family's Gauss corrector then failed at the transient's speed.
  int final_collocation_intervals = 0;
  // The circle's coordinates (shooting/invariant_circle.h): the state, or the rub model's contact
  // chart (the gap |d| − C a coordinate of its own), for contacts pressed by nanometres.
  CircleCoordinates coordinates = CircleCoordinates::kState;
  // Convergence in K: once the circle with `harmonics` converged, K is doubled while the Fourier
  // tail exceeds `converged_tail` and 2K ≤ max_harmonics. The finer circle's start is the solved
  // circle's graph transform: 4(2K′ + 1) of its points each mapped n times by the solved map (its
  // T and φ, Newton's own integrator), fitted at their angles advanced by 2πnρ; then Newton with
  // its steps halved where they fail (up to 8 times), for each n of `refinement_images` in turn
  // until one converges. Each K's ρ, tail, invariance error and n are reported
  // (ModulatedTorus::by_harmonics); where no start converges, the coarser circle stays with the
  // reasons. 0: harmonics only. Decision, measured (bench/transient_tori_bench, one run each;
  // results/bench/torus_in_k.txt): from the circle padded with zero harmonics, or mapped once or
  // ten times, C(a) at 49 rpm (state, Gauss 800) stalls at K = 16 (|F| 7.5e-5 … 7.8e-5 over 30
  // iterations), mapped 3 times it reaches K = 128; C(c) at 64 rpm (chart) from 3 images meets a
  // singular Jacobian at K = 32, from 10 it reaches K = 64. The images pull the start towards the
  // torus by its normal contraction; which count lands in a root's basin of the truncated
  // equations (near a resonance several roots, ρ 1e-4 apart at K = 16) is not known beforehand.
  // The earlier start, a circle fitted to the transient's orbit under the solved map, reached
  // neither C(a)'s K = 32 (a non-finite residual) nor C(c)'s K = 16 (a singular Jacobian).
  int max_harmonics = 0;          // 0 … 1000
  double converged_tail = 1e-4;  // (0, 1)
  std::vector<int> refinement_images = {3, 10};  // each in 1 … 100, tried in turn
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const ModulatedTorusOptions& options);

// The start from a settled transient of the rub, as measured on C(a) at 49 rpm
// (docs/levels/l2_orbits_tori.md, "Tori from a settled transient"): 4 s of approach and 4 s of
// search (with 2 s each the points were no circle: misfit 15 % of their size), up to 30 Newton
// iterations (it took 10–19) with failing steps halved up to 8 times, and no Lyapunov exponents (a family's first torus has its own). The
// scene's transient, its test and bench/transient_tori_bench start so.
ModulatedTorusOptions SettledTransientStart(int harmonics);

struct ModulatedTorus {
  bool converged = false;
  std::string message;       // how the search and Newton went, one sentence with numbers
  NewtonResult newton;
  double frame_rate = 0.0;   // Ω_f [rad/s]
  int laps = 0;              // m: periods per section (0 where the search failed)
  // T from the search (1 / the slip's dominant frequency; one modulation period, not the section's)
  // and φ̄ per section from the first points: the start, also when Newton does not converge (NaN
  // where the search failed).
  double search_period = kNaN;
  double search_rotation = kNaN;
  double period = kNaN;           // the section's time [s]
  double rotation = kNaN;         // φ per section [rad]
  double rotation_number = kNaN;  // ρ
  double carrier_hz = kNaN;       // (Ω_f − φ/T) / 2π
  double first_hz = kNaN;         // f₁ = 1/T
  double second_hz = kNaN;        // f₂ = ρ/T
  double fourier_tail = kNaN;
  double invariance_error = kNaN;
  // Where the first circle was solved again under the final map
  // (ModulatedTorusOptions::final_collocation_intervals): its ρ under the first map (else NaN).
  double first_map_rotation_number = kNaN;
  // The circle at each K solved (ModulatedTorusOptions::max_harmonics), ascending; the last is u's.
  struct AtHarmonics {
    int harmonics = 0;
    double rotation_number = kNaN;
    double fourier_tail = kNaN;
    double invariance_error = kNaN;
    int newton_iterations = 0;
    int images = 0;  // the start's images under the map (0: the first circle, from the transient)
  };
  std::vector<AtHarmonics> by_harmonics;
  int harmonics = 0;  // K of u
  InvariantCircleProblem::TorusStability stability;  // valid = false when not computed
  Vector u;                  // the circle's unknowns (InvariantCircleProblem::Pack layout)
  double seconds = 0.0;      // wall time of the search, Newton and the stability
};

// The torus near `fixed_state` (RubFixedFrame layout) at running speed ω [rad/s], with the frame
// precessing at `frame_rate` Ω_f [rad/s] > 0. The structure must be balanced. Throws
// std::invalid_argument for wrong sizes, non-positive Ω_f or ω, an imbalance or invalid options;
// numerical outcomes (no modulation, integration failures, points that do not wind once round a
// circle, Newton not converged) are `converged = false` with the message; where the points are
// no circle and their sequence's strongest line is near p/m, the message says the section may cut
// the torus m times.
ModulatedTorus SolveModulatedTorus(const RubStructure& structure, double omega, double frame_rate,
                                   const Vector& fixed_state, const ModulatedTorusOptions& options = {});

}  // namespace rubcont
