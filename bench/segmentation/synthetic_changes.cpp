#include "synthetic_changes.hpp"

#include <cmath>
#include <random>

namespace lista::bench {

PointSet synthetic_changes(const SyntheticChangeConfig& c, std::vector<uint32_t>* truth) {
  std::mt19937_64 rng(c.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<float> range_noise(0.f, 0.005f);
  PointSet s;
  std::vector<uint32_t> who;
  auto add = [&](Eigen::Vector3f p, uint32_t id) {
    s.xyz.push_back(p + Eigen::Vector3f(range_noise(rng), range_noise(rng), range_noise(rng)));
    s.scan.push_back(uint32_t(s.size() / 50000));
    s.index.push_back(uint32_t(s.index.size()));
    who.push_back(id);
  };
  const float h = float(c.spacing);
  // Objects on a jittered grid, so they do not touch (at least 0.5 m apart).
  const int side = int(std::ceil(std::sqrt(double(c.objects))));
  const double cellw = c.extent / side;
  for (int k = 0; k < c.objects; ++k) {
    const float size = float(0.2 + 1.3 * u(rng));
    const float room = float(std::max(0.0, cellw - size - 0.5));
    const Eigen::Vector3f at(float((k % side) * cellw + room * u(rng)), float((k / side) * cellw + room * u(rng)), 0.f);
    const uint32_t id = uint32_t(k + 1);
    if (k % 3 == 2) {  // ball: Fibonacci lattice
      const float r = size / 2;
      const int n = int(4 * M_PI * r * r / (h * h));
      const float golden = float(M_PI * (3.0 - std::sqrt(5.0)));
      for (int i = 0; i < n; ++i) {
        const float z = 1.f - 2.f * (float(i) + 0.5f) / float(n), rho = std::sqrt(1.f - z * z);
        add(at + Eigen::Vector3f(r, r, r) + r * Eigen::Vector3f(rho * std::cos(golden * i), rho * std::sin(golden * i), z), id);
      }
    } else {  // box, bottom face unseen; about half the surface seen from the sensor side
      const int n = std::max(2, int(size / h));
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
          for (int l = 1; l <= n; ++l) {
            const bool seen = i == 0 || j == 0 || l == n;  // two sides and the top
            if (seen) add(at + h * Eigen::Vector3f(float(i), float(j), float(l)) * (size / (h * n)), id);
          }
    }
    // A floor patch next to it: where it stood in the other mission.
    const float patch = size * 0.8f;
    for (float x = 0; x < patch; x += h)
      for (float y = 0; y < patch; y += h) add(at + Eigen::Vector3f(size + 0.3f + x, y, 0.f), 0);
  }
  const size_t object_points = s.size();
  for (size_t i = 0; i < size_t(c.noise_fraction * double(object_points)); ++i)
    add(Eigen::Vector3f(float(u(rng) * c.extent), float(u(rng) * c.extent), float(u(rng) * 3.0)), 0);
  if (truth) *truth = std::move(who);
  return s;
}

}  // namespace lista::bench
