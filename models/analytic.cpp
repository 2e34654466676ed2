#include "models/analytic.h"

#include "models/units.h"
#include "solvers/scalar_root.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include <Eigen/Eigenvalues>

namespace rubcont {
namespace {

using Complex = std::complex<double>;
using ComplexMatrix2 = Eigen::Matrix2cd;

// m [[(1−c)², c(1−c)], [c(1−c), c²]] + (I/L²) [[1, −1], [−1, 1]]: a rigid body of mass m and
// transverse inertia I about its mass centre, described by its displacements at two planes L apart,
// the mass centre at the fraction c of the way from the first plane (c > 1 or c < 0: outside).
Matrix2 RigidBodyMassMatrix(double mass, double inertia, double span, double c) {
  const double j = inertia / (span * span);
  Matrix2 M;
  M << mass * (1.0 - c) * (1.0 - c) + j, mass * c * (1.0 - c) - j,
       mass * c * (1.0 - c) - j,         mass * c * c + j;
  return M;
}

// Undamped modes of K v = ω² M v, labelled bounce (in phase) and pitch (antiphase) by shape.
std::pair<NaturalMode, NaturalMode> BounceAndPitch(const Matrix2& K, const Matrix2& M) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Matrix2> solver(K, M);
  NaturalMode modes[2];
  double in_phase[2];
  for (int i = 0; i < 2; ++i) {
    Vector2 v = solver.eigenvectors().col(i);
    const Index largest = std::abs(v(0)) >= std::abs(v(1)) ? 0 : 1;
    v /= v(largest);  // largest entry becomes +1
    modes[i].frequency_hz = RadPerSecondToHz(std::sqrt(std::max(solver.eigenvalues()(i), 0.0)));
    modes[i].shape = v;
    in_phase[i] = v(0) * v(1) / v.squaredNorm();
  }
  // Ties (both shapes with a zero entry: decoupled stations) go to ordering: lower = bounce.
  const int bounce = in_phase[1] > in_phase[0] ? 1 : 0;
  return {modes[bounce], modes[1 - bounce]};
}

// The closed form for one mode with everything that does not depend on Ω precomputed.
class ModeEvaluator {
 public:
  ModeEvaluator(const TwoPointParams& p, CircularMode mode)
      : rotor_mass_inverse_(RotorMassMatrix(p).inverse()),
        stator_mass_(StatorMassMatrix(p)),
        stiffness_(SupportStiffnessMatrix(p)),
        damping_(SupportDampingMatrix(p)),
        sign_(ContactSign(mode)),
        center_damping_(p.center_damping) {
    relative_amplitude_ << p.clearance[0], sign_ * p.clearance[1];  // d0 = S C [m]
    // wᵀ d0 with w = (½, ½): relative displacement of the mid-points [m].
    midpoint_amplitude_ = 0.5 * (relative_amplitude_(0) + relative_amplitude_(1));
  }

  // S P − f_d = W⁻¹ d0: the net force amplitude the stator receives [N]; fills P and f_d.
  ComplexVector2 Forces(double omega, ComplexVector2& contact_force, ComplexVector2& damper_force,
                        ComplexMatrix2* stator_receptance = nullptr) const {
    const Complex j(0.0, 1.0);
    const ComplexMatrix2 Z = stiffness_.cast<Complex>() - (omega * omega) * stator_mass_.cast<Complex>() -
                             (j * omega) * damping_.cast<Complex>();
    const ComplexMatrix2 Z_inverse = Z.inverse();
    const ComplexMatrix2 W = rotor_mass_inverse_.cast<Complex>() / (omega * omega) - Z_inverse;
    const ComplexVector2 net = W.inverse() * relative_amplitude_.cast<Complex>();
    // f_d = jΩ c_d w wᵀ d0: both entries j Ω c_d (wᵀ d0) / 2.
    damper_force.setConstant(j * (0.5 * omega * center_damping_ * midpoint_amplitude_));
    const ComplexVector2 s_p = net + damper_force;  // S P = W⁻¹ d0 + f_d
    contact_force << s_p(0), static_cast<double>(sign_) * s_p(1);
    if (stator_receptance != nullptr) *stator_receptance = Z_inverse;
    return net;
  }

