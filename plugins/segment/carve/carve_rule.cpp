#include "carve_rule.hpp"

#include <lista/parallel.hpp>
#include <lista_geometry/object_geometry.hpp>
#include <lista_geometry/voxel_key.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace lista::segment {
namespace {

// Dense bitmap over a box: each marked point marks its own cell "near" (2)
// and the cells within `radius` of it "within tolerance" (1), so how near a
// point of the marked set lies is one lookup.
class Grid {
 public:
  Grid(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, float cell, float radius) : lo_(lo), cell_(cell) {
    dims_ = ((hi - lo) / cell).array().ceil().cast<int>() + 1;
    levels_.assign(size_t(dims_.x()) * size_t(dims_.y()) * size_t(dims_.z()), 0);
    const int r = int(std::ceil(radius / cell));
    for (int x = -r; x <= r; ++x)
      for (int y = -r; y <= r; ++y)
        for (int z = -r; z <= r; ++z)
          if (cell * std::sqrt(float(x * x + y * y + z * z)) <= radius + 1e-6f) ball_.emplace_back(x, y, z);
  }
  void mark(const Eigen::Vector3f& p) {
    const Eigen::Vector3i c = cell_of(p);
    for (const auto& d : ball_) {
      const Eigen::Vector3i q = c + d;
      if (inside(q)) levels_[offset(q)] = std::max<uint8_t>(levels_[offset(q)], d.isZero() ? 2 : 1);
    }
  }
  // 2: a marked point in p's cell; 1: one within the radius; 0: none.
  int level(const Eigen::Vector3f& p) const {
    const Eigen::Vector3i c = cell_of(p);
    return inside(c) ? levels_[offset(c)] : 0;
  }

