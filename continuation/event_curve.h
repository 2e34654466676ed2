// Event curves: two-parameter continuation of the located events of a piecewise-smooth problem.
//
// On one smooth piece of an inner problem F(u, λ; η) = 0 with validity margins m_j(u, λ; η)
// (Problem::EventFunctions), an event point — where the branch leaves the piece, e.g. a contact
// switching from stick to slip — is a regular solution of the n + 1 equations
//     F(u, λ; η) = 0,   m_k(u, λ; η) = 0
// in the n + 1 unknowns U = (u, λ), for a fixed event k, just as a fold is a solution of
// [F; g] = 0 (continuation/fold.h). Continued in η by the same engine, it traces the curve in the
// (λ, η) plane along which the speed sweep's jump moves: the analogue for a non-smooth fold (or a
// plain switch) of a fold curve. Its tangent's η-component vanishes where the curve turns back in
// η; the engine reports that as a fold of the event curve.
//
// The curve is only meaningful while the event point lies on the piece: every other margin must
// stay ≥ 0 there. The other margins that are positive at the start are this problem's own event
// functions, and SwitchAt refuses, so the engine ends the curve where one of them vanishes
// (status kSwitchRefused, the special point labelled with that margin's name): a codimension-two
// point where two events meet. Margins that vanish at the start with m_k (simultaneous events of
// symmetric contacts) are not monitored; PartnerMargins() lists them.
//
// The margins of the inner problem are expected to be scaled (O(1) over the branch, as
// RotatingWaveProblem's are): the added equation has residual scale 1.
#pragma once

#include <string>
#include <vector>

#include "continuation/branch.h"
#include "continuation/continuation.h"
#include "continuation/options.h"
#include "continuation/problem.h"

namespace rubcont {

class EventCurveProblem : public Problem {
 public:
  // `inner` must have a second parameter and stay on its current piece (no SwitchAt is called on
  // it). (u, λ): a point at or near the event k at the inner's current η, used to decide which
  // other margins are monitored. Throws std::invalid_argument when the inner problem has no second
  // parameter, k is not one of its events, or u has the wrong size.
  EventCurveProblem(Problem& inner, int event, const Vector& u, double lambda);

  Index Dimension() const override { return n_ + 1; }
  // [F(u, λ; η); m_k(u, λ; η)], U = (u, λ).
  void Residual(const Vector& U, double eta, Vector& G) override;
  // [F_u F_λ; ∇m_k] with ∇m_k by central differences in the inner's scaled variables.
  void Jacobian(const Vector& U, double eta, Matrix& DG) override;
  // [F_η; ∂m_k/∂η].
  void DfDlambda(const Vector& U, double eta, Vector& dG) override;
  Vector Scale() const override;
  double LambdaScale() const override { return inner_.SecondParameterScale(); }
  Vector ResidualScale() const override;

  // "lambda" followed by the inner problem's measures.
  std::vector<std::string> MeasureNames() const override;
  Vector Measures(const Vector& U, double eta) override;

  // The monitored margins (see above); the curve ends where one vanishes.
  std::vector<std::string> EventNames() const override;
  Vector EventFunctions(const Vector& U, double eta) override;
  bool SwitchAt(int /*event*/, Vector& /*U*/, double /*eta*/) override { return false; }
  std::string PieceLabel() const override { return inner_.PieceLabel(); }

  void PointAccepted(const Vector& U, double eta) override;

  int event() const { return event_; }
  const std::string& event_name() const { return event_name_; }
  // Names of the inner margins that vanish with m_k at the start and are not monitored.
  const std::vector<std::string>& PartnerMargins() const { return partner_names_; }

 private:
  // Sets the inner η; false when the inner problem rejects it (std::invalid_argument: outside
  // its physical range), and then residuals, Jacobians and margins are NaN, which the engine
  // treats as a failed corrector step (it halves the step) rather than an exception.
  bool SetEta(double eta);
  double Margin(const Vector& U, double eta);

  Problem& inner_;
  int event_;
  Index n_;
  std::string event_name_;
  std::vector<int> monitored_;
  std::vector<std::string> monitored_names_;
  std::vector<std::string> partner_names_;
  Vector s_;
  double s_lambda_;
  Vector r_;
};

// Continues the event curve through a located event point of `problem` (a kEvent special point of
// a branch computed on the same problem, with the problem set to the piece that ends there) in the
// second parameter η, both ways from the current η, and joins the halves (JoinAtStart). The
// branch's λ is η; its measure "lambda" is the inner λ. The options apply to the curve
// (bounds.lambda_min/max bound η). The inner η is restored at the end. Throws
// std::invalid_argument when the point is not an event, its label is not an event of the current
// piece, or the problem has no second parameter.
Branch ContinueEventCurve(Problem& problem, const SpecialPoint& event_point,
                          const ContinuationOptions& options = {});

}  // namespace rubcont
