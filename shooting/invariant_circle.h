// Quasi-periodic motion on a 2-torus, as an invariant circle of the stroboscopic map (Schilder,
// Osinga & Vogt 2005, SIAM J. Appl. Dyn. Syst. 4: "Continuation of quasi-periodic invariant tori"),
// a continuation problem F(u, λ) = 0 (continuation/problem.h). Three kinds, as the orbits of
// shooting/shooting.h:
//   kForced      ẋ = f(t, x), f T-periodic in t (T = OdeSystem::ForcingPeriod() at λ): the
//                stroboscopic map P(x) = x(T; 0, x) carries a 2-torus of the flow into itself as a
//                closed curve.
//   kAutonomous  ẋ = f(x): P = Φ_T, the flow over a time T that is an unknown — the return time of
//                one angle of the torus (2π over its frequency), fixed by the circle itself: Φ_T
//                has an invariant circle only for that T. The torus's two frequencies are 1/T and
//                ρ/T (or (1 − ρ)/T, by the circle's orientation).
//   kRelative    ẋ = f(x) with a rotation symmetry R_φ (OdeSystem::Rotate): P = R_{−φ} Φ_T, T and φ
//                unknown — a relative 2-torus (three frequencies in the original frame; in the frame
//                turning by φ per T, a 2-torus): the two-frequency whips of case C in the frame
//                co-rotating with the whip.
// An autonomous torus's circle can slide along the flow (Φ_s of an invariant circle is one) and a
// relative torus's along the group orbit (R_α of one is one): one more phase condition each, the
// scaled mean of ⟨u(θ_j) − u_ref(θ_j), f(u_ref(θ_j))⟩ resp. ⟨·, g(u_ref(θ_j))⟩ (g the rotation
// generator), as the θ phase condition below. Decision: the conditions on the whole circle rather
// than on one point (shooting's hyperplane), because the circle's points are all unknowns alike.
//
// The circle u(θ), θ ∈ [0, 2π), is a truncated Fourier series with K harmonics,
//     u(θ) = a₀ + Σ_{k=1..K} (a_k cos kθ + b_k sin kθ)        (a_k, b_k ∈ Rⁿ),
// and invariance means that P moves it along itself by a rigid rotation ρ (the rotation number):
//     P(u(θ)) = u(θ + 2πρ),   i.e.   Φ_T(u(θ)) = R_φ u(θ + 2πρ)   (R = I unless kRelative),
// collocated at the N = 2K + 1 points θ_j = 2πj/N. The circle is only defined up to θ ↦ θ + c: one
// phase condition fixes that, the scaled mean of ⟨u(θ_j) − u_ref(θ_j), u_ref′(θ_j)⟩ over j (AUTO's
// integral condition on the circle). Unknowns u = [a₀, a₁, b₁, …, a_K, b_K, ρ, T, φ] (T for
// kAutonomous and kRelative, φ for kRelative: n(2K + 1) + 1 + e, e = 0, 1, 2); equations: n N + 1 + e.
// Jacobian: ∂r_j/∂c = M_j ⊗ B(θ_j) − R_φ ⊗ B(θ_j + 2πρ), ∂r_j/∂ρ = −2π R_φ u′(θ_j + 2πρ),
// ∂r_j/∂T = f(Φ_T(u(θ_j))), ∂r_j/∂φ = −g(R_φ u(θ_j + 2πρ)). Why Fourier points rather than a 2-D collocation: the map is integrated by
// the same error-controlled integrators as the orbits (N independent trajectories of one forcing
// period, with sensitivities), the circle of a smooth torus converges spectrally in K, and the
// growth of the last harmonic measures the loss of smoothness that precedes breakdown.
//
// Where ρ is rational (phase locking) no rigid rotation conjugates the map on the circle and the
// Fourier series stops converging: measure "fourier_tail" (the last harmonic's size against the
// largest) grows; "invariance_error" is the defect |P(u(θ)) − u(θ + 2πρ)| (scaled) half-way
// between the collocation points.
//
// Stability, two ways. (1) CircleMultipliers: the linearized map carries a perturbation v of the
// circle to w(θ + 2πρ) = ∂P(u(θ)) v(θ); in Fourier coefficients that is Λ = Ê⁻¹ diag(M_j) E (E, Ê:
// the basis at θ_j and at θ_j + 2πρ; M_j the monodromy of point j). For a torus whose linearization
// is reducible its eigenvalues come in clusters of 2K + 1 of one modulus (1 along the circle, the
// normal multipliers across it), but the pair of each cluster that belongs to the last harmonic is
// polluted by the truncation (measured: 0.96–0.998 instead of 1 on the clocked Stuart–Landau
// torus, 1.003 on the forced van der Pol one) and the clusters of a non-reducible torus spread
// (0.46–0.68 for that van der Pol torus): a diagnostic, not a verdict. (2) Lyapunov: the exponents
// of the map along an orbit on the circle, by QR of the tangent maps (Benettin et al. 1980), the one
// nearest 0 the tangent's, whose distance from 0 states the estimate's accuracy: the verdict.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "continuation/problem.h"
#include "shooting/shooting.h"
#include "solvers/newton.h"
#include "solvers/ode.h"