 private:
  Eigen::Vector3i cell_of(const Eigen::Vector3f& p) const {
    return ((p - lo_) / cell_).array().floor().cast<int>();
  }
  bool inside(const Eigen::Vector3i& c) const { return (c.array() >= 0).all() && (c.array() < dims_.array()).all(); }
  size_t offset(const Eigen::Vector3i& c) const {
    return (size_t(c.z()) * size_t(dims_.y()) + size_t(c.y())) * size_t(dims_.x()) + size_t(c.x());
  }
  Eigen::Vector3f lo_;
  float cell_;
  Eigen::Vector3i dims_;
  std::vector<uint8_t> levels_;
  std::vector<Eigen::Vector3i> ball_;
};

// Hosts with a footprint over kMaxHostArea (m^2), or a grid over more cells
// than this, are not searched: that large is structure or a heap, not two
// pieces of furniture, and the search grows with the host's area.
constexpr size_t kMaxGridCells = size_t(16) << 20;

size_t cells_over(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, float cell) {
  const Eigen::Vector3f n = ((hi - lo) / cell).array().ceil() + 1.f;
  return size_t(double(n.x()) * double(n.y()) * double(n.z()));
}

// A template placed in a host: turned by `yaw` about its centre (xy), whose
// image is `centre`; heights unchanged.
struct Placement {
  double yaw = 0.0;
  Eigen::Vector2f centre = Eigen::Vector2f::Zero();
};

struct Template {
  std::vector<Eigen::Vector3f> samples;  // relative to `centre` in xy, z as is
  Eigen::Vector2f centre = Eigen::Vector2f::Zero();
};

// One point per voxel (the first in point order), then every k-th so that
// at most kMaxSamples remain: deterministic, and even over the surface.
// Heights moved by `dz` (the host's floor minus the template's, when both
// are known: missions may disagree on the floor's height).
Template make_template(const Object& t, float voxel, float dz) {
  std::unordered_map<uint64_t, size_t> seen;
  std::vector<Eigen::Vector3f> kept;
  for (const auto& p : t.points.xyz) {
    const Eigen::Vector3i c = (p / voxel).array().floor().cast<int>();
    if (seen.emplace(geometry::voxel_key(c), kept.size()).second) kept.push_back(p);
  }
  Template out;
  const size_t stride = (kept.size() + kMaxSamples - 1) / kMaxSamples;
  for (size_t i = 0; i < kept.size(); i += std::max<size_t>(1, stride)) out.samples.push_back(kept[i]);
  for (const auto& p : out.samples) out.centre += p.head<2>();
  out.centre /= float(std::max<size_t>(1, out.samples.size()));
  for (auto& p : out.samples) p.head<2>() -= out.centre, p.z() += dz;
  return out;
}

std::vector<Eigen::Vector3f> turned(const std::vector<Eigen::Vector3f>& pts, double yaw) {
  const float c = float(std::cos(yaw)), s = float(std::sin(yaw));
  std::vector<Eigen::Vector3f> out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.emplace_back(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z());
  return out;
}

// How well `q` (turned samples) lies on the grid with its centre put at
// `u`: `fitting` = points within the tolerance, `score` = the sum of their
// levels (a point in a host point's own cell counts twice, so that of the
// poses within the tolerance the tightest wins: a 0.6 x 0.5 crate turned by
// 90 degrees also fits within 8 cm). Stops early, with score 0, once it can
// no longer fit `must` points, beat `best` or reach `elsewhere` (the best
// another search found: a tie with it may still come first).
struct Score {
  size_t fitting = 0, score = 0;
};
Score score_at(const std::vector<Eigen::Vector3f>& q, const Eigen::Vector2f& u, const Grid& g, size_t must,
               size_t best, size_t elsewhere) {
  Score s;
  for (size_t i = 0; i < q.size(); ++i) {
    const int l = g.level({q[i].x() + u.x(), q[i].y() + u.y(), q[i].z()});
    s.fitting += l > 0;
    s.score += size_t(l);
    const size_t left = q.size() - i - 1;
    if (s.fitting + left < must || s.score + 2 * left <= best || s.score + 2 * left < elsewhere) return {};
  }
  return s;
}

struct Fit {
  size_t fitting = 0, score = 0;
  Placement pose;
};

// A template's search in one host (box [lo, hi], points in `g`); only
// placements where `must` points fit count.
struct FitSearch {
  const Template& t;
  const Grid& g;
  Eigen::Vector3f lo, hi;
  const CarveConfig& c;
  size_t must;

