// Basic linear-algebra aliases shared by every library: dense vectors and matrices and the compressed
// sparse column matrix type used for Jacobians and mass matrices (int indices, as UMFPACK's
// umfpack_di_* routines expect).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace keller {

using Vector = Eigen::VectorXd;
using Matrix = Eigen::MatrixXd;
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

}  // namespace keller