  ComplexVector2 ContactForce(double omega) const {
    ComplexVector2 contact_force, damper_force;
    Forces(omega, contact_force, damper_force);
    return contact_force;
  }

  CircularOrbit Orbit(double omega) const {
    CircularOrbit orbit;
    orbit.precession = omega;
    ComplexMatrix2 Z_inverse;
    const ComplexVector2 net = Forces(omega, orbit.contact_force, orbit.damper_force, &Z_inverse);
    // −Ω² M_r r0 = −S P + f_d  ⇒  r0 = M_r⁻¹ (S P − f_d) / Ω²;   Z s0 = S P − f_d.
    orbit.rotor_amplitude = rotor_mass_inverse_.cast<Complex>() * net / (omega * omega);
    orbit.stator_amplitude = Z_inverse * net;
    return orbit;
  }

 private:
  Matrix2 rotor_mass_inverse_;
  Matrix2 stator_mass_;
  Matrix2 stiffness_;
  Matrix2 damping_;
  int sign_;
  double center_damping_;
  Vector2 relative_amplitude_;
  double midpoint_amplitude_ = 0.0;
};

int SignOf(double x) { return (x > 0.0) - (x < 0.0); }

// The root of f in the grid bracket [a, b] (f(a)·f(b) < 0) to a few ulps of the frequency, by
// Illinois regula falsi (solvers/scalar_root.h); the closed form never fails to evaluate.
template <class Function>
double RefineRoot(const Function& f, double a, double b, double fa, double fb) {
  BracketedRootOptions options;
  options.max_evaluations = 200;
  options.x_tolerance = 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b));
  const auto evaluate = [&f](double x, double& value) {
    value = f(x);
    return true;
  };
  return IllinoisRoot(evaluate, a, fa, b, fb, options).x;
}

// One scalar function on the grid whose sign changes are transitions.
enum class Quantity { kMuExcess, kMuDeficit, kFriction, kNormalForce };

double EvaluateQuantity(Quantity quantity, const ComplexVector2& P, int k, double mu) {
  switch (quantity) {
    case Quantity::kMuExcess: return P(k).imag() - mu * P(k).real();   // F − μN
    case Quantity::kMuDeficit: return P(k).imag() + mu * P(k).real();  // F + μN
    case Quantity::kFriction: return P(k).imag();                      // F
    case Quantity::kNormalForce: return P(k).real();                   // N
  }
  return 0.0;
}

std::string FormatHz(double hz) {
  std::ostringstream out;
  out << hz;
  return out.str();
}

}  // namespace

const char* ToString(CircularMode mode) {
  switch (mode) {
    case CircularMode::kMode1: return "mode1";
    case CircularMode::kMode2: return "mode2";
    case CircularMode::kSingleContact: return "single";
  }
  return "?";
}

int ContactSign(CircularMode mode) { return mode == CircularMode::kMode2 ? -1 : 1; }

const char* ToString(TransitionType type) {
  switch (type) {
    case TransitionType::kMuCrossing: return "mu_crossing";
    case TransitionType::kNegativeMuCrossing: return "negative_mu_crossing";
    case TransitionType::kZeroMuCrossing: return "zero_mu_crossing";
    case TransitionType::kContactLoss: return "contact_loss";
    case TransitionType::kContactRegain: return "contact_regain";
  }
  return "?";
}

const char* ToString(AnalyticStatus status) {
  return status == AnalyticStatus::kSuccess ? "success" : "non_finite";
}

Matrix2 RotorMassMatrix(const TwoPointParams& p) {
  return RigidBodyMassMatrix(p.rotor_mass, p.rotor_inertia, p.contact_span, p.a());
}

Matrix2 StatorMassMatrix(const TwoPointParams& p) {
  return RigidBodyMassMatrix(p.stator_mass, p.stator_inertia, p.stator_span, p.b());
}

