#include "layout.hpp"

#include "rng.hpp"

#include <lista/error.hpp>

#include <cmath>

namespace lista::sim {
namespace {

using V2 = Eigen::Vector2d;
using V3f = Eigen::Vector3f;

void add_part(Layout& l, const TriMesh& m, float reflectivity) { l.structure.push_back({m, reflectivity}); }

// A wall from p to q (floor to height), thickness t, recorded as an obstacle.
void add_wall(Layout& l, const V2& p, const V2& q, double t, double height, float refl, double z0 = 0.0) {
  Footprint f = segment_footprint(p, q, 0.5 * t);
  f.half.x() -= 0.5 * t;  // walls end at their end points
  TriMesh m;
  m.add_oriented_box(V3f(float(f.centre.x()), float(f.centre.y()), float(z0 + 0.5 * height)),
                     V3f(float(f.half.x()), float(f.half.y()), float(0.5 * height)), float(f.yaw));
  add_part(l, m, refl);
  l.obstacles.push_back(f);
}

bool near_route(const Layout& l, const Footprint& f, double margin) { return overlaps_any(f, l.corridor(), margin); }

void add_shell(Layout& l, double w, double len, double h, bool ceiling) {
  TriMesh floor;
  floor.add_box(V3f(-0.3f, -0.3f, -0.1f), V3f(float(w) + 0.3f, float(len) + 0.3f, 0.0f));
  add_part(l, floor, 0.3f);
  if (ceiling) {
    TriMesh c;
    c.add_box(V3f(-0.3f, -0.3f, float(h)), V3f(float(w) + 0.3f, float(len) + 0.3f, float(h) + 0.1f));
    add_part(l, c, 0.75f);
  }
  const double t = 0.2;
  add_wall(l, V2(-t / 2, -t / 2), V2(w + t / 2, -t / 2), t, h, 0.6f);
  add_wall(l, V2(w + t / 2, -t / 2), V2(w + t / 2, len + t / 2), t, h, 0.6f);
  add_wall(l, V2(w + t / 2, len + t / 2), V2(-t / 2, len + t / 2), t, h, 0.6f);
  add_wall(l, V2(-t / 2, len + t / 2), V2(-t / 2, -t / 2), t, h, 0.6f);
}

// Rectangular loop inset from the walls.
void add_loop_route(Layout& l, double w, double len, double inset_x, double inset_y) {
  if (w < 2 * inset_x + 1.0 || len < 2 * inset_y + 1.0)
    throw Error("lista-sim: the scene is too small for an inspection route");
  l.route = {V2(inset_x, inset_y), V2(w - inset_x, inset_y), V2(w - inset_x, len - inset_y), V2(inset_x, len - inset_y)};
}

// Pillars on a grid, skipping those in the robot's way.
void add_pillars(Layout& l, double w, double len, double h, double spacing, double size, Rng& rng) {
  for (double x = spacing; x < w - 1.0; x += spacing)
    for (double y = spacing; y < len - 1.0; y += spacing) {
      Footprint f{V2(x, y), V2(size / 2, size / 2), 0.0};
      if (near_route(l, f, 0.3)) continue;
      TriMesh m;
      m.add_box(V3f(float(x - size / 2), float(y - size / 2), 0), V3f(float(x + size / 2), float(y + size / 2), float(h)));
      add_part(l, m, 0.5f);
      l.obstacles.push_back(f);
    }
}

void build_office(Layout& l, const LayoutParams& p, Rng& rng) {
  add_shell(l, p.width, p.length, p.height, true);
  const double inset = std::min(2.2, std::min(p.width, p.length) / 4.0);
  add_loop_route(l, p.width, p.length, inset, inset);
  l.sensor_height = 0.7;
  l.route_clearance = 0.6;
  if (p.width * p.length > 120) add_pillars(l, p.width, p.length, p.height, 6.0, 0.4, rng);
  // Low desk screens and a few full-height partitions with gaps, kept off the route.
  const int partitions = int(p.width * p.length / 60.0);
  for (int k = 0, tries = 0; k < partitions && tries < 200; ++tries) {
    const bool along_x = rng.chance(0.5);
    const double len = rng.uniform(1.2, 3.0);
    const V2 a(rng.uniform(0.5, p.width - 0.5), rng.uniform(0.5, p.length - 0.5));
    const V2 b = a + (along_x ? V2(len, 0) : V2(0, len));
    if (b.x() > p.width - 0.3 || b.y() > p.length - 0.3) continue;
    const Footprint f = segment_footprint(a, b, 0.05);
    if (near_route(l, f, 0.2) || overlaps_any(f, l.obstacles, 0.8)) continue;
    const bool tall = rng.chance(0.35);
    add_wall(l, a, b, 0.06, tall ? p.height : rng.uniform(1.1, 1.5), 0.45f);
    ++k;
  }
}

void build_hall(Layout& l, const LayoutParams& p, Rng& rng) {
  add_shell(l, p.width, p.length, p.height, true);
  const double inset = std::min(3.0, std::min(p.width, p.length) / 4.0);
  add_loop_route(l, p.width, p.length, inset, inset);
  l.sensor_height = 0.7;
  add_pillars(l, p.width, p.length, p.height, 8.0, 0.5, rng);
  // Pallet racking along the long walls: uprights and beams with shelves.
  const double depth = 1.0, rack_h = std::min(p.height - 1.0, 4.5);
  for (int side = 0; side < 2; ++side) {
    const double y0 = side == 0 ? 0.15 : p.length - 0.15 - depth;
    for (double x = 2.0; x + 2.7 < p.width - 2.0; x += 2.8) {
      const Footprint f{V2(x + 1.35, y0 + depth / 2), V2(1.35, depth / 2), 0.0};
      if (near_route(l, f, 0.2)) continue;
      TriMesh m;
      for (double ux : {x, x + 2.7})
        for (double uy : {y0, y0 + depth - 0.08})
          m.add_box(V3f(float(ux), float(uy), 0), V3f(float(ux) + 0.08f, float(uy) + 0.08f, float(rack_h)));
      for (double z = 0.15; z < rack_h; z += 1.4)
        m.add_box(V3f(float(x), float(y0), float(z)), V3f(float(x) + 2.78f, float(y0 + depth), float(z) + 0.05f));
      add_part(l, m, 0.55f);
      l.obstacles.push_back(f);
    }
  }
}

void build_yard(Layout& l, const LayoutParams& p, Rng& rng) {
  TriMesh ground;
  ground.add_box(V3f(-40, -40, -0.2f), V3f(float(p.width) + 40, float(p.length) + 40, 0.0f));
  add_part(l, ground, 0.25f);
  add_loop_route(l, p.width, p.length, 8.0, 8.0);
  l.sensor_height = 0.75;
  // Buildings around the yard and inside the loop: large boxes.
  const double mid_x = p.width / 2, mid_y = p.length / 2;
  auto building = [&](double x0, double y0, double x1, double y1, double h) {
    TriMesh m;
    m.add_box(V3f(float(x0), float(y0), 0), V3f(float(x1), float(y1), float(h)));
    add_part(l, m, 0.55f);
    l.obstacles.push_back(Footprint{V2((x0 + x1) / 2, (y0 + y1) / 2), V2((x1 - x0) / 2, (y1 - y0) / 2), 0.0});
  };
  building(mid_x - p.width * 0.25, mid_y - p.length * 0.15, mid_x + p.width * 0.1, mid_y + p.length * 0.15,
           rng.uniform(6, 10));
  building(-12, p.length * 0.3, -2, p.length * 0.7, rng.uniform(5, 9));
  building(p.width * 0.4, p.length + 3, p.width * 0.7, p.length + 12, rng.uniform(8, 12));
  // Perimeter fence posts: thin, sparse structure at the far field.
  for (double x = -2; x <= p.width + 2; x += 3.0)
    for (double y : {-3.0, p.length + 1.5}) {
      TriMesh m;
      m.add_box(V3f(float(x), float(y), 0), V3f(float(x) + 0.06f, float(y) + 0.06f, 2.0f));
      add_part(l, m, 0.6f);
    }
  // Objects stay inside the yard rectangle.
  l.area_min = V2(1.0, 1.0);
  l.area_max = V2(p.width - 1.0, p.length - 1.0);
  l.route_clearance = 1.5;
}

}  // namespace

double Layout::route_length() const {
  double s = 0;
  for (size_t i = 0; i < route.size(); ++i) s += (route[(i + 1) % route.size()] - route[i]).norm();
  return s;
}

Eigen::Vector2d Layout::route_point(double s, Eigen::Vector2d* tangent) const {
  const double total = route_length();
  s = std::fmod(s, total);
  if (s < 0) s += total;
  for (size_t i = 0; i < route.size(); ++i) {
    const V2 a = route[i], b = route[(i + 1) % route.size()];
    const double len = (b - a).norm();
    if (s <= len || i + 1 == route.size()) {
      if (tangent) *tangent = (b - a).normalized();
      return a + (b - a) * std::min(1.0, s / len);
    }
    s -= len;
  }
  return route.front();
}

std::vector<Footprint> Layout::corridor() const {
  std::vector<Footprint> c;
  for (size_t i = 0; i < route.size(); ++i)
    c.push_back(segment_footprint(route[i], route[(i + 1) % route.size()], route_clearance));
  return c;
}

Layout build_layout(const LayoutParams& params, uint64_t seed) {
  if (params.width <= 0 || params.length <= 0 || params.height <= 0)
    throw Error("lista-sim: scene sizes must be > 0");
  Layout l;
  l.kind = params.kind;
  l.area_min = V2(0.3, 0.3);
  l.area_max = V2(params.width - 0.3, params.length - 0.3);
  Rng rng(seed, hash_string("layout"));
  if (params.kind == "office")
    build_office(l, params, rng);
  else if (params.kind == "hall")
    build_hall(l, params, rng);
  else if (params.kind == "yard")
    build_yard(l, params, rng);
  else
    throw Error("lista-sim: unknown scene kind '" + params.kind + "' (office, hall or yard)");
  return l;
}

}  // namespace lista::sim