namespace rubcont {

// The coordinates the circle's Fourier series is written in: the state x, or the system's chart y
// (OdeSystem::HasStateChart, x = Ψ(y)): u(θ) = Ψ(a₀ + Σ_k a_k cos kθ + b_k sin kθ). The chart's
// purpose is a stiff contact: where the torus lies within nanometres of the contact surface (its
// penetration) while it moves by micrometres along it, the series in x leaves the surface by its
// truncation error — C(c) at 64 rpm: K = 8 points up to 44 nm off against penetrations of
// 0.5–2.5 nm, so the contact opens and closes within the map and its Jacobian is singular — and
// the series in the chart by that error relative to the penetration's own variation. Everything
// else is the same: the residual compares states, the phase conditions and the Fourier tail are
// taken on the coefficients (scaled by OdeSystem::ChartScale), the chart's angles are unwrapped
// where points are fitted (CircleFromOrbit).
enum class CircleCoordinates { kState, kChart };
const char* ToString(CircleCoordinates coordinates);

// The name of InvariantCircleProblem's event "the Fourier tail reached its maximum"
// (SetMaxFourierTail): the label of the special point a family ending there carries.
inline constexpr char kFourierTailReached[] = "circle breaks down (Fourier tail)";
// The name of InvariantCircleProblem's event "the radius reached its minimum" (SetMinRadius): the
// label of the special point a family ending there carries.
inline constexpr char kShrinksOntoCentre[] = "circle shrinks onto its centre (radius)";

// A switching surface h(x) = 0 (h > 0 where the other law applies: a contact's penetration) whose
// grazing by the torus is a special point of its family (SpecialPointType::kGrazing, labelled
// `name`): the extremum of h over the torus — its minimum for kLiftOff, its maximum for kTouchdown
// (GrazingSide, shooting/shooting.h) — changes sign. h must be a function of the state alone and,
// for relative tori, invariant under the system's rotation (a contact's penetration is).
struct TorusGrazing {
  std::function<double(ConstVectorRef)> surface;
  GrazingSide side = GrazingSide::kLiftOff;
  std::string name;
};

class InvariantCircleProblem : public Problem {
 public:
  // K ≥ 1 harmonics. kForced needs a forced system (ForcingPeriod() > 0 at its parameter), the
  // others an unforced one, kRelative one with a rotation symmetry, kChart one with a chart;
  // std::invalid_argument else.
  InvariantCircleProblem(std::shared_ptr<OdeSystem> system, int harmonics, OrbitKind kind,
                         const IntegratorOptions& options = {},
                         CircleCoordinates coordinates = CircleCoordinates::kState);

  int harmonics() const { return harmonics_; }
  Index states() const { return n_; }
  OrbitKind kind() const { return kind_; }

