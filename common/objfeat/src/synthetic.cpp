#include <lista_objfeat/synthetic.hpp>

#include <Eigen/Geometry>
#include <cmath>

namespace lista::objfeat {
namespace {

float uni(std::mt19937_64& rng, float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); }

struct Sample {
  Eigen::Vector3f p, n;
};

// Area-weighted surface samples of one primitive with outward normals.
void sample_surface(const Primitive& pr, float density, std::mt19937_64& rng, std::vector<Sample>& out) {
  const Eigen::Vector3f& h = pr.half;
  if (pr.kind == Primitive::box) {
    for (int axis = 0; axis < 3; ++axis)
      for (int sign = -1; sign <= 1; sign += 2) {
        int u = (axis + 1) % 3, v = (axis + 2) % 3;
        float area = 4.f * h[u] * h[v];
        int n = int(area * density) + 1;
        for (int i = 0; i < n; ++i) {
          Eigen::Vector3f p, nrm = Eigen::Vector3f::Zero();
          p[axis] = sign * h[axis];
          p[u] = uni(rng, -h[u], h[u]);
          p[v] = uni(rng, -h[v], h[v]);
          nrm[axis] = float(sign);
          out.push_back({pr.centre + p, nrm});
        }
      }
  } else if (pr.kind == Primitive::cylinder) {
    float r = h.x(), hz = h.z();
    int n = int(2.f * float(M_PI) * r * 2.f * hz * density) + 1;
    for (int i = 0; i < n; ++i) {
      float a = uni(rng, 0.f, 2.f * float(M_PI));
      Eigen::Vector3f nrm(std::cos(a), std::sin(a), 0.f);
      out.push_back({pr.centre + Eigen::Vector3f(r * nrm.x(), r * nrm.y(), uni(rng, -hz, hz)), nrm});
    }
    int m = int(float(M_PI) * r * r * density) + 1;
    for (int sign = -1; sign <= 1; sign += 2)
      for (int i = 0; i < m; ++i) {
        float a = uni(rng, 0.f, 2.f * float(M_PI)), rr = r * std::sqrt(uni(rng, 0.f, 1.f));
        out.push_back({pr.centre + Eigen::Vector3f(rr * std::cos(a), rr * std::sin(a), sign * hz),
                       Eigen::Vector3f(0.f, 0.f, float(sign))});
      }
  } else {
    float r = h.x();
    int n = int(4.f * float(M_PI) * r * r * density) + 1;
    std::normal_distribution<float> g(0.f, 1.f);
    for (int i = 0; i < n; ++i) {
      Eigen::Vector3f d(g(rng), g(rng), g(rng));
      d.normalize();
      out.push_back({pr.centre + r * d, d});
    }
  }
}

Primitive box(Eigen::Vector3f c, Eigen::Vector3f h) { return {Primitive::box, c, h}; }

}  // namespace

Shape random_shape(std::mt19937_64& rng) {
  Shape s;
  int family = std::uniform_int_distribution<int>(0, 5)(rng);
  float w = uni(rng, 0.3f, 1.2f), d = uni(rng, 0.3f, 1.0f), ht = uni(rng, 0.4f, 1.8f);
  switch (family) {
    case 0:  // table: top + four legs
    case 1: {
      float leg = uni(rng, 0.02f, 0.06f), top = uni(rng, 0.02f, 0.06f);
      s.parts.push_back(box({0, 0, ht - top}, {w, d, top}));
      for (int sx = -1; sx <= 1; sx += 2)
        for (int sy = -1; sy <= 1; sy += 2)
          s.parts.push_back(box({sx * (w - leg), sy * (d - leg), (ht - top) / 2}, {leg, leg, (ht - top) / 2}));
      if (family == 1)  // chair back
        s.parts.push_back(box({-(w - leg), 0, ht + 0.3f * ht}, {leg, d, 0.3f * ht}));
      break;
    }
    case 2:  // cabinet with a plinth or a top shelf
      s.parts.push_back(box({0, 0, ht / 2}, {w / 2, d / 2, ht / 2}));
      s.parts.push_back(box({w / 4, 0, ht + 0.1f}, {w / 4, d / 3, 0.1f}));
      break;
    case 3:  // barrel / bin, maybe with a lid sphere
      s.parts.push_back({Primitive::cylinder, {0, 0, ht / 2}, {w / 2, w / 2, ht / 2}});
      if (uni(rng, 0, 1) < 0.5f) s.parts.push_back({Primitive::sphere, {0, 0, ht}, Eigen::Vector3f::Constant(w / 3)});
      break;
    case 4: {  // L-shaped stack of boxes
      s.parts.push_back(box({0, 0, ht / 4}, {w / 2, d / 2, ht / 4}));
      s.parts.push_back(box({w / 4, d / 4, ht * 0.75f}, {w / 4, d / 4, ht / 4}));
      break;
    }
    default: {  // post with a sign or lamp
      float r = uni(rng, 0.03f, 0.1f);
      s.parts.push_back({Primitive::cylinder, {0, 0, ht / 2}, {r, r, ht / 2}});
      s.parts.push_back(box({w / 4, 0, ht}, {w / 4, 0.03f, d / 3}));
      break;
    }
  }
  return s;
}

std::vector<Eigen::Vector3f> render_view(const Shape& shape, float yaw, const Eigen::Vector2f& offset,
                                         std::mt19937_64& rng, const ViewConfig& cfg) {
  std::vector<Sample> surface;
  float density = cfg.points_per_m2 * uni(rng, 0.4f, 1.6f);
  for (const auto& p : shape.parts) sample_surface(p, density, rng, surface);

  float az = uni(rng, 0.f, 2.f * float(M_PI)), range = uni(rng, cfg.min_range, cfg.max_range);
  Eigen::Vector3f sensor(range * std::cos(az), range * std::sin(az), uni(rng, 0.3f, 2.0f));
  // Occlusion: drop points on one side of a random vertical plane through the object.
  bool cut = uni(rng, 0.f, 1.f) < cfg.occlusion;
  float cut_a = uni(rng, 0.f, 2.f * float(M_PI)), cut_off = uni(rng, -0.1f, 0.3f);
  Eigen::Vector2f cut_dir(std::cos(cut_a), std::sin(cut_a));

  Eigen::Matrix3f rot = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  std::normal_distribution<float> noise(0.f, cfg.noise);
  std::vector<Eigen::Vector3f> out, all;
  for (const auto& s : surface) {
    Eigen::Vector3f w = rot * s.p;
    w.x() += offset.x();
    w.y() += offset.y();
    all.push_back(w);
    Eigen::Vector3f sensor_w(sensor.x() + offset.x(), sensor.y() + offset.y(), sensor.z());
    if ((rot * s.n).dot(sensor_w - w) <= 0.f) continue;
    if (cut && cut_dir.dot((rot * s.p).head<2>()) > cut_off) continue;
    Eigen::Vector3f ray = (w - sensor_w).normalized();
    out.push_back(w + ray * noise(rng));
  }
  if (out.size() < 20) return all;
  return out;
}

}  // namespace lista::objfeat
