#include "models/contact.h"

#include <cmath>

namespace rubcont {

namespace {

// j·v for a planar vector: rotation by +90°.
Vector2 Perp(const Vector2& v) { return Vector2(-v.y(), v.x()); }

}  // namespace

void EvaluateContact(const ContactLaw& law, const ContactGeometry& geometry, double omega,
                     const Vector2& d, const Vector2& ddot, FrictionMode mode, double stick_force,
                     bool with_derivatives, ContactEvaluation& out) {
  // The derivatives are reset only when asked for (they are read only then): time marching calls
  // this millions of times per simulated second without them.
  out.touching = false;
  out.normal_force = 0.0;
  out.friction_force = 0.0;
  out.force.setZero();
  if (with_derivatives) {
    out.dN_dd.setZero();
    out.dN_dddot.setZero();
    out.dV_dd.setZero();
    out.dV_dddot.setZero();
    out.df_dd.setZero();
    out.df_dddot.setZero();
    out.df_domega.setZero();
    out.df_dF.setZero();
  }
  const double rho = d.norm();
  out.penetration = rho - geometry.clearance;
  out.normal.setZero();
  out.tangent.setZero();
  if (rho > 0.0) {
    out.normal = d / rho;
    out.tangent = Perp(out.normal);
  }
  const Vector2& n = out.normal;
  const Vector2& t = out.tangent;
  out.penetration_rate = n.dot(ddot);
  out.slip_velocity = omega * geometry.radius + t.dot(ddot);

  // ∂V/∂d and ∂V/∂ḋ are needed even without contact (stick/slip events use V everywhere).
  Matrix2 dn_dd = Matrix2::Zero();  // (I − n nᵀ)/ρ
  if (with_derivatives && rho > 0.0) {
    dn_dd = (Matrix2::Identity() - n * n.transpose()) / rho;
    Matrix2 rotation;  // J2: v ↦ j v
    rotation << 0.0, -1.0, 1.0, 0.0;
    out.dV_dd = ddot.transpose() * rotation * dn_dd;
    out.dV_dddot = t.transpose();
  }

  const double delta = out.penetration;
  if (mode == FrictionMode::kInactive) return;
  // The other modes hold the contact closed: the force law continues smoothly past δ = 0 (N < 0),
  // so each piece of a piecewise formulation stays smooth; its caller checks the margin δ ≥ 0.
  const bool held = mode != FrictionMode::kRegularized;
  if (!held && !(delta > 0.0)) return;
  const double delta_dot = out.penetration_rate;
  const double normal = law.stiffness * delta + law.stiffness2 * delta * delta +
                        law.damping * delta_dot * delta;
  if (!held && !(normal > 0.0)) return;  // Hunt–Crossley force clamped at zero while separating
  out.touching = true;
  out.normal_force = normal;

  double sigma = 0.0;       // F = μ N σ  (σ = tanh(V/ε) or ±1)
  double dsigma_dV = 0.0;
  switch (mode) {
    case FrictionMode::kRegularized:
    case FrictionMode::kRegularizedHeld: {
      sigma = std::tanh(out.slip_velocity / law.velocity_scale);
      dsigma_dV = (1.0 - sigma * sigma) / law.velocity_scale;
      break;
    }
    case FrictionMode::kSlipPositive: sigma = 1.0; break;
    case FrictionMode::kSlipNegative: sigma = -1.0; break;
    case FrictionMode::kStick: break;
    case FrictionMode::kInactive: break;  // not reached: returned above
  }
  const double mu = law.friction;
  out.friction_force = mode == FrictionMode::kStick ? stick_force : mu * normal * sigma;
  out.force = -normal * n - out.friction_force * t;

  if (!with_derivatives) return;
  Matrix2 rotation;
  rotation << 0.0, -1.0, 1.0, 0.0;
  out.dN_dd = (law.stiffness + 2.0 * law.stiffness2 * delta + law.damping * delta_dot) *
                  n.transpose() +
              law.damping * delta * ddot.transpose() * dn_dd;
  out.dN_dddot = law.damping * delta * n.transpose();

  RowVector2 dF_dd = RowVector2::Zero(), dF_dddot = RowVector2::Zero();
  if (mode != FrictionMode::kStick) {
    dF_dd = mu * sigma * out.dN_dd + mu * normal * dsigma_dV * out.dV_dd;
    dF_dddot = mu * sigma * out.dN_dddot + mu * normal * dsigma_dV * out.dV_dddot;
    out.df_domega = -t * (mu * normal * dsigma_dV * geometry.radius);
  } else {
    out.df_dF = -t;
  }
  out.df_dd = -n * out.dN_dd - normal * dn_dd - t * dF_dd - out.friction_force * rotation * dn_dd;
  out.df_dddot = -n * out.dN_dddot - t * dF_dddot;
}

}  // namespace rubcont
