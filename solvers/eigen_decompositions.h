// Eigen's dense decompositions of a MatrixXd (rubcont's Matrix), compiled once, in
// solvers/eigen_decompositions.cpp, instead of in every file (and unity batch) that uses them.
// Included by solvers/types.h, so every file that names a Matrix sees these declarations.
// Decision: alone at -O3 each cost 6–17 s of compile CPU (PartialPivLU 6 s, JacobiSVD 12.5 s,
// EigenSolver 17 s; all seven together 37 s), and eight of the library's nine batches and some test
// files compiled some of them again. The code is Eigen's, compiled with the same flags (no
// fast-math, so inlining elsewhere changes no rounding): the same results (the duffing, default
// and van_der_pol scenes' files identical to the bit, 2026-11-30).
//
// Covered: PartialPivLU, HouseholderQR, JacobiSVD and GeneralizedSelfAdjointEigenSolver of a
// MatrixXd (their non-template members: the factorizations), and compute() of EigenSolver,
// ComplexEigenSolver and SelfAdjointEigenSolver from a MatrixXd, which their constructors from a
// MatrixXd call. Solves (templates on the right-hand side) and decompositions of an expression (a
// transpose, a sum) still compile where they are used.
#pragma once

#include <Eigen/Dense>

extern template class Eigen::PartialPivLU<Eigen::MatrixXd>;
extern template class Eigen::HouseholderQR<Eigen::MatrixXd>;
extern template class Eigen::JacobiSVD<Eigen::MatrixXd>;
extern template class Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd>;
extern template Eigen::EigenSolver<Eigen::MatrixXd>&
Eigen::EigenSolver<Eigen::MatrixXd>::compute(const Eigen::EigenBase<Eigen::MatrixXd>&, bool);
extern template Eigen::ComplexEigenSolver<Eigen::MatrixXd>&
Eigen::ComplexEigenSolver<Eigen::MatrixXd>::compute(const Eigen::EigenBase<Eigen::MatrixXd>&, bool);
extern template Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>&
Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>::compute(const Eigen::EigenBase<Eigen::MatrixXd>&, int);
