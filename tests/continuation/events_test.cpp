// Events of piecewise-smooth problems: location, switching, orientation on the new piece.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "test_problems.h"

namespace rubcont {
namespace {

using testing::Vec;

// One smooth piece: F(u, λ) with its Jacobian and ∂F/∂λ, and its validity margins (≥ 0 valid).
struct Piece {
  std::string label;
  Index n = 1;
  std::function<void(const Vector&, double, Vector&)> F;
  std::function<void(const Vector&, double, Matrix&)> J;
  std::function<void(const Vector&, double, Vector&)> dF;
  std::string event_name;
  std::function<double(const Vector&, double)> margin;
};

// Two pieces A → B; at A's event the problem switches to B, mapping u with `to_b` (which may
// change the dimension), unless `refuse` is set.
class TwoPieceProblem : public Problem {
 public:
  TwoPieceProblem(Piece a, Piece b, std::function<Vector(const Vector&)> to_b)
      : pieces_{std::move(a), std::move(b)}, to_b_(std::move(to_b)) {}

  Index Dimension() const override { return piece().n; }
  void Residual(const Vector& u, double l, Vector& F) override {
    F.resize(piece().n);
    piece().F(u, l, F);
  }
  void Jacobian(const Vector& u, double l, Matrix& J) override {
    J.resize(piece().n, piece().n);
    piece().J(u, l, J);
  }
  void DfDlambda(const Vector& u, double l, Vector& dF) override {
    dF.resize(piece().n);
    piece().dF(u, l, dF);
  }
  std::vector<std::string> EventNames() const override { return {piece().event_name}; }
  Vector EventFunctions(const Vector& u, double l) override {
    ++event_evaluations;
    return Vec({piece().margin(u, l)});
  }
  bool SwitchAt(int event, Vector& u, double) override {
    switch_calls.push_back(event);
    if (refuse || active_ == 1) return false;
    active_ = 1;
    u = to_b_(u);
    return true;
  }
  std::string PieceLabel() const override { return piece().label; }

  bool refuse = false;
  std::vector<int> switch_calls;
  long event_evaluations = 0;

