#include "pair_costs.hpp"

#include <lista/error.hpp>
#include <lista_geometry/object_geometry.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lista::match {
namespace {

// Scales the entries of `d` where `mask` holds, as configured: minmax over
// the masked entries; max divides by max(largest masked entry, floor).
void normalise(Eigen::MatrixXd& d, const BoolMatrix& mask, Normalization how, double floor = 0.0) {
  double lo = std::numeric_limits<double>::max(), hi = 0.0;
  for (int i = 0; i < d.rows(); ++i)
    for (int j = 0; j < d.cols(); ++j)
      if (mask(i, j)) lo = std::min(lo, d(i, j)), hi = std::max(hi, d(i, j));
  if (how == Normalization::max) lo = 0.0, hi = std::max(hi, floor);
  const double range = hi - lo;
  for (int i = 0; i < d.rows(); ++i)
    for (int j = 0; j < d.cols(); ++j)
      d(i, j) = range > 1e-12 ? std::clamp((d(i, j) - lo) / range, 0.0, 1.0) : 0.0;
}

// Height and footprint-rectangle sides (larger first): what
// a rigid object keeps when it moves, whatever its yaw.
Eigen::Vector3d size_of(const Object& o) {
  const Eigen::Vector2f e = geometry::horizontal_extents(o.points.xyz);
  return {double(o.bbox_max.z() - o.bbox_min.z()), double(e[0]), double(e[1])};
}

bool same_size(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double relative, double slack) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(a[k] - b[k]) > std::max(slack, relative * std::max(a[k], b[k]))) return false;
  return true;
}

}  // namespace

double descriptor_scale(const ObjectSet& objects, const DescriptorSet& desc) {
  std::vector<int> rows;
  for (const Object& o : objects.objects)
    if (desc.row_of(o.id) >= 0) rows.push_back(desc.row_of(o.id));
  double best = 0.0;
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = i + 1; j < rows.size(); ++j)
      best = std::max(best, static_cast<double>((desc.values.row(rows[i]) - desc.values.row(rows[j])).norm()));
  return best;
}

PairCosts pair_costs(const std::vector<const Object*>& a, const std::vector<const Object*>& b,
                     const DescriptorSet& desc, const Groups* groups, const WeightedMatchConfig& cfg,
                     double desc_scale, const PairFit& fit, const std::vector<bool>& a_changed,
                     const std::vector<bool>& b_changed) {
  const int n = static_cast<int>(a.size()), m = static_cast<int>(b.size());
  PairCosts pc;
  pc.physical.resize(n, m);
  pc.descriptor.resize(n, m);
  pc.allowed.setConstant(n, m, true);
  pc.cross = Eigen::MatrixXd::Zero(n, m);
  std::vector<Eigen::Vector3d> size_a, size_b;
  if (cfg.size_gate.enabled) {
    for (const Object* o : a) size_a.push_back(size_of(*o));
    for (const Object* o : b) size_b.push_back(size_of(*o));
  }
  for (int i = 0; i < n; ++i) {
    const int ra = desc.row_of(a[i]->id);
    for (int j = 0; j < m; ++j) {
      const int rb = desc.row_of(b[j]->id);
      pc.physical(i, j) = (a[i]->centroid - b[j]->centroid).cast<double>().norm();
      // An object without a descriptor is as unlike everything as possible.
      pc.descriptor(i, j) = (ra >= 0 && rb >= 0)
          ? (desc.values.row(ra) - desc.values.row(rb)).cast<double>().norm()
          : std::numeric_limits<double>::quiet_NaN();
      bool ok = (!cfg.distance_gate.enabled || pc.physical(i, j) <= cfg.distance_gate.max_distance) &&
                (a_changed[size_t(i)] || b_changed[size_t(j)]);
      const auto& size = cfg.size_gate;
      if (size.enabled && !same_size(size_a[size_t(i)], size_b[size_t(j)], size.max_change, size.slack)) ok = false;
      if (cfg.descriptor_gate.enabled && !(pc.descriptor(i, j) <= cfg.descriptor_gate.max_distance)) ok = false;
      if (groups && cfg.groups.mode != GroupMode::ignore) {
        const int ga = groups->group_of(a[i]->id), gb = groups->group_of(b[j]->id);
        const bool same = ga >= 0 && ga == gb;
        if (!same && cfg.groups.mode == GroupMode::hard) ok = false;
        if (!same) pc.cross(i, j) = cfg.groups.penalty;
      }
      pc.allowed(i, j) = ok;
    }
  }
  double dmax = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
      if (std::isfinite(pc.descriptor(i, j))) dmax = std::max(dmax, pc.descriptor(i, j));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
      if (!std::isfinite(pc.descriptor(i, j))) pc.descriptor(i, j) = dmax;
  // Shape check last: it registers every surviving pair, the costly part.
  pc.shape = Eigen::MatrixXd::Zero(n, m);
  if (cfg.shape_weight > 0.0 || cfg.shape_gate.enabled) {
    std::vector<std::pair<const Object*, const Object*>> todo;
    std::vector<std::pair<int, int>> where;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j)
        if (pc.allowed(i, j)) todo.emplace_back(a[size_t(i)], b[size_t(j)]), where.emplace_back(i, j);
    const std::vector<double> f = todo.empty() ? std::vector<double>{} : fit(todo);
    if (f.size() != todo.size()) throw Error("shape fit returned " + std::to_string(f.size()) + " values for " +
                                             std::to_string(todo.size()) + " pairs");
    for (size_t k = 0; k < todo.size(); ++k) {
      const auto [i, j] = where[k];
      pc.shape(i, j) = 1.0 - std::clamp(f[k], 0.0, 1.0);
      if (f[k] < cfg.shape_gate.bar()) pc.allowed(i, j) = false;
    }
  }
  Eigen::MatrixXd p = pc.physical, d = pc.descriptor;
  normalise(p, pc.allowed, cfg.normalization);
  normalise(d, pc.allowed, cfg.normalization, desc_scale);
  pc.weighted = cfg.alpha * p + cfg.beta * d + cfg.shape_weight * pc.shape + pc.cross;
  return pc;
}

}  // namespace lista::match
