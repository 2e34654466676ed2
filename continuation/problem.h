// The one interface the continuation engine sees: F(u, λ) = 0, F: Rⁿ × R → Rⁿ.
//
// Every layer of rubcont wraps the one below and presents this interface upward
// (BifurcationKit's BifurcationProblem / WrapPOSh / FoldMAProblem, LOCA's groups): a rotating-wave
// problem, a shooting problem and a minimally augmented fold problem are all "a residual with a
// Jacobian" to the engine. Methods are non-const because problems keep scratch space (and shooting
// problems cache integrations); a Problem is not safe to share between threads.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "solvers/types.h"

namespace rubcont {

// What the stability operator returns for one solution.
enum class SpectrumKind {
  kEigenvalues,         // equilibria / rotating waves: stable when all Re < 0
  kFloquetMultipliers,  // periodic orbits: stable when all |·| < 1
};

struct Spectrum {
  SpectrumKind kind = SpectrumKind::kEigenvalues;
  // The spectrum with the trivial values removed (the zero eigenvalue of a continuous symmetry,
  // the unit multiplier of an autonomous orbit), sorted by decreasing Re (eigenvalues) or |·|
  // (multipliers).
  ComplexVector values;
  int trivial_removed = 0;  // how many trivial values were identified and removed
  bool valid = false;       // false when the operator could not be evaluated (e.g. integration failed)

  // Number of values in the unstable half-plane / outside the unit circle.
  int UnstableCount(double tolerance = 1e-9) const;
  bool Stable(double tolerance = 1e-9) const { return valid && UnstableCount(tolerance) == 0; }
};

// Kinds of special points on a branch (continuation/branch.h records them). Declared here because
// a problem's own test functions name the kind they mark (Problem::TestFunctionType).
enum class SpecialPointType {
  kFold,                    // turning point in λ: the λ-component of the tangent changes sign
  kBranchPoint,             // simple branch point: det [F_u F_λ; τᵀ] changes sign
  kHopf,                    // a complex pair of eigenvalues crosses the imaginary axis
  kRealEigenvalueCrossing,  // a real eigenvalue crosses 0 where the fold and branch-point tests
                            // did not fire (e.g. the stability operator is not F_u)
  kPeriodDoubling,          // a real Floquet multiplier crosses −1
  kNeimarkSacker,           // a complex pair of Floquet multipliers crosses the unit circle
  kMultiplierPlusOne,       // a real multiplier crosses +1 where the fold and branch-point tests
                            // did not fire
  kEvent,                   // an event function of a piecewise-smooth problem vanished; switched
  kCusp,                    // the fold normal-form coefficient vanishes on a fold curve
  kTestFunction,            // a problem-defined test function vanished (Problem::TestFunctions)
  kGrazing,                 // an orbit became tangent to a switching surface (a contact's
                            // penetration): past it the orbit crosses the surface twice per
                            // period (shooting/shooting.h, Grazing)
  // Codimension-two points on a Hopf curve (continuation/hopf.h):
  kBogdanovTakens,          // the Hopf pair meets at 0 (Hopf frequency → 0)
  kZeroHopf,                // a real eigenvalue of the rest of the spectrum crosses 0
  kDoubleHopf,              // a second complex pair crosses the imaginary axis
  kGeneralizedHopf,         // the first Lyapunov coefficient changes sign (Bautin point)
};

const char* ToString(SpecialPointType type);

struct LyapunovCoefficient;  // continuation/lyapunov.h

class Problem {
 public:
  virtual ~Problem() = default;

  // n: the number of unknowns in u and of equations in F.
  virtual Index Dimension() const = 0;

  // F(u, λ), written into F (resized by the callee if needed).
  virtual void Residual(const Vector& u, double lambda, Vector& F) = 0;

  // ∂F/∂u (n × n). Default: central differences scaled by Scale().
  virtual void Jacobian(const Vector& u, double lambda, Matrix& J);

  // ∂F/∂λ (n). Default: central difference with step relative to max(|λ|, LambdaScale()).
  virtual void DfDlambda(const Vector& u, double lambda, Vector& dF);

  // Typical magnitude of each unknown (n entries > 0) and of λ, and of each equation. The engine
  // works in u / Scale() and λ / LambdaScale(), and measures residuals in F / ResidualScale(), so
  // that unknowns of very different units (metres ~1e-4, forces ~1e3, frequencies ~1e2) weigh
  // alike in arclength, tangents, step control and convergence tests (continuation/
  // scaled_system.h says how; the options' step lengths and tolerances are in these units). Read
  // once per smooth piece: they must not depend on u.
  virtual Vector Scale() const { return Vector::Ones(Dimension()); }
  virtual double LambdaScale() const { return 1.0; }
  virtual Vector ResidualScale() const { return Vector::Ones(Dimension()); }

  // Optional stability operator: eigenvalues (equilibria) or Floquet multipliers (orbits).
  virtual bool HasStability() const { return false; }
  virtual Spectrum Stability(const Vector& u, double lambda);
  // Values with Re ≤ this (eigenvalues) or |·| ≤ 1 + this (multipliers) count as stable: the
  // tolerance of Spectrum::UnstableCount the engine uses. Problems with physically marginal modes
  // (e.g. a growth rate of 1e-5 s⁻¹ from contact compliance) raise it and say why.
  virtual double StabilityTolerance() const { return 1e-9; }

