#include <lista_objreg/upright.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lista::objreg {

bool stays_on_floor(const Object& a, const Object& b, const Eigen::Isometry3d& t, double max_lift,
                    double max_tilt_deg) {
  if (!std::isfinite(a.floor_z) || !std::isfinite(b.floor_z)) return true;
  if (max_lift > 0.0) {
    const Eigen::Vector3d c = a.centroid.cast<double>();
    if (std::abs((t * c).z() - c.z() - (double(b.floor_z) - double(a.floor_z))) > max_lift) return false;
  }
  const double tilt = std::acos(std::clamp(t.linear()(2, 2), -1.0, 1.0)) * 180.0 / M_PI;
  return tilt <= max_tilt_deg;
}

double floor_lift(const Object& a, const Object& b) {
  if (!std::isfinite(a.floor_z) || !std::isfinite(b.floor_z)) return std::numeric_limits<double>::quiet_NaN();
  return double(b.floor_z) - double(a.floor_z);
}

}  // namespace lista::objreg