  // Unknowns from coefficients (n × (2K + 1): columns a₀, a₁, b₁, …), ρ, and T and φ where the
  // kind has them (ignored otherwise).
  Vector Pack(const Matrix& coefficients, double rho, double period = 0.0, double rotation = 0.0) const;
  Matrix Coefficients(const Vector& u) const;
  double RotationNumber(const Vector& u) const { return u(n_ * points_); }
  // T: the unknown (kAutonomous, kRelative) or the forcing period at λ (kForced). Sets the
  // system's parameter to λ (every integration of the problem goes through here).
  double Period(const Vector& u, double lambda);
  // φ (kRelative), else 0.
  double Rotation(const Vector& u) const;
  // u(θ) for the circle held in u (a state).
  Vector PointAt(const Vector& u, double theta) const;
  CircleCoordinates coordinates() const { return chart_ ? CircleCoordinates::kChart : CircleCoordinates::kState; }
  // A state in the circle's coordinates (the chart's y = Ψ⁻¹(x), or x), and ∂x/∂y at y.
  Vector ToCoordinates(const Vector& x) const;
  Matrix CoordinateJacobian(const Vector& y) const;
  // ‖(a_k, b_k) ./ scale‖ of harmonic k in 1 … K of the circle held in u.
  double HarmonicSize(const Vector& u, int k) const;
  // The circle's radius (measure "radius"): the RMS over its N points x(θ_j) of their distance
  // from the points' mean, ‖(x_j − x̄) ./ the state scale‖ (in the state also for a chart's
  // circle): r for a round circle of radius r; 0 where the torus has shrunk onto the periodic
  // orbit at its centre.
  double Radius(const Vector& u) const;
  // The points' mean x̄ (a state): near a Neimark–Sacker point, a point of the orbit the circle
  // shrinks onto.
  Vector Centre(const Vector& u) const;

  // The phase conditions' reference circle (its coefficients are taken from u; the flow's
  // direction at the system's present parameter). Set at the start; PointAccepted moves it to
  // every accepted point.
  void SetPhaseReference(const Vector& u);

  // The event "circle breaks down": the Fourier tail (measure "fourier_tail") reaches this. Past
  // it the collocation equations still have solutions, but they are no invariant circles
  // (measured on the forced van der Pol torus continued into 1:1 locking: the tail grows from
  // 1e-10 to 0.13 and the invariance error between the points to 0.3); the branch ends there with
  // the event as its reason. Default 1e-6.
  void SetMaxFourierTail(double tail);
  // The event "circle shrinks onto its centre": the radius falls to this (> 0; 0, the default,
  // switches it off). Where a torus family ends at a Neimark–Sacker point of the orbit inside it,
  // the circle shrinks as √|λ − λ_NS| and its phase conditions, which measure shifts of the circle,
  // lose their hold: at radius 0 the equations are singular, and a step across meets the same
  // tori again, parametrised half a turn apart (C(a) at 62.988 rpm: the family came back on
  // itself). The branch ends at the event with it as its reason.
  void SetMinRadius(double radius);

  Index Dimension() const override;
  void Residual(const Vector& u, double lambda, Vector& F) override;
  void Jacobian(const Vector& u, double lambda, Matrix& J) override;
  void DfDlambda(const Vector& u, double lambda, Vector& dF) override;
  Vector Scale() const override;
  double LambdaScale() const override;
  Vector ResidualScale() const override;
  std::vector<std::string> MeasureNames() const override;
  Vector Measures(const Vector& u, double lambda) override;
  void PointAccepted(const Vector& u, double lambda) override;
  // A corrected circle turned against the reference (the last accepted one) along θ, the flow or
  // the group orbit: each phase condition, a function of that shift, has a second root about half
  // a period away, where its slope in the shift — Σ_j ⟨w_j, d_j⟩, d_j the shift's direction at
  // the new circle's point j — has the sign opposite to the reference's own. A long step can land
  // there: the same torus, its circle turned by half a turn, and the tangent there oriented against
  // the branch (C(a) at 62.99 rpm: the family came back on itself). Named, so that the engine
  // shortens the step.
  std::string StrayPoint(const Vector& u, double lambda) override;
  std::vector<std::string> EventNames() const override;
  Vector EventFunctions(const Vector& u, double lambda) override;

