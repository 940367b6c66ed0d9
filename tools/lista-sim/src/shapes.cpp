#include "shapes.hpp"

#include "rng.hpp"

#include <lista/error.hpp>

#include <cmath>
#include <functional>
#include <map>

namespace lista::sim {
namespace {

using V3 = Eigen::Vector3f;

// Four legs under a rectangular top of half sizes (hx, hy).
void add_legs(TriMesh& m, float hx, float hy, float h, float leg, float inset) {
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      const V3 c(sx * (hx - inset - leg), sy * (hy - inset - leg), 0.0f);
      m.add_box(c - V3(leg, leg, 0), c + V3(leg, leg, h));
    }
}

Shape chair(Rng& r) {
  Shape s;
  const float hx = r.uniform(0.21f, 0.27f), hy = r.uniform(0.21f, 0.26f);
  const float seat = r.uniform(0.42f, 0.48f), back = r.uniform(0.35f, 0.5f);
  add_legs(s.mesh, hx, hy, seat - 0.04f, 0.015f, 0.01f);
  s.mesh.add_box(V3(-hx, -hy, seat - 0.04f), V3(hx, hy, seat));
  s.mesh.add_box(V3(-hx, hy - 0.03f, seat), V3(hx, hy, seat + back));
  if (r.chance(0.5)) {  // armrests
    for (int sx : {-1, 1}) s.mesh.add_box(V3(sx * hx - 0.02f, -hy, seat + 0.18f), V3(sx * hx + 0.02f, hy, seat + 0.21f));
  }
  s.reflectivity = r.uniform(0.2f, 0.5f);
  return s;
}

Shape table(Rng& r) {
  Shape s;
  const float hx = r.uniform(0.4f, 0.8f), hy = r.uniform(0.3f, 0.45f), h = r.uniform(0.71f, 0.76f);
  s.mesh.add_box(V3(-hx, -hy, h - 0.03f), V3(hx, hy, h));
  add_legs(s.mesh, hx, hy, h - 0.03f, 0.025f, 0.03f);
  s.reflectivity = r.uniform(0.4f, 0.7f);
  return s;
}

Shape desk(Rng& r) {
  Shape s;
  const float hx = r.uniform(0.6f, 0.9f), hy = r.uniform(0.35f, 0.4f), h = r.uniform(0.72f, 0.76f);
  s.mesh.add_box(V3(-hx, -hy, h - 0.03f), V3(hx, hy, h));
  for (int sx : {-1, 1}) s.mesh.add_box(V3(sx * hx - 0.02f, -hy, 0), V3(sx * hx + 0.02f, hy, h - 0.03f));
  s.mesh.add_box(V3(-hx, hy - 0.03f, 0.3f), V3(hx, hy - 0.01f, h - 0.03f));  // modesty panel
  if (r.chance(0.6)) {  // drawer pedestal
    const float w = 0.2f;
    s.mesh.add_box(V3(hx - 0.02f - 2 * w, -hy + 0.05f, 0), V3(hx - 0.02f, hy - 0.05f, h - 0.08f));
  }
  s.reflectivity = r.uniform(0.4f, 0.7f);
  return s;
}

Shape cabinet(Rng& r) {
  Shape s;
  const float hx = r.uniform(0.2f, 0.45f), hy = r.uniform(0.2f, 0.3f), h = r.uniform(0.7f, 1.9f);
  s.mesh.add_box(V3(-hx, -hy, 0.05f), V3(hx, hy, h));
  s.mesh.add_box(V3(-hx + 0.02f, -hy + 0.02f, 0), V3(hx - 0.02f, hy - 0.02f, 0.05f));  // plinth
  s.mesh.add_box(V3(-0.02f, -hy - 0.03f, h * 0.5f), V3(0.02f, -hy, h * 0.5f + 0.12f));  // handle
  s.reflectivity = r.uniform(0.5f, 0.8f);
  return s;
}

Shape shelf(Rng& r) {
  Shape s;
  const float hx = r.uniform(0.4f, 0.6f), hy = r.uniform(0.15f, 0.25f), h = r.uniform(1.2f, 2.0f);
  const int levels = r.integer(3, 5);
  add_legs(s.mesh, hx, hy, h, 0.02f, 0.0f);
  for (int k = 0; k < levels; ++k) {
    const float z = 0.08f + (h - 0.1f) * float(k) / float(levels - 1);
    s.mesh.add_box(V3(-hx, -hy, z - 0.02f), V3(hx, hy, z));
  }
  s.reflectivity = r.uniform(0.3f, 0.6f);
  return s;
}

Shape box(Rng& r) {
  Shape s;
  const float hx = r.uniform(0.15f, 0.35f), hy = r.uniform(0.15f, 0.3f), h = r.uniform(0.25f, 0.6f);
  s.mesh.add_box(V3(-hx, -hy, 0), V3(hx, hy, h));
  s.reflectivity = r.uniform(0.4f, 0.6f);
  return s;
}

Shape crate(Rng& r) {
  Shape s;
  const float hx = r.uniform(0.3f, 0.6f), hy = r.uniform(0.3f, 0.5f), h = r.uniform(0.4f, 0.9f);
  const float t = 0.03f;
  s.mesh.add_box(V3(-hx + t, -hy + t, 0), V3(hx - t, hy - t, h));
  // Edge battens stand proud of the panels, as on a wooden crate.
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      const V3 c(sx * (hx - t), sy * (hy - t), 0);
      s.mesh.add_box(c - V3(t, t, 0), c + V3(t, t, h));
    }
  for (float z : {0.0f, h - 2 * t}) {
    s.mesh.add_box(V3(-hx, -hy, z), V3(hx, -hy + 2 * t, z + 2 * t));
    s.mesh.add_box(V3(-hx, hy - 2 * t, z), V3(hx, hy, z + 2 * t));
  }
  s.reflectivity = r.uniform(0.35f, 0.55f);
  return s;
}

