#include "solvers/ode_system.h"

#include <algorithm>
#include <cmath>

#include "solvers/finite_difference.h"

namespace rubcont {

void OdeSystem::JacobianX(double t, ConstVectorRef x, MatrixRef J) {
  const Index n = Dimension();
  const Vector scale = StateScale();
  Vector xp = x;
  Vector f_plus(n), f_minus(n);
  for (Index j = 0; j < n; ++j) {
    const double h = CentralDifferenceStep(x(j), scale(j));
    xp(j) = x(j) + h;
    Rhs(t, xp, f_plus);
    xp(j) = x(j) - h;
    Rhs(t, xp, f_minus);
    xp(j) = x(j);
    J.col(j) = (f_plus - f_minus) / (2.0 * h);
  }
}

void OdeSystem::DfDparameter(double t, ConstVectorRef x, VectorRef df) {
  const double p = Parameter();
  const double h = CentralDifferenceStep(p, 1.0);
  const Index n = Dimension();
  Vector f_plus(n), f_minus(n);
  SetParameter(p + h);
  Rhs(t, x, f_plus);
  SetParameter(p - h);
  Rhs(t, x, f_minus);
  SetParameter(p);
  df = (f_plus - f_minus) / (2.0 * h);
}

}  // namespace rubcont