 private:
  const Piece& piece() const { return pieces_[active_]; }
  Piece pieces_[2];
  int active_ = 0;
  std::function<Vector(const Vector&)> to_b_;
};

// A scalar piece F = φ(x) − λ·slope... given as residual x − f(λ) with f linear or cubic.
Piece Scalar(std::string label, std::function<double(double, double)> F,
             std::function<double(double, double)> Fx, std::function<double(double, double)> Fl,
             std::string event, std::function<double(double)> margin) {
  Piece p;
  p.label = std::move(label);
  p.n = 1;
  p.F = [F](const Vector& u, double l, Vector& out) { out(0) = F(u(0), l); };
  p.J = [Fx](const Vector& u, double l, Matrix& J) { J(0, 0) = Fx(u(0), l); };
  p.dF = [Fl](const Vector& u, double l, Vector& dF) { dF(0) = Fl(u(0), l); };
  p.event_name = std::move(event);
  p.margin = [margin](const Vector& u, double) { return margin(u(0)); };
  return p;
}

ContinuationOptions Bounds(double lo, double hi) {
  ContinuationOptions options;
  options.bounds.lambda_min = lo;
  options.bounds.lambda_max = hi;
  return options;
}

TEST_CASE("an event is located, the problem switches (changing dimension) and the branch goes on",
          "[continuation][events]") {
  // A: x³ + x − λ = 0, valid while x ≤ 1/2 (event at λ = 5/8). B: the same x and a new unknown
  // y = x − 1/2, valid while y ≥ 0. Closed form after the switch: y = x − 1/2 with x³ + x = λ.
  Piece a = Scalar(
      "A", [](double x, double l) { return x * x * x + x - l; },
      [](double x, double) { return 3 * x * x + 1; }, [](double, double) { return -1.0; },
      "x reaches 1/2", [](double x) { return 0.5 - x; });
  Piece b;
  b.label = "B";
  b.n = 2;
  b.F = [](const Vector& u, double l, Vector& F) {
    F << u(0) * u(0) * u(0) + u(0) - l, u(1) - (u(0) - 0.5);
  };
  b.J = [](const Vector& u, double, Matrix& J) { J << 3 * u(0) * u(0) + 1, 0.0, -1.0, 1.0; };
  b.dF = [](const Vector&, double, Vector& dF) { dF << -1.0, 0.0; };
  b.event_name = "y reaches 0";
  b.margin = [](const Vector& u, double) { return u(1); };
  TwoPieceProblem problem(a, b, [](const Vector& u) { return Vec({u(0), 0.0}); });

  const Branch branch = Continue(problem, Vec({0.0}), 0.0, Bounds(-1.0, 2.0));
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.Count(SpecialPointType::kEvent) == 1);
  const SpecialPoint& event = branch.special_points.front();
  CHECK(event.label == "x reaches 1/2");
  CHECK(event.Name() == "event: x reaches 1/2");
  CHECK(event.piece == "A");
  CHECK(event.converged);
  CHECK(std::abs(event.lambda - 0.625) <= 1e-10);
  CHECK(std::abs(event.u(0) - 0.5) <= 1e-10);
  CHECK_FALSE(event.nonsmooth_fold);
  CHECK(problem.switch_calls == std::vector<int>{0});
  CHECK(branch.statistics.switches == 1);
  // The event point ends piece A and starts piece B.
  const BranchPoint& end_a = branch.points[event.index + 1];
  const BranchPoint& start_b = branch.points[event.index + 2];
  CHECK(end_a.piece == "A");
  CHECK(start_b.piece == "B");
  CHECK(end_a.lambda == start_b.lambda);
  CHECK(end_a.u.size() == 1);
  CHECK(start_b.u.size() == 2);
  // Every point is on its piece and inside it; B runs to λ = 2 where x = 1, y = 1/2.
  for (const BranchPoint& p : branch.points) {
    CHECK(std::abs(p.u(0) * p.u(0) * p.u(0) + p.u(0) - p.lambda) <= 1e-10);
    if (p.piece == "A") CHECK(p.u(0) <= 0.5 + 1e-10);
    if (p.piece == "B") CHECK(p.u(1) == Approx(p.u(0) - 0.5).epsilon(0).margin(1e-10));
  }
  CHECK(branch.points.back().piece == "B");
  CHECK(branch.points.back().u(0) == Approx(1.0).epsilon(0).margin(1e-9));
  CHECK(branch.points.back().u(1) == Approx(0.5).epsilon(0).margin(1e-9));
  // Column accessors pad the missing second unknown of piece A with NaN.
  CHECK(std::isnan(branch.StateComponent(1)(0)));
}

TEST_CASE("a switch onto a piece that is valid only backwards is a non-smooth fold",
          "[continuation][events]") {
  // A: x = λ, valid while x ≤ 1. B: x = 1 + s(1 − λ), valid while x ≥ 1. Past λ = 1 B would need
  // x < 1: the solution set turns back at (1, 1) and continues on B towards λ → −∞. With s = 2
  // the new tangent oriented by its dot product with the old one already points the valid way;
  // with s = 1/2 it points back into A's region and the engine must turn it round.
  const double s = GENERATE(2.0, 0.5);
  Piece a = Scalar(
      "A", [](double x, double l) { return x - l; }, [](double, double) { return 1.0; },
      [](double, double) { return -1.0; }, "x reaches 1", [](double x) { return 1.0 - x; });
  Piece b = Scalar(
      "B", [s](double x, double l) { return x - 1.0 - s * (1.0 - l); },
      [](double, double) { return 1.0; }, [s](double, double) { return s; }, "x falls to 1",
      [](double x) { return x - 1.0; });
  TwoPieceProblem problem(a, b, [](const Vector& u) { return u; });
  const Branch branch = Continue(problem, Vec({0.0}), 0.0, Bounds(-1.0, 3.0));
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.Count(SpecialPointType::kEvent) == 1);
  const SpecialPoint& event = branch.special_points.front();
  CHECK(std::abs(event.lambda - 1.0) <= 1e-10);
  CHECK(event.nonsmooth_fold);
  CHECK(event.note.find("non-smooth fold") != std::string::npos);
  if (s < 1.0) CHECK(event.note.find("turns back into the region") != std::string::npos);
  // The branch went back down in λ along B and ends at λ_min = −1 with x = 1 + 2s.
  CHECK(branch.points.back().piece == "B");
  CHECK(branch.points.back().lambda == Approx(-1.0).epsilon(0).margin(1e-12));
  CHECK(branch.points.back().u(0) == Approx(1.0 + 2.0 * s).epsilon(0).margin(1e-9));
  for (const BranchPoint& p : branch.points) {
    if (p.piece == "B") CHECK(p.u(0) >= 1.0 - 1e-10);
  }
  // No smooth fold is reported at the corner.
  CHECK(branch.Count(SpecialPointType::kFold) == 0);
}