  // Centres from `from` to `to` in steps of `s` at `yaw`, in x then y
  // order, into `best` where they beat it (ties keep the first found).
  void search(double yaw, const Eigen::Vector2f& from, const Eigen::Vector2f& to, float s, Fit& best,
              const std::atomic<size_t>& elsewhere) const {
    const float tol = float(c.tolerance);
    const std::vector<Eigen::Vector3f> q = turned(t.samples, yaw);
    Eigen::Vector2f qlo(INFINITY, INFINITY), qhi(-INFINITY, -INFINITY);
    for (const auto& p : q) qlo = qlo.cwiseMin(p.head<2>()), qhi = qhi.cwiseMax(p.head<2>());
    // The turned template stays inside the host's box (grown by the tolerance).
    const Eigen::Vector2f ulo = from.cwiseMax(lo.head<2>() - qlo - Eigen::Vector2f::Constant(tol));
    const Eigen::Vector2f uhi = to.cwiseMin(hi.head<2>() - qhi + Eigen::Vector2f::Constant(tol));
    if (ulo.x() > uhi.x() || ulo.y() > uhi.y()) return;
    const int nx = int(std::floor((uhi.x() - ulo.x()) / s + 1e-4f)), ny = int(std::floor((uhi.y() - ulo.y()) / s + 1e-4f));
    for (int i = 0; i <= nx; ++i)
      for (int j = 0; j <= ny; ++j) {
        const float x = ulo.x() + float(i) * s, y = ulo.y() + float(j) * s;
        const Score sc = score_at(q, {x, y}, g, must, best.score, elsewhere.load(std::memory_order_relaxed));
        if (sc.score > best.score) best = {sc.fitting, sc.score, {yaw, {x, y}}};
      }
  }
};

double yaw_step_of(const CarveConfig& c) { return c.yaw_step * M_PI / 180.0; }
int yaw_count(const CarveConfig& c) { return int(std::lround(2.0 * M_PI / yaw_step_of(c))); }

// The coarse search at the k-th yaw, over every centre.
Fit coarse_fit(const FitSearch& f, int k, std::atomic<size_t>& best_elsewhere) {
  Fit best;
  const Eigen::Vector2f everywhere = Eigen::Vector2f::Constant(INFINITY);
  f.search(k * yaw_step_of(f.c), -everywhere, everywhere, float(f.c.voxel), best, best_elsewhere);
  size_t seen = best_elsewhere.load();
  while (best.score > seen && !best_elsewhere.compare_exchange_weak(seen, best.score)) {
  }
  return best;
}

// The best of the coarse fits (the first of equals, in yaw order), refined
// once at half the steps around it; none where nothing fitted.
Fit refined_fit(const FitSearch& f, const std::vector<Fit>& coarse) {
  Fit best;
  for (const Fit& fit : coarse)
    if (fit.score > best.score) best = fit;
  if (best.score == 0) return {};
  const Placement pose = best.pose;
  const float step = float(f.c.voxel);
  const double yaw_step = yaw_step_of(f.c);
  const std::atomic<size_t> none{0};
  for (double dy : {-0.5, 0.0, 0.5})
    f.search(pose.yaw + dy * yaw_step, pose.centre - Eigen::Vector2f::Constant(step),
             pose.centre + Eigen::Vector2f::Constant(step), 0.5f * step, best, none);
  return best;
}

// Share of the template's top band (its highest samples, the top fifth of
// its height and at least two voxels) that fits at `pose`: a lower object
// fits the lower part of a taller one everywhere but on its top.
double top_fit(const Template& t, const Grid& g, const Placement& pose, float voxel) {
  float top = -INFINITY, bottom = INFINITY;
  for (const auto& p : t.samples) top = std::max(top, p.z()), bottom = std::min(bottom, p.z());
  const float band = std::max(2.f * voxel, 0.2f * (top - bottom));
  size_t n = 0, fit = 0;
  for (const auto& p : turned(t.samples, pose.yaw)) {
    if (p.z() < top - band) continue;
    ++n;
    fit += g.level({p.x() + pose.centre.x(), p.y() + pose.centre.y(), p.z()}) > 0;
  }
  return n ? double(fit) / double(n) : 0.0;
}

float height_of(const Object& o) { return o.bbox_max.z() - o.bbox_min.z(); }


// The 98th percentile of the heights of `idx`: a top robust to a stray point.
float top_of(const PointSet& s, const std::vector<uint32_t>& idx) {
  std::vector<float> z;
  z.reserve(idx.size());
  for (uint32_t i : idx) z.push_back(s.xyz[i].z());
  return geometry::kth_smallest(z, std::min(z.size() - 1, size_t(0.98 * double(z.size()))));
}

// Connected parts of the points `idx` (voxels of edge `cell`, 26-neighbourhood),
// each in point order, the parts in order of their first point.
std::vector<std::vector<uint32_t>> connected_parts(const PointSet& s, const std::vector<uint32_t>& idx, float cell) {
  const auto key = geometry::voxel_key;
  auto cell_of = [&](uint32_t i) -> Eigen::Vector3i { return (s.xyz[i] / cell).array().floor().cast<int>(); };
  std::unordered_map<uint64_t, std::vector<uint32_t>> voxels;  // voxel -> positions in idx
  for (uint32_t k = 0; k < idx.size(); ++k) voxels[key(cell_of(idx[k]))].push_back(k);
  std::vector<int> part(idx.size(), -1);
  std::vector<std::vector<uint32_t>> parts;
  for (uint32_t k = 0; k < idx.size(); ++k) {
    if (part[k] >= 0) continue;
    const int id = int(parts.size());
    parts.emplace_back();
    std::vector<Eigen::Vector3i> stack{cell_of(idx[k])};
    for (uint32_t j : voxels[key(stack.back())]) part[j] = id;
    while (!stack.empty()) {
      const Eigen::Vector3i v = stack.back();
      stack.pop_back();
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const Eigen::Vector3i n = v + Eigen::Vector3i(dx, dy, dz);
            auto it = voxels.find(key(n));
            if (it == voxels.end() || part[it->second.front()] >= 0) continue;
            for (uint32_t j : it->second) part[j] = id;
            stack.push_back(n);
          }
    }
  }
  for (uint32_t k = 0; k < idx.size(); ++k) parts[size_t(part[k])].push_back(idx[k]);
  return parts;
}