Matrix2 SupportStiffnessMatrix(const TwoPointParams& p) {
  return Vector2(p.support_stiffness[0], p.support_stiffness[1]).asDiagonal();
}

Matrix2 SupportDampingMatrix(const TwoPointParams& p) {
  return Vector2(p.support_damping[0], p.support_damping[1]).asDiagonal();
}

NaturalFrequencies ComputeNaturalFrequencies(const TwoPointParams& p) {
  Validate(p);
  const Matrix2 K = SupportStiffnessMatrix(p);
  const Matrix2 M_s = StatorMassMatrix(p);
  NaturalFrequencies result;
  std::tie(result.stator_bounce, result.stator_pitch) = BounceAndPitch(K, M_s);
  std::tie(result.pinned_bounce, result.pinned_pitch) = BounceAndPitch(K, M_s + RotorMassMatrix(p));
  return result;
}

CircularOrbit SolveCircularOrbit(const TwoPointParams& p, CircularMode mode, double precession) {
  Validate(p);
  if (!(std::isfinite(precession) && precession > 0.0)) {
    std::ostringstream message;
    message << "SolveCircularOrbit: precession = " << precession
            << ": must be positive and finite (rad/s)";
    throw std::invalid_argument(message.str());
  }
  return ModeEvaluator(p, mode).Orbit(precession);
}

void Validate(const AnalyticOptions& options) {
  auto fail = [](const char* field, double value, const char* rule) {
    std::ostringstream message;
    message << "AnalyticOptions." << field << " = " << value << ": " << rule;
    throw std::invalid_argument(message.str());
  };
  if (!(std::isfinite(options.min_precession_hz) && options.min_precession_hz > 0.0))
    fail("min_precession_hz", options.min_precession_hz, "must be positive and finite (Hz)");
  if (!(std::isfinite(options.max_precession_hz) &&
        options.max_precession_hz > options.min_precession_hz))
    fail("max_precession_hz", options.max_precession_hz,
         "must be finite and greater than min_precession_hz (Hz)");
  if (options.precession_points < 2)
    fail("precession_points", options.precession_points, "must be at least 2");
}

AnalyticCurve ComputeAnalyticCurve(const TwoPointParams& p, CircularMode mode,
                                   const AnalyticOptions& options) {
  Validate(p);
  if (mode == CircularMode::kSingleContact) {
    throw std::invalid_argument("ComputeAnalyticCurve: the two-point model has Mode 1 and Mode 2 only");
  }
  const ModeEvaluator evaluator(p, mode);
  return ComputeClosedFormCurve(
      [&](double omega) { return evaluator.ContactForce(omega); }, 2, p.friction, mode, options);
}