TEST_CASE("a switch onto a piece that continues forwards keeps the direction",
          "[continuation][events]") {
  // A: x = λ valid while x ≤ 1; B: x = 1 + 2(λ − 1) valid while x ≥ 1: a kink, not a fold.
  Piece a = Scalar(
      "A", [](double x, double l) { return x - l; }, [](double, double) { return 1.0; },
      [](double, double) { return -1.0; }, "x reaches 1", [](double x) { return 1.0 - x; });
  Piece b = Scalar(
      "B", [](double x, double l) { return x - 1.0 - 2.0 * (l - 1.0); },
      [](double, double) { return 1.0; }, [](double, double) { return -2.0; }, "x falls to 1",
      [](double x) { return x - 1.0; });
  TwoPieceProblem problem(a, b, [](const Vector& u) { return u; });
  const Branch branch = Continue(problem, Vec({0.0}), 0.0, Bounds(-1.0, 2.0));
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.Count(SpecialPointType::kEvent) == 1);
  CHECK_FALSE(branch.special_points.front().nonsmooth_fold);
  CHECK(branch.points.back().lambda == Approx(2.0).epsilon(0).margin(1e-12));
  CHECK(branch.points.back().u(0) == Approx(3.0).epsilon(0).margin(1e-9));
}

TEST_CASE("a refused switch ends the branch at the event", "[continuation][events]") {
  Piece a = Scalar(
      "A", [](double x, double l) { return x - l * l; }, [](double, double) { return 1.0; },
      [](double, double l) { return -2.0 * l; }, "x reaches 2", [](double x) { return 2.0 - x; });
  TwoPieceProblem problem(a, a, [](const Vector& u) { return u; });
  problem.refuse = true;
  const Branch branch = Continue(problem, Vec({0.0}), 0.0, Bounds(-1.0, 3.0));
  INFO(branch.BriefReport());
  CHECK(branch.status == BranchStatus::kSwitchRefused);
  CHECK_FALSE(IsFailure(branch.status));
  CHECK(branch.message.find("x reaches 2") != std::string::npos);
  REQUIRE(branch.Count(SpecialPointType::kEvent) == 1);
  CHECK(std::abs(branch.points.back().lambda - std::sqrt(2.0)) <= 1e-10);
  CHECK(std::abs(branch.points.back().u(0) - 2.0) <= 1e-10);
}

TEST_CASE("a new piece invalid both ways ends the branch there", "[continuation][events]") {
  // B: x = 1 − (λ − 1)² touches x = 1 from below: B's margin x − 1 is negative both ways.
  Piece a = Scalar(
      "A", [](double x, double l) { return x - l; }, [](double, double) { return 1.0; },
      [](double, double) { return -1.0; }, "x reaches 1", [](double x) { return 1.0 - x; });
  Piece b = Scalar(
      "B", [](double x, double l) { return x - 1.0 + (l - 1.0) * (l - 1.0); },
      [](double, double) { return 1.0; }, [](double, double l) { return 2.0 * (l - 1.0); },
      "x falls to 1", [](double x) { return x - 1.0; });
  TwoPieceProblem problem(a, b, [](const Vector& u) { return u; });
  const Branch branch = Continue(problem, Vec({0.0}), 0.0, Bounds(-1.0, 3.0));
  INFO(branch.BriefReport());
  CHECK(branch.status == BranchStatus::kNoValidDirection);
  CHECK(branch.message.find("x falls to 1") != std::string::npos);
  CHECK(std::abs(branch.points.back().lambda - 1.0) <= 1e-10);
}

TEST_CASE("a start point outside its piece is reported, not continued", "[continuation][events]") {
  Piece a = Scalar(
      "A", [](double x, double l) { return x - l; }, [](double, double) { return 1.0; },
      [](double, double) { return -1.0; }, "x reaches 1", [](double x) { return 1.0 - x; });
  TwoPieceProblem problem(a, a, [](const Vector& u) { return u; });
  const Branch branch = Continue(problem, Vec({2.0}), 2.0, Bounds(-1.0, 3.0));
  CHECK(branch.status == BranchStatus::kStartFailed);
  CHECK(branch.message.find("x reaches 1") != std::string::npos);
}

}  // namespace
}  // namespace rubcont