  // The test functions of the grazing surfaces (empty: none): per surface the extremum of h over
  // the torus, read on a grid of kGrazingStartsPerPoint · N orbits of one period T from the circle's
  // points u(2πi/M), M = kGrazingStartsPerPoint · N, each at GrazingSamples() + 1 instants sT,
  // s = 0 … 1 — the torus in the coordinates (start angle, s), which cover it once with the seam
  // s = 1 ≡ s = 0 shifted by 2πρ. The extreme sample is refined by the quadratic through the 3 × 3
  // samples round it (the torus's coordinates are sheared: the cross term counts); across the
  // seam a neighbour is h(Φ_{(1 − 1/S)T}(u(ϑ − 2πρ))) (before s = 0) or h(Φ_{T/S}(u(ϑ + 2πρ)))
  // (after s = 1), by the map's invariance, one more orbit each. Decision: the grid
  // rather than the samples TorusLines reads (64 instants of N orbits): C(c)'s least normal force
  // read that way was not smooth along its family (0.52 N at 71.0993 rpm, 0.81 N at 71.1066), as
  // the orbits' grazing on 64 samples per segment was not (ShootingProblem::TestOrbit).
  void SetGrazingTests(std::vector<TorusGrazing> tests);
  static constexpr Index kGrazingStartsPerPoint = 4;
  // S: ShootingProblem::kTestSamplesPerCollocationStep per step of a Gauss collocation mesh over
  // the period, at least 64 (64 with the other integrators).
  Index GrazingSamples() const;
  // A denser grid (starts per circle point, samples per collocation step and at least
  // samples_per_step · 16 with other integrators; ≥ 1 each), to measure how far a located grazing
  // moves with it (bench/torus_grazing_bench).
  void SetGrazingGrid(int starts_per_point, int samples_per_step);
  std::vector<std::string> TestFunctionNames() const override;
  Vector TestFunctions(const Vector& u, double lambda) override;
  SpecialPointType TestFunctionType(int k) const override;

  // The moduli of Λ's eigenvalues, largest first (see above); empty when an integration failed.
  std::vector<double> CircleMultipliers(const Vector& u, double lambda);

  // Lyapunov exponents of the map P (per period T), largest first, from `iterates` steps of the
  // orbit of u(0) with QR of the tangent maps, after iterates/4 steps not counted (the frame's
  // alignment). `trivial` indexes the 1 + e nearest 0, whose exact
  // value is 0: along the circle, and along the flow (kAutonomous, kRelative) and the group orbit
  // (kRelative). Stable when every other is below −tolerance, unstable when one is above
  // +tolerance, tolerance = max(10 · the largest |trivial exponent|, 1e-6): the trivial exponents'
  // distance from 0 is the estimate's error. Neither (undecided): the largest nontrivial exponent
  // is within the tolerance of 0 — more iterates, or a torus too close to its birth, where its
  // attraction is as weak as the estimate's error (C(a) 0.01 rpm past its Neimark–Sacker point).
  struct TorusStability {
    bool valid = false;          // an integration failed
    Vector exponents;            // n, per period
    std::vector<Index> trivial;
    double tolerance = 0.0;
    bool stable = false;
    bool unstable = false;
    // "stable", "unstable" or "undecided" (valid estimates only).
    const char* Verdict() const { return stable ? "stable" : unstable ? "unstable" : "undecided"; }
    // Whether exponent i is one of the trivial ones.
    bool IsTrivial(Index i) const;
    // The largest exponent that is not trivial (−∞ when all are).
    double LargestNontrivial() const;
    // The nontrivial exponents above the tolerance: 0 when stable; −1 when undecided or not
    // computed (BranchPoint::num_unstable's convention).
    int UnstableCount() const;
  };
  TorusStability LyapunovStability(const Vector& u, double lambda, int iterates = 200);

  // The defect max_j |P(u(ϑ_j)) − u(ϑ_j + 2πρ)| ./ scale at ϑ_j = θ_j + π/N.
  double InvarianceError(const Vector& u, double lambda);
  // Where the last map of the circle's points failed ("" when it succeeded): the point and the
  // integrator's report. A failed map makes the residual non-finite, which Newton's report names
  // without its cause.
  const std::string& MapFailure() const { return cached_.failure; }
  // The circle's graph transform: its points u(ϑ_k) at `angles`, each mapped `images` times by the
  // problem's map P (n × angles, states); the k-th lies on the image circle at ϑ_k + 2π·images·ρ.
  // Empty, with `failure` saying where, when an integration fails.
  Matrix Images(const Vector& u, double lambda, const Vector& angles, int images,
                std::string& failure);