Shape barrel(Rng& r) {
  Shape s;
  const float radius = r.uniform(0.26f, 0.31f), h = r.uniform(0.8f, 0.92f);
  s.mesh.add_cylinder(V3::Zero(), radius, h, 20);
  for (float z : {0.0f, h * 0.33f, h * 0.66f, h - 0.03f}) s.mesh.add_cylinder(V3(0, 0, z), radius + 0.012f, 0.03f, 20);
  s.reflectivity = r.uniform(0.3f, 0.8f);
  return s;
}

Shape pallet(Rng& r) {
  Shape s;
  const bool euro = r.chance(0.5);
  const float hx = euro ? 0.6f : 0.6f, hy = euro ? 0.4f : 0.5f;
  const float deck = 0.022f, block = 0.1f;
  for (int k = 0; k < 5; ++k) {  // top boards
    const float y = -hy + 0.05f + (2 * hy - 0.1f) * float(k) / 4.0f;
    s.mesh.add_box(V3(-hx, y - 0.05f, block + deck), V3(hx, y + 0.05f, block + 2 * deck));
  }
  for (int sy : {-1, 0, 1}) {  // stringer boards and blocks
    const float y = sy * (hy - 0.05f);
    s.mesh.add_box(V3(-hx, y - 0.05f, block), V3(hx, y + 0.05f, block + deck));
    for (int sx : {-1, 0, 1}) {
      const float x = sx * (hx - 0.07f);
      s.mesh.add_box(V3(x - 0.07f, y - 0.05f, 0), V3(x + 0.07f, y + 0.05f, block));
    }
  }
  s.reflectivity = r.uniform(0.4f, 0.6f);
  return s;
}

Shape cart(Rng& r) {
  Shape s;
  const float hx = r.uniform(0.35f, 0.5f), hy = r.uniform(0.25f, 0.35f), deck = r.uniform(0.2f, 0.3f);
  const float wheel = 0.06f;
  s.mesh.add_box(V3(-hx, -hy, deck - 0.03f), V3(hx, hy, deck));
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      const V3 c(sx * (hx - 0.06f), sy * (hy - 0.06f), wheel);
      s.mesh.add_wheel(c, wheel, 0.03f);
      s.mesh.add_box(c + V3(-0.01f, -0.01f, 0), c + V3(0.01f, 0.01f, deck - 0.03f - wheel));
    }
  const float top = r.uniform(0.85f, 1.0f);
  for (int sy : {-1, 1}) s.mesh.add_box(V3(hx - 0.03f, sy * hy - 0.015f, deck), V3(hx, sy * hy + 0.015f, top));
  s.mesh.add_box(V3(hx - 0.03f, -hy, top - 0.03f), V3(hx, hy, top));
  if (r.chance(0.5)) s.mesh.add_box(V3(-hx, -hy, deck + 0.35f), V3(hx - 0.03f, hy, deck + 0.37f));  // 2nd tier
  s.reflectivity = r.uniform(0.3f, 0.7f);
  return s;
}

Shape car(Rng& r) {
  Shape s;
  const float hx = r.uniform(2.0f, 2.4f), hy = r.uniform(0.85f, 0.95f);
  const float wheel = 0.32f, body = r.uniform(0.95f, 1.1f), roof = r.uniform(1.4f, 1.55f);
  s.mesh.add_box(V3(-hx, -hy, 0.3f), V3(hx, hy, body));
  const float cab0 = -hx * r.uniform(0.45f, 0.6f), cab1 = hx * r.uniform(0.2f, 0.35f);
  s.mesh.add_box(V3(cab0, -hy + 0.08f, body), V3(cab1, hy - 0.08f, roof));
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      TriMesh w;
      w.add_wheel(V3::Zero(), wheel, 0.22f, 16);
      Eigen::Isometry3f p = Eigen::Isometry3f::Identity();
      p.linear() = Eigen::AngleAxisf(float(M_PI) / 2, V3::UnitZ()).toRotationMatrix();
      p.translation() = V3(sx * (hx - 0.7f), sy * (hy - 0.1f), wheel);
      s.mesh.append(w, p);
    }
  s.reflectivity = r.uniform(0.2f, 0.9f);
  return s;
}