// Of the floor cells (edge `cell`) under the smaller of two point sets, the
// share also under the other: objects beside each other share only their
// contact; a cut through one object leaves parts above each other.
double footprint_overlap(const PointSet& s, const std::vector<uint32_t>& a, const std::vector<uint32_t>& b, float cell) {
  auto cells = [&](const std::vector<uint32_t>& idx) {
    std::unordered_set<uint64_t> out;
    for (uint32_t i : idx) {
      const Eigen::Vector2i c = (s.xyz[i].head<2>() / cell).array().floor().cast<int>();
      out.insert(geometry::voxel_key({c.x(), c.y(), 0}));
    }
    return out;
  };
  const auto ca = cells(a), cb = cells(b);
  const auto& small = ca.size() <= cb.size() ? ca : cb;
  const auto& large = ca.size() <= cb.size() ? cb : ca;
  size_t shared = 0;
  for (uint64_t k : small) shared += large.count(k);
  return small.empty() ? 1.0 : double(shared) / double(small.size());
}

Object part_of(const Object& host, const std::vector<uint32_t>& idx) {
  Object o;
  o.mission = host.mission;
  o.floor_z = host.floor_z;
  o.points = host.points.select(idx);
  o.update_geometry();
  return o;
}

struct Candidate {
  size_t host, tmpl;
  Fit fit;
  size_t samples = 0;
  Eigen::Vector2f centre = Eigen::Vector2f::Zero();  // the template's, which the fit turned it about
  float dz = 0.f;                                     // height shift onto the host's floor
};

// Orders objects by what they hold, not by where they stand in the set.
std::tuple<uint32_t, uint32_t, uint32_t, size_t> key_of(const Object& o) {
  return {o.mission, o.points.scan.empty() ? 0u : o.points.scan[0], o.points.index.empty() ? 0u : o.points.index[0],
          o.points.size()};
}

// The host cut by the template placed at `pose`: {E, rest parts}, or nothing
// when a part is too small or the parts' tops do not differ (rule 4).
std::vector<Object> cut(const Object& host, const Object& tmpl, const Eigen::Vector2f& centre, float dz,
                        const Placement& pose, const CarveConfig& c) {
  const float tol = float(c.tolerance);
  const Eigen::Vector3f grow = Eigen::Vector3f::Constant(tol);
  Grid placed(host.bbox_min - grow, host.bbox_max + grow, float(c.voxel), tol);
  std::vector<Eigen::Vector3f> whole;  // every template point, about the centre the search turned it about
  for (const auto& p : tmpl.points.xyz) whole.emplace_back(p.x() - centre.x(), p.y() - centre.y(), p.z() + dz);
  for (const auto& p : turned(whole, pose.yaw))
    placed.mark({p.x() + pose.centre.x(), p.y() + pose.centre.y(), p.z()});
  std::vector<uint32_t> carved, rest;
  for (uint32_t i = 0; i < host.points.size(); ++i) (placed.level(host.points.xyz[i]) > 0 ? carved : rest).push_back(i);
  std::vector<std::vector<uint32_t>> parts;
  std::vector<uint32_t> kept_rest;
  for (auto& p : connected_parts(host.points, rest, 2.f * float(c.voxel))) {
    if (p.size() < c.min_points) {
      carved.insert(carved.end(), p.begin(), p.end());
    } else {
      kept_rest.insert(kept_rest.end(), p.begin(), p.end());
      parts.push_back(std::move(p));
    }
  }
  const double n = double(host.points.size());
  if (carved.empty() || kept_rest.empty()) return {};
  if (double(carved.size()) < c.min_share * n || double(kept_rest.size()) < c.min_share * n) return {};
  if (std::abs(top_of(host.points, carved) - top_of(host.points, kept_rest)) < float(c.min_height_step)) return {};
  if (footprint_overlap(host.points, carved, kept_rest, 2.f * float(c.voxel)) > c.max_overlap) return {};
  std::sort(carved.begin(), carved.end());
  std::vector<Object> out{part_of(host, carved)};
  for (const auto& p : parts) out.push_back(part_of(host, p));
  return out;
}

}  // namespace