  // A first circle from points of one orbit of the map, x_{k+1} = P(x_k) (n × m, m ≥ 2K + 2),
  // lying on a circle that winds once around its centroid in the plane of its two leading
  // principal directions: each point's angle there gives θ_k, ρ is the mean angle advance per
  // iterate (in [0, 1/2]: of ρ and 1 − ρ, the same torus traversed either way, the angle runs the
  // way that gives the smaller), and the coefficients are fitted by least squares in θ. Then the
  // map's own angles θ_k = 2πkρ (the parametrisation in which P turns the circle rigidly), ρ
  // refined by the least misfit round that estimate, replace them where they fit better. T and φ,
  // those of the map the points came from, are packed as given. With a chart the angles and ρ
  // come from the states as above, the coefficients are then fitted in the chart at those angles.
  // Throws std::invalid_argument when the points do not wind (a locked or non-circular set).
  Vector CircleFromOrbit(const Matrix& points, double period = 0.0, double rotation = 0.0) const;
  // The circle through the same points when ρ is known (a solved circle's, of fewer harmonics):
  // θ_k = 2πkρ, the coefficients fitted by least squares. Where the first fit's ρ is off by δ the
  // m points' angles drift by 2πmδ: C(c) at 64 rpm, K = 16, fitted ρ 4.8e-4 from the solved one
  // over 132 points (0.4 rad), and Newton diverged from that circle. Throws as CircleFromOrbit.
  Vector CircleAtRotationNumber(const Matrix& points, double rho, double period = 0.0,
                                double rotation = 0.0) const;
  // The circle through states at given angles (points n × m, m ≥ 2K + 2; angles m), ρ, T and φ
  // packed as given: the coefficients fitted by least squares (in the chart with one).
  Vector CircleAtAngles(const Matrix& points, const Vector& angles, double rho, double period = 0.0,
                        double rotation = 0.0) const;

 private:
  struct Integrated {
    bool ok = false;
    Matrix ends;                  // n × N: P(u(θ_j))
    std::vector<Matrix> stms;     // M_j (with sensitivities)
    Matrix dpdp;                  // n × N: ∂P/∂λ (with sensitivities)
    // n × N: ∂P/∂T, the integrator's own (OdeIntegrator::Integrate's dxdt1: for Gauss collocation
    // its map's, not f at the end); with sensitivities.
    Matrix dpdt;
    std::string failure;          // where an integration failed (ok false), else ""
  };
  // The collocation point θ_j = 2πj/N.
  double Node(Index j) const;
  // Basis row [1, cos θ, sin θ, …, cos Kθ, sin Kθ] and its θ-derivative.
  Vector Basis(double theta) const;
  Vector BasisDerivative(double theta) const;
  double FourierTail(const Vector& u) const;
  // The states x(θ_j) at the circle's N points (n × N).
  Matrix States(const Vector& u) const;
  // The m × (2K + 1) matrix whose rows are the basis at m angles.
  Matrix BasisMatrix(const Vector& angles) const;
  // Coefficients (n × (2K + 1), in the circle's coordinates) fitted by least squares to states at
  // the angles whose basis rows `basis` holds (BasisMatrix).
  Matrix FitCoefficients(const Matrix& states, const Matrix& basis) const;
  // ‖(a_k, b_k) ./ scale‖ of harmonic k of an n × (2K + 1) coefficient matrix.
  static double HarmonicSizeOf(const Matrix& coefficients, int k, const Vector& scale);
  // A phase condition Σ_j ⟨w_j, u(θ_j) − u_ref(θ_j)⟩ from directions v_j at the reference's points
  // (u_ref′(θ_j), f(u_ref(θ_j)), g(u_ref(θ_j))): w_j = v_j ./ scale² over the RMS of v ./ scale.
  Matrix PhaseWeights(const Matrix& directions) const;
  // The directions of the circle with coefficients c's shifts at its points, in the circle's
  // coordinates: along θ (u′(θ_j)), and where the kind has them along the flow (D⁻¹ f) and the
  // group orbit (D⁻¹ g), f and g at the system's present parameter; one matrix per phase condition.
  std::vector<Matrix> ShiftDirections(const Matrix& c) const;
  const Integrated& Integrate(const Vector& u, double lambda, bool sensitivities);
  double PeriodAt(double lambda);
  // x = Ψ(y) (or y), with ∂Ψ/∂y into `jacobian` when not null.
  Vector ToState(const Vector& y, Matrix* jacobian = nullptr) const;
  Matrix RotationMatrix(double phi) const;  // R_φ (identity unless kRelative)
  Index Extras() const;                     // e: 0, 1, 2

