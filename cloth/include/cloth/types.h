#pragma once
// Basic numeric types of the cloth library. Positions, velocities and forces of n particles are
// flat 3 x n column-major arrays (one column per particle), so kernels are plain index loops.

#include <Eigen/Dense>
#include <cstdint>

namespace cloth {

using Scalar = double;
using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
using Mat3 = Eigen::Matrix<Scalar, 3, 3>;
using Points = Eigen::Matrix<Scalar, 3, Eigen::Dynamic>;
using Index = std::int32_t;

}  // namespace cloth