Shape container(Rng& r) {
  Shape s;
  const bool forty = r.chance(0.3);
  const float hx = forty ? 6.06f : 3.03f, hy = 1.22f, h = r.chance(0.3) ? 2.9f : 2.59f;
  s.mesh.add_box(V3(-hx, -hy, 0), V3(hx, hy, h));
  // Corrugation ribs on the long sides.
  for (float x = -hx + 0.3f; x < hx - 0.2f; x += 0.6f)
    for (int sy : {-1, 1}) s.mesh.add_box(V3(x - 0.05f, sy * hy - 0.03f, 0.1f), V3(x + 0.05f, sy * hy + 0.03f, h - 0.1f));
  s.reflectivity = r.uniform(0.3f, 0.8f);
  return s;
}

Shape ibc_tank(Rng& r) {  // intermediate bulk container: cage on a pallet
  Shape s = pallet(r);
  const float h = r.uniform(1.0f, 1.16f);
  s.mesh.add_box(V3(-0.55f, -0.45f, 0.15f), V3(0.55f, 0.45f, h));
  s.reflectivity = r.uniform(0.6f, 0.9f);
  return s;
}

const std::map<std::string, std::function<Shape(Rng&)>>& makers() {
  static const std::map<std::string, std::function<Shape(Rng&)>> m = {
      {"chair", chair},   {"table", table},   {"desk", desk},   {"cabinet", cabinet},
      {"shelf", shelf},   {"box", box},       {"crate", crate}, {"barrel", barrel},
      {"pallet", pallet}, {"cart", cart},     {"car", car},     {"container", container},
      {"ibc", ibc_tank}};
  return m;
}

}  // namespace

const std::vector<std::string>& indoor_classes() {
  static const std::vector<std::string> c = {"chair", "table", "desk",   "cabinet", "shelf",
                                             "box",   "crate", "barrel", "pallet",  "cart"};
  return c;
}

const std::vector<std::string>& outdoor_classes() {
  static const std::vector<std::string> c = {"car", "crate", "container", "barrel", "pallet", "ibc"};
  return c;
}

void normalise_shape(Shape& shape) {
  Eigen::Vector3f lo, hi;
  shape.mesh.bounds(lo, hi);
  const Eigen::Vector3f shift(-0.5f * (lo.x() + hi.x()), -0.5f * (lo.y() + hi.y()), -lo.z());
  for (auto& v : shape.mesh.vertices) v += shift;
  shape.half_extent = 0.5f * (hi - lo).head<2>();
  shape.height = hi.z() - lo.z();
}

Shape make_shape(const std::string& cls, uint64_t variant) {
  const auto it = makers().find(cls);
  if (it == makers().end()) throw Error("lista-sim: unknown object class '" + cls + "'");
  Rng rng(variant, hash_string(cls.c_str()));
  Shape s = it->second(rng);
  s.cls = cls;
  s.source = "procedural";
  s.id = cls + "#" + std::to_string(variant);
  normalise_shape(s);
  return s;
}

void share_ids_of_identical_geometry(std::vector<Shape>& shapes) {
  std::map<uint64_t, std::string> first_id;
  for (auto& s : shapes) s.id = first_id.emplace(s.mesh.geometry_key(), s.id).first->second;
}

Shape make_person(uint64_t variant) {
  Rng r(variant, 77);
  Shape s;
  const float h = r.uniform(1.6f, 1.9f);
  s.mesh.add_cylinder(Eigen::Vector3f(-0.1f, 0, 0), 0.08f, h * 0.47f, 10);  // legs
  s.mesh.add_cylinder(Eigen::Vector3f(0.1f, 0, 0), 0.08f, h * 0.47f, 10);
  s.mesh.add_cylinder(Eigen::Vector3f(0, 0, h * 0.47f), 0.19f, h * 0.38f, 14);  // torso
  s.mesh.add_cylinder(Eigen::Vector3f(0, 0, h * 0.87f), 0.1f, h * 0.13f, 12);   // head
  s.cls = "person";
  s.source = "procedural";
  s.id = "person#" + std::to_string(variant);
  s.reflectivity = r.uniform(0.2f, 0.6f);
  normalise_shape(s);
  return s;
}

}  // namespace lista::sim
