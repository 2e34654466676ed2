// A first-order ODE system ẋ = f(t, x; p) with one scalar parameter p (the continuation parameter:
// running speed, forcing frequency, ...), optional analytic derivatives, and optional description
// of a continuous rotational symmetry. The integrators in solvers/ and the shooting problems in
// shooting/ see models only through this interface.
//
// Signatures take Eigen::Ref so that integrators can pass maps over SUNDIALS N_Vector storage
// without copying. Implementations must not allocate in Rhs / JacobianX (keep a workspace).
#pragma once

#include <string>
#include <vector>

#include "solvers/types.h"

namespace rubcont {

using ConstVectorRef = Eigen::Ref<const Vector>;
using VectorRef = Eigen::Ref<Vector>;
using MatrixRef = Eigen::Ref<Matrix>;

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;

  virtual Index Dimension() const = 0;

  // f = ẋ at (t, x) for the current parameter value. f has Dimension() entries.
  virtual void Rhs(double t, ConstVectorRef x, VectorRef f) = 0;

  // ∂f/∂x (Dimension() × Dimension()). Default: central differences of Rhs.
  virtual bool HasJacobian() const { return false; }
  virtual void JacobianX(double t, ConstVectorRef x, MatrixRef J);

  // The scalar parameter p and ∂f/∂p (default: central difference through SetParameter).
  virtual double Parameter() const = 0;
  virtual void SetParameter(double p) = 0;
  virtual void DfDparameter(double t, ConstVectorRef x, VectorRef df);

  // Typical magnitude of each state (entries > 0): scales finite differences, tolerances and
  // shooting unknowns. Default: all ones.
  virtual Vector StateScale() const { return Vector::Ones(Dimension()); }

  // Period of an explicit time-periodic forcing at the current parameter (0: autonomous).
  virtual double ForcingPeriod() const { return 0.0; }

  // A short name for state i (0 ≤ i < Dimension()), used to label measures such as "max_<name>".
  // Default: "x<i>".
  virtual std::string StateName(Index i) const { return "x" + std::to_string(i); }

  // Optional SO(2) symmetry: f(R_φ x) = R_φ f(x) for a rotation action R_φ (e.g. rotating every
  // complex coordinate by e^{jφ}). Relative periodic orbits satisfy x(T) = R_φ x(0).
  // The shooting code assumes the action is linear in x (R_φ a matrix, R_{φ+ψ} = R_φ R_ψ).
  virtual bool HasRotationSymmetry() const { return false; }
  // x ← R_φ x.
  virtual void Rotate(double /*phi*/, VectorRef /*x*/) const {}
  // g = d/dφ (R_φ x) at φ = 0, the infinitesimal generator applied to x.
  virtual void RotationGenerator(ConstVectorRef /*x*/, VectorRef /*g*/) const {}

  // Optional mirror symmetry: a linear involution κ of the state (κ² = I) with f(t, κx) = κ f(t, x),
  // commuting with Rotate — e.g. the exchange of the two contacts of a left–right symmetric rotor.
  // An orbit in its fixed space (κx(t) = x(t)) can lose stability to a κ-odd perturbation: a
  // symmetry-breaking pitchfork, whose two new branches are each other's mirror images.
  virtual bool HasMirrorSymmetry() const { return false; }
  // x ← κ x.
  virtual void Mirror(VectorRef /*x*/) const {}

  // Optional switching surfaces of a piecewise-smooth vector field: SwitchingCount() functions
  // h_k(t, x) whose zeros are where f changes law (a contact closing or opening: h = its
  // penetration). An integrator that steps across such a zero sees a kink in f (or a jump) and
  // loses accuracy and smoothness in x0 there; stopped and restarted at the zero (EventOptions::
  // restart) it integrates each smooth piece on its own (shooting/shooting.h uses this).
  virtual int SwitchingCount() const { return 0; }
  virtual void SwitchingFunctions(double /*t*/, ConstVectorRef /*x*/, VectorRef /*h*/) const {}
  // Optional, for IntegratorOptions::land_on_switches: per switching function a bound b_k ≥
  // |h_k(t + s, x + s f) − h_k(t, x)| for this s > 0 and f = f(t, x), both h as evaluated in
  // floating point with x + s f rounded componentwise (within a few ulps). With it the integrator
  // skips predicting a switch that cannot come within the step (the prediction's own cost on A(a)
  // in full contact, where no contact switches: bench/march_bench.cpp). Returns false where the
  // system gives no bound (the default: every step predicts).
  virtual bool SwitchingIncrementBounds(double /*t*/, ConstVectorRef /*x*/, ConstVectorRef /*f*/,
                                        double /*s*/, VectorRef /*bound*/) const {
    return false;
  }

  // Optional chart of the state space, x = Ψ(y) (Dimension() coordinates both), in which the
  // system's invariant sets are represented with less error than in x: where a stiff contact
  // holds a state within nanometres of a surface (its penetration) while the state moves by
  // micrometres along it, a curve interpolated in x leaves the surface by its interpolation
  // error, in y (the penetration one of the coordinates) by that error relative to the
  // penetration's own variation (shooting/invariant_circle.h uses it; the rub models' chart in
  // models/rub_model.h). Coordinates listed by ChartAngles are angles: Ψ is 2π-periodic in each,
  // ToChart returns them in (−π, π], and a caller comparing two of them takes the difference
  // modulo 2π. Default: none.
  virtual bool HasStateChart() const { return false; }
  // y = Ψ⁻¹(x).
  virtual void ToChart(ConstVectorRef x, VectorRef y) const { y = x; }
  // x = Ψ(y), and ∂Ψ/∂y into `jacobian` when it is not null.
  virtual void FromChart(ConstVectorRef y, VectorRef x, Matrix* jacobian = nullptr) const {
    x = y;
    if (jacobian) jacobian->setIdentity(Dimension(), Dimension());
  }
  // The typical size of each chart coordinate (as StateScale for x).
  virtual Vector ChartScale() const { return StateScale(); }
  virtual std::vector<Index> ChartAngles() const { return {}; }
};

}  // namespace rubcont