ObjectSet carve_objects(const ObjectSet& in, const CarveConfig& c, CarveStats* stats) {
  CarveStats st;
  ObjectSet out = in;
  const size_t n = in.objects.size();
  const float voxel = float(c.voxel), tol = float(c.tolerance), step = float(c.min_height_step);

  // 1. Candidate pairs.
  std::vector<float> area(n), width(n), height(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2f e = geometry::horizontal_extents(in.objects[i].points.xyz);
    area[i] = e.x() * e.y();
    width[i] = e.y();
    height[i] = height_of(in.objects[i]);
  }
  std::vector<Candidate> cands;
  for (size_t h = 0; h < n; ++h) {
    const Object& H = in.objects[h];
    if (H.points.size() < 2 * c.min_points) continue;
    const Eigen::Vector3f grow = Eigen::Vector3f::Constant(tol);
    if (area[h] > kMaxHostArea || cells_over(H.bbox_min - grow, H.bbox_max + grow, voxel) > kMaxGridCells) continue;
    for (size_t t = 0; t < n; ++t) {
      const Object& T = in.objects[t];
      if (T.mission + 1 != H.mission && H.mission + 1 != T.mission) continue;
      if (T.points.size() < c.min_points || width[t] < float(c.min_width) || height[t] > height[h] + tol) continue;
      const bool bigger = area[h] >= kBiggerArea * area[t] || height[h] >= height[t] + step;
      const bool floors = std::isfinite(H.floor_z) && std::isfinite(T.floor_z);
      if (bigger) cands.push_back({h, t, {}, 0, Eigen::Vector2f::Zero(), floors ? H.floor_z - T.floor_z : 0.f});
    }
  }
  st.candidates = cands.size();

  // 2. Fits, in parallel over hosts (one grid per host, shared by its
  // candidates; each candidate writes only its own slot).
  std::vector<std::vector<size_t>> of_host(n);
  for (size_t k = 0; k < cands.size(); ++k) of_host[cands[k].host].push_back(k);
  std::vector<size_t> hosts;
  for (size_t h = 0; h < n; ++h)
    if (!of_host[h].empty()) hosts.push_back(h);
  // Hosts one at a time; their candidates' coarse searches in parallel
  // over yaws (one host with many candidates, the usual case outdoors,
  // would hold a single thread), each yaw into its own slot.
  const int yaws = yaw_count(c);
  for (size_t h : hosts) {
    if (c.cancelled && c.cancelled()) break;
    const Object& H = in.objects[h];
    const Eigen::Vector3f grow = Eigen::Vector3f::Constant(tol);
    Grid g(H.bbox_min - grow, H.bbox_max + grow, voxel, tol);
    for (const auto& p : H.points.xyz) g.mark(p);
    const std::vector<size_t>& mine = of_host[h];
    std::vector<Template> templates;
    std::vector<FitSearch> searches;
    templates.reserve(mine.size());
    for (size_t i : mine) {
      Candidate& cd = cands[i];
      templates.push_back(make_template(in.objects[cd.tmpl], voxel, cd.dz));
      cd.samples = templates.back().samples.size();
      cd.centre = templates.back().centre;
    }
    for (size_t k = 0; k < mine.size(); ++k)
      searches.push_back({templates[k], g, H.bbox_min, H.bbox_max, c,
                          size_t(std::ceil(c.min_fit * double(templates[k].samples.size())))});
    std::vector<std::atomic<size_t>> best_of(mine.size());
    std::vector<Fit> coarse(mine.size() * size_t(yaws));
    parallel_for(coarse.size(), std::max(1, c.threads), [&](size_t k) {
      const size_t i = k / size_t(yaws);
      if (templates[i].samples.empty() || (c.cancelled && c.cancelled())) return;
      coarse[k] = coarse_fit(searches[i], int(k % size_t(yaws)), best_of[i]);
    });
    parallel_for(mine.size(), std::max(1, c.threads), [&](size_t i) {
      if (templates[i].samples.empty()) return;
      Candidate& cd = cands[mine[i]];
      const auto first = coarse.begin() + long(i * size_t(yaws));
      cd.fit = refined_fit(searches[i], std::vector<Fit>(first, first + yaws));
      if (cd.fit.score > 0 && top_fit(templates[i], g, cd.fit.pose, voxel) < c.min_fit) cd.fit = {};
    });
  }
  if (c.cancelled && c.cancelled()) return out;

  // 3-4. Best fits first; each object in at most one carve.
  std::vector<Candidate> fitted;
  for (const auto& cd : cands)
    if (cd.fit.score > 0) fitted.push_back(cd);
  st.fitted = fitted.size();
  // Best share fitting first, then the tighter fit; ties by what the objects
  // hold, so the order of the set decides nothing.
  std::sort(fitted.begin(), fitted.end(), [&](const Candidate& a, const Candidate& b) {
    const double fa = double(a.fit.fitting) * double(b.samples), fb = double(b.fit.fitting) * double(a.samples);
    if (fa != fb) return fa > fb;
    const double sa = double(a.fit.score) * double(b.samples), sb = double(b.fit.score) * double(a.samples);
    if (sa != sb) return sa > sb;
    return std::tuple(key_of(in.objects[a.host]), key_of(in.objects[a.tmpl])) <
           std::tuple(key_of(in.objects[b.host]), key_of(in.objects[b.tmpl]));
  });
  std::vector<char> used(n, 0);
  std::vector<std::vector<Object>> replaced(n);
  for (const auto& cd : fitted) {
    if (used[cd.host] || used[cd.tmpl]) continue;
    std::vector<Object> parts = cut(in.objects[cd.host], in.objects[cd.tmpl], cd.centre, cd.dz, cd.fit.pose, c);
    if (parts.empty()) continue;
    used[cd.host] = used[cd.tmpl] = 1;
    ++st.carved;
    st.parts += parts.size() - 1;
    size_t rest = 0;
    for (size_t k = 1; k < parts.size(); ++k) rest += parts[k].points.size();
    st.carves.push_back({in.objects[cd.host].id, in.objects[cd.tmpl].id,
                         double(cd.fit.fitting) / double(cd.samples), parts[0].points.size(), rest});
    replaced[cd.host] = std::move(parts);
  }
  if (st.carved) {
    std::vector<Object> objects;
    for (size_t i = 0; i < n; ++i) {
      if (replaced[i].empty())
        objects.push_back(in.objects[i]);
      else
        for (auto& o : replaced[i]) objects.push_back(std::move(o));
    }
    out.objects = std::move(objects);
    out.renumber();
  }
  if (stats) *stats = st;
  return out;
}

}  // namespace lista::segment
