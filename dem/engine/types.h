// Small dense types of the DEM engine (Eigen fixed-size: inlined, no heap).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace trackbed::dem {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

}  // namespace trackbed::dem