AnalyticCurve ComputeClosedFormCurve(const std::function<ComplexVector2(double precession)>& contact_force,
                                     int contacts, double mu, CircularMode mode,
                                     const AnalyticOptions& options) {
  Validate(options);
  if (contacts < 1 || contacts > 2) {
    throw std::invalid_argument("ComputeClosedFormCurve: contacts = " + std::to_string(contacts) +
                                ": must be 1 or 2");
  }
  const Index n = options.precession_points;

  AnalyticCurve curve;
  curve.mode = mode;
  curve.precession_hz =
      Vector::LinSpaced(n, options.min_precession_hz, options.max_precession_hz);
  for (int k = 0; k < contacts; ++k) {
    curve.normal_force[k].resize(n);
    curve.friction_force[k].resize(n);
    curve.mu_required[k].resize(n);
  }
  std::vector<ComplexVector2> forces(n);
  for (Index i = 0; i < n; ++i) {
    forces[i] = contact_force(HzToRadPerSecond(curve.precession_hz(i)));
    for (int k = 0; k < contacts; ++k) {
      curve.normal_force[k](i) = forces[i](k).real();
      curve.friction_force[k](i) = forces[i](k).imag();
      curve.mu_required[k](i) = forces[i](k).imag() / forces[i](k).real();
      if (curve.Succeeded() && !std::isfinite(std::abs(forces[i](k)))) {
        curve.status = AnalyticStatus::kNonFinite;
        curve.message = std::string(ToString(mode)) + ": contact force not finite at " +
                        FormatHz(curve.precession_hz(i)) + " Hz (" +
                        (contacts == 1 ? "the" : (k == 0 ? "left" : "right")) + " contact)";
      }
    }
  }

  // Transitions: sign changes between neighbouring grid points, refined on the closed form.
  for (int k = 0; k < contacts; ++k) {
    for (Quantity quantity : {Quantity::kMuExcess, Quantity::kMuDeficit, Quantity::kFriction,
                              Quantity::kNormalForce}) {
      // With μ = 0 all three μ crossings are the same root: keep it once.
      if (quantity != Quantity::kMuExcess && quantity != Quantity::kNormalForce && mu == 0.0) continue;
      auto f = [&](double hz) {
        return EvaluateQuantity(quantity, contact_force(HzToRadPerSecond(hz)), k, mu);
      };
      for (Index i = 0; i + 1 < n; ++i) {
        const double a = curve.precession_hz(i), b = curve.precession_hz(i + 1);
        const double fa = EvaluateQuantity(quantity, forces[i], k, mu);
        const double fb = EvaluateQuantity(quantity, forces[i + 1], k, mu);
        if (!(std::isfinite(fa) && std::isfinite(fb))) continue;
        const int sa = SignOf(fa), sb = SignOf(fb);
        double root;
        if (sa * sb < 0) {
          root = RefineRoot(f, a, b, fa, fb);
        } else if (sa == 0 && i > 0 &&
                   SignOf(EvaluateQuantity(quantity, forces[i - 1], k, mu)) * sb < 0) {
          root = a;  // exactly on a grid point
        } else {
          continue;
        }
        const ComplexVector2 P = contact_force(kTwoPi * root);
        // A sign change through a pole (|value| grows instead of vanishing) is not a root.
        const bool through_pole =
            std::abs(EvaluateQuantity(quantity, P, k, mu)) > std::max(std::abs(fa), std::abs(fb));
        const int direction = sb > 0 ? 1 : -1;  // sign of the quantity just above the root
        Transition t;
        t.contact = k;
        t.precession_hz = root;
        t.normal_force = P(k).real();
        if (quantity == Quantity::kNormalForce) {
          t.type = direction > 0 ? TransitionType::kContactRegain : TransitionType::kContactLoss;
          t.direction = direction;
          t.through_pole = through_pole;
        } else {
          // μ_req − c = (F − cN)/N: with N > 0 it changes sign with F − cN. Out of contact
          // (N ≤ 0) μ_req means nothing, nor where N vanishes (with no friction force, on
          // undamped supports, F − cN changes sign with N, and rounding leaves N ≈ 1e-13 N > 0
          // at that root: N must exceed 1e-9 of its size at the neighbours); through a pole of
          // P, μ_req = F/N stays finite.
          const double n_scale = std::abs(forces[i](k).real()) + std::abs(forces[i + 1](k).real());
          if (through_pole || !(t.normal_force > 1e-9 * n_scale)) continue;
          t.type = quantity == Quantity::kMuExcess    ? TransitionType::kMuCrossing
                   : quantity == Quantity::kMuDeficit ? TransitionType::kNegativeMuCrossing
                                                      : TransitionType::kZeroMuCrossing;
          t.direction = direction;
        }
        curve.transitions.push_back(t);
      }
    }
  }
  std::sort(curve.transitions.begin(), curve.transitions.end(),
            [](const Transition& x, const Transition& y) {
              return x.precession_hz != y.precession_hz ? x.precession_hz < y.precession_hz
                                                        : x.contact < y.contact;
            });
  return curve;
}

AnalyticResult ComputeAnalytic(const TwoPointParams& p, const AnalyticOptions& options) {
  AnalyticResult result;
  result.natural_frequencies = ComputeNaturalFrequencies(p);
  result.mode1 = ComputeAnalyticCurve(p, CircularMode::kMode1, options);
  result.mode2 = ComputeAnalyticCurve(p, CircularMode::kMode2, options);
  return result;
}

}  // namespace rubcont