  std::shared_ptr<OdeSystem> system_;
  int harmonics_;
  OrbitKind kind_;
  Index n_;
  Index points_;  // N = 2K + 1
  IntegratorOptions options_;
  bool chart_ = false;        // CircleCoordinates::kChart
  Vector scale_;              // the system's state scale
  Vector coordinate_scale_;   // the coefficients' scale: the chart's, or scale_
  std::vector<Index> angles_;  // the chart's angle coordinates
  Matrix reference_;  // n × (2K + 1)
  std::vector<Matrix> phase_weights_;  // θ, flow (kAutonomous, kRelative), group (kRelative)
  double period_scale_ = 1.0;          // |T| of the reference
  double max_tail_ = 1e-6;
  double min_radius_ = 0.0;
  std::vector<TorusGrazing> grazing_;
  Index grazing_starts_per_point_ = kGrazingStartsPerPoint;
  Index grazing_samples_per_step_ = ShootingProblem::kTestSamplesPerCollocationStep;
  Vector cached_u_;
  double cached_lambda_ = 0.0;
  bool cached_sensitivities_ = false;
  Integrated cached_;
};

// A circle's unknowns u (InvariantCircleProblem::Pack layout for `states` states and `from`
// harmonics) in the layout of `to` harmonics: the same trigonometric polynomial, its coefficients
// padded with zero harmonics (to ≥ from) or cut after harmonic `to` (exact where the harmonics
// above are zero: a circle padded before); ρ, T and φ as they were. Also the û part of a tangent
// (scaled: the coefficients' scale does not depend on k). Throws std::invalid_argument when u's
// size does not fit `from`.
Vector CircleWithHarmonics(const Vector& u, Index states, int from, int to);

// A solved circle refined in K: the circle u of `coarse` at λ, solved again with `finer`'s
// harmonics (same system, kind and coordinates, more harmonics). The start is the solved circle's
// graph transform: 4(2K′ + 1) of its points, each mapped n times by `coarse`'s map (its T and φ),
// fitted at their angles advanced by 2πnρ (InvariantCircleProblem::Images, CircleAtAngles); then
// Newton at λ, with the phase conditions referred to that start — for each n of `images` in turn
// until one converges. The images pull the start towards the torus by its normal contraction,
// where the coarse circle padded with zero harmonics stalls (shooting/modulated_torus.h: C(a) at
// 49 rpm, K = 16). Used for the transient's torus (ModulatedTorusOptions::max_harmonics) and
// along torus families (TorusBranchOptions::max_harmonics).
struct CircleRefinement {
  bool converged = false;
  Vector u;             // finer's layout: the solved circle; else the coarse one padded
  NewtonResult newton;  // of the count that converged (else of the last tried)
  int images = 0;       // the count that converged (0: none)
  std::string failures;  // "from n images: why; …" for the counts that did not converge
};
// Throws std::invalid_argument, its message starting with `prefix` (the options' name and
// separator: "TorusBranchOptions: "), unless `images` holds one or more counts in 1 … 100.
void ValidateRefinementImages(const std::string& prefix, const std::vector<int>& images);
CircleRefinement RefineCircle(InvariantCircleProblem& coarse, const Vector& u, double lambda,
                              InvariantCircleProblem& finer, const std::vector<int>& images,
                              const NewtonOptions& newton);

}  // namespace rubcont
