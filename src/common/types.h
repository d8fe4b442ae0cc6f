#pragma once
/// Eigen aliases used across viscera. Positions are metres, in the world frame, z up.
#include <Eigen/Dense>

namespace viscera {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
/// One 3D point per row (#points by 3). Row-major so that the flat data is interleaved
/// x0 y0 z0 x1 ..., the order of the implicit integrator's unknowns.
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

}  // namespace viscera