  // Optional named scalar measures stored with every branch point (e.g. "precession_hz",
  // "normal_force_left"). Measures(u, λ) returns one value per name, in order.
  virtual std::vector<std::string> MeasureNames() const { return {}; }
  virtual Vector Measures(const Vector& /*u*/, double /*lambda*/) { return Vector(); }

  // Optional second parameter η, for two-parameter continuation (fold curves, cusps).
  virtual bool HasSecondParameter() const { return false; }
  virtual double SecondParameter() const;
  virtual void SetSecondParameter(double eta);
  virtual double SecondParameterScale() const { return 1.0; }
  // ∂F/∂η at the current η. Default: central difference through SetSecondParameter.
  virtual void DfDeta(const Vector& u, double lambda, Vector& dF);

  // Optional events of a piecewise-smooth problem (stick ↔ slip, contact loss). The problem is
  // smooth between events; EventFunctions(u, λ) returns EventNames().size() values whose sign
  // changes mark the switching manifolds. When the engine has located a zero of event k it calls
  // SwitchAt(k, u, λ); the problem changes its formulation (e.g. a contact changes from stick to
  // slip) and may rewrite u into the new formulation's unknowns (Dimension() may change). It
  // returns false when it cannot continue past the event (the branch ends there, saying why).
  //
  // Sign convention the engine relies on: every event function is a validity margin, ≥ 0 while the
  // current piece is valid (e.g. μN − |F| in stick, ±V in slip±, the penetration while in contact;
  // a constant 1 for a condition that does not apply to the piece). An event fires when a margin
  // turns negative; the branch must start where all margins are ≥ 0. After a switch the engine
  // continues along the new piece in the direction where its margins that vanish at the switch
  // point grow: when that is back towards where the branch came from (a non-smooth fold), it turns
  // round and says so; when neither direction is valid the branch ends there. Names and the number
  // of events may differ between pieces; the engine re-reads EventNames() after a switch.
  virtual std::vector<std::string> EventNames() const { return {}; }
  virtual Vector EventFunctions(const Vector& /*u*/, double /*lambda*/) { return Vector(); }
  virtual bool SwitchAt(int /*event*/, Vector& /*u*/, double /*lambda*/) { return false; }
  // A label for the current smooth piece (e.g. "L:stick R:slip+"), stored with each branch point.
  virtual std::string PieceLabel() const { return {}; }

  // Optional smooth test functions of the problem itself, located where they change sign and
  // recorded as special points of type TestFunctionType(k) (default kTestFunction) labelled
  // TestFunctionNames()[k]. Unlike events, nothing switches there. The fold problem uses this for
  // cusps (continuation/fold.h); AUTO's and BifurcationKit's user test functions are the model.
  virtual std::vector<std::string> TestFunctionNames() const { return {}; }
  virtual Vector TestFunctions(const Vector& /*u*/, double /*lambda*/) { return Vector(); }
  virtual SpecialPointType TestFunctionType(int /*k*/) const {
    return SpecialPointType::kTestFunction;
  }

  // Called by the engine after it has accepted a branch point (u, λ), before the next step. A
  // problem may refresh internal data that leaves its solution set unchanged, such as the
  // bordering vectors of a minimally augmented system (continuation/fold.h). Default: nothing.
  virtual void PointAccepted(const Vector& /*u*/, double /*lambda*/) {}

  // Called by the engine on the point a step's corrector converged to, before it is accepted: empty
  // when it continues the branch, else why not. The engine then shortens the step as after a
  // corrector failure. For problems whose equations have roots that are no neighbours of the last
  // point: integral phase conditions are also met by the solution shifted by about half a period
  // (shooting/invariant_circle.h). Default: every point continues the branch.
  virtual std::string StrayPoint(const Vector& /*u*/, double /*lambda*/) { return {}; }

  // The first Lyapunov coefficient at a Hopf point (u, λ) of this problem's states, its critical
  // eigenvalue near `critical` (continuation/lyapunov.h): < 0 supercritical, > 0 subcritical.
  // Default: not valid, "not computed by this problem" (F need not be a vector field). Equilibria
  // (EquilibriumProblem) and rotating waves (waves/rotating_wave.h) compute it; Hopf curves test
  // its sign for generalized Hopf (Bautin) points (continuation/hopf.h).
  virtual LyapunovCoefficient FirstLyapunov(const Vector& u, double lambda,
                                            std::complex<double> critical);
};

// (u, λ) as one vector: the unknowns of a problem augmented by its parameter (fold, event and Hopf
// curves continue (u, λ) in the second parameter η).
Vector Joined(const Vector& u, double lambda);

// Puts a problem's second parameter back, however the scope is left (the curve problems move it).
class SecondParameterGuard {
 public:
  explicit SecondParameterGuard(Problem& problem)
      : problem_(problem), eta_(problem.SecondParameter()) {}
  ~SecondParameterGuard() { problem_.SetSecondParameter(eta_); }
  SecondParameterGuard(const SecondParameterGuard&) = delete;
  SecondParameterGuard& operator=(const SecondParameterGuard&) = delete;
  double eta() const { return eta_; }

 private:
  Problem& problem_;
  double eta_;
};

}  // namespace rubcont
