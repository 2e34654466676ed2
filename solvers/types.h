// Common linear-algebra types. Dense Eigen throughout: the largest systems rubcont solves
// (multiple shooting on 16 states × tens of segments) are a few hundred unknowns.
#pragma once

#include <Eigen/Dense>

#include "solvers/eigen_decompositions.h"  // compiled once, not in each file

namespace rubcont {

using Index = Eigen::Index;
using Vector = Eigen::VectorXd;
using Matrix = Eigen::MatrixXd;
using ComplexVector = Eigen::VectorXcd;
using ComplexMatrix = Eigen::MatrixXcd;

}  // namespace rubcont
