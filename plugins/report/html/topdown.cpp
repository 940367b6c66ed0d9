#include "topdown.hpp"

#include "svg.hpp"

#include <stb/stb_image_write.h>

#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <cmath>

namespace lista::report {

namespace {

// What an object is in the map of missions a and b (= a + 1): what left a
// ("removed"), what arrived in b ("added"), one end of a move from one to
// the other ("moved"), or nothing ("": another pair's change). With three or
// more missions an object of b may also move on to c, or leave before c;
// that belongs to the next map. A report whose points changed against
// neither neighbour (history.static's: the object standing still before or
// after its change) is in no map. Which neighbour an unpaired object changed
// against comes from its change points (PointSet::changed_against): a desk
// that arrived in b and left before c is an arrival here, whatever its one
// status says; without that channel the status decides.
std::string status_in_pair(const ObjectView& v, const ReportModel& model, size_t a, size_t b) {
  const size_t m = v.object->mission;
  if (m != a && m != b) return "";
  const size_t other = m == a ? b : a;
  if (v.object->points.has_changed_against() && v.object->points.changed_against_all() == 0) return "";
  if (v.status == ChangeStatus::moved) {
    if (const ObjectView* p = v.match >= 0 ? model.find(v.match) : nullptr; p && p->object->mission == other)
      return "moved";
    for (const auto& o : model.objects)  // its partner may name it while its own match points on
      if (o.match == v.object->id && o.object->mission == other) return "moved";
  }
  if (!v.object->points.has_changed_against()) {
    if (v.status == ChangeStatus::removed && m == a) return "removed";
    if (v.status == ChangeStatus::added && m == b) return "added";
    return "";
  }
  const uint8_t bits = v.object->points.changed_against_all();
  if (m == a && (bits & changed_against_next)) return "removed";
  if (m == b && (bits & changed_against_previous)) return "added";
  return "";
}

struct Raster {
  int width = 1, height = 1;
  double x0 = 0, y1 = 0, res = 0.05;  // x of column 0, y of row 0, metres per pixel
  int col(double x) const { return int((x - x0) / res); }
  int row(double y) const { return int((y1 - y) / res); }
  bool inside(int c, int r) const { return c >= 0 && r >= 0 && c < width && r < height; }
};

// Map points of both missions in the common frame, floor and ceiling cut away
// by height percentiles so walls and furniture remain.
std::vector<Eigen::Vector3f> static_map(const MissionSet& missions, size_t a, size_t b, size_t budget) {
  size_t total = missions.missions[a].point_count() + missions.missions[b].point_count();
  const size_t stride = std::max<size_t>(1, total / std::max<size_t>(1, budget));
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(total / stride + 16);
  for (size_t m : {a, b}) {
    const Mission& mission = missions.missions[m];
    for (size_t s = 0; s < mission.scans.size(); ++s) {
      if (!mission.scans[s].points) continue;
      const Eigen::Isometry3f T = mission.sensor_to_common(s).cast<float>();
      const auto& xyz = mission.scans[s].points->xyz;
      for (size_t i = (s * 7) % stride; i < xyz.size(); i += stride) pts.push_back(T * xyz[i]);
    }
  }
  if (pts.size() < 100) return pts;
  std::vector<float> z(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) z[i] = pts[i].z();
  auto pct = [&](double q) { return geometry::kth_smallest(z, size_t(q * (z.size() - 1))); };
  const float floor_z = pct(0.03), ceiling_z = pct(0.97);
  const float lo = floor_z + 0.15f, hi = ceiling_z - 0.15f;
  if (hi <= lo) return pts;
  std::vector<Eigen::Vector3f> kept;
  kept.reserve(pts.size());
  for (const auto& p : pts)
    if (p.z() > lo && p.z() < hi) kept.push_back(p);
  return kept;
}

void write_png(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* bytes = static_cast<const uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

// An object drawn in the map of missions a and b, with its status there
// (status_in_pair).
struct Shown {
  const ObjectView* view;
  std::string status;
};

// Metres to pixels of one map.
struct Frame {
  Raster r;
  Eigen::Vector2d lo, hi;  // bounds (m), margins included
  double extent = 0;       // the longer side (m)
  // The pixel position of a point (x right, y down).
  std::pair<double, double> px(const Eigen::Vector3f& p) const {
    return {(p.x() - r.x0) / r.res, (r.y1 - p.y()) / r.res};
  }
};

// Bounds over the map and every object shown, half a metre round, in at
// most options.pixels along the longer side.
Frame frame_of(const std::vector<Eigen::Vector3f>& map, const std::vector<Shown>& shown,
               const TopdownOptions& options) {
  Frame f;
  Eigen::Vector2d& lo = f.lo;
  Eigen::Vector2d& hi = f.hi;
  lo = Eigen::Vector2d(1e30, 1e30);
  hi = Eigen::Vector2d(-1e30, -1e30);
  auto grow = [&](const Eigen::Vector3f& p) {
    lo = lo.cwiseMin(p.head<2>().cast<double>());
    hi = hi.cwiseMax(p.head<2>().cast<double>());
  };
  for (const auto& p : map) grow(p);
  for (const auto& s : shown) {
    grow(s.view->object->bbox_min);
    grow(s.view->object->bbox_max);
  }
  if (lo.x() > hi.x()) lo = hi = Eigen::Vector2d::Zero();
  lo -= Eigen::Vector2d(0.5, 0.5);
  hi += Eigen::Vector2d(0.5, 0.5);
  Raster& r = f.r;
  f.extent = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  // Never coarser-capped: a map kilometres wide (a stray pose) must still fit options.pixels, not take gigabytes.
  r.res = std::max(f.extent / std::max(64, options.pixels), 0.01);
  r.width = std::max(1, int(std::ceil((hi.x() - lo.x()) / r.res)));
  r.height = std::max(1, int(std::ceil((hi.y() - lo.y()) / r.res)));
  r.x0 = lo.x();
  r.y1 = hi.y();
  return f;
}

// The map as a PNG: the static points as density, the objects' points on
// top in their status colours.
std::vector<uint8_t> map_png(const std::vector<Eigen::Vector3f>& map, const std::vector<Shown>& shown,
                             const Raster& r, size_t b) {
  // Static map as point density, log-scaled so sparse far walls stay visible.
  std::vector<uint32_t> density(size_t(r.width) * r.height, 0);
  for (const auto& p : map) {
    const int c = r.col(p.x()), w = r.row(p.y());
    if (r.inside(c, w)) ++density[size_t(w) * r.width + c];
  }
  std::vector<uint32_t> nonzero;
  for (uint32_t d : density)
    if (d) nonzero.push_back(d);
  double top = 1;
  if (!nonzero.empty()) top = std::max<double>(1, geometry::kth_smallest(nonzero, size_t(0.95 * (nonzero.size() - 1))));
  std::vector<uint8_t> rgb(size_t(r.width) * r.height * 3, 255);
  for (size_t i = 0; i < density.size(); ++i) {
    if (!density[i]) continue;
    const double t = std::min(1.0, std::log1p(density[i]) / std::log1p(top));
    const uint8_t g = uint8_t(225 - 150 * t);
    rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = g;
  }
  // Object points on top, coloured by status; the later mission of a moved
  // pair is drawn darker so both places can be told apart.
  for (const auto& [v, status] : shown) {
    Rgb colour = status_colour(status);
    if (status == "moved" && v->object->mission == b)
      colour = {uint8_t(colour.r / 2), uint8_t(colour.g / 2), uint8_t(colour.b / 2 + 60)};
    for (const auto& p : v->object->points.xyz) {
      const int c = r.col(p.x()), w = r.row(p.y());
      if (!r.inside(c, w)) continue;
      uint8_t* px = &rgb[(size_t(w) * r.width + c) * 3];
      px[0] = colour.r;
      px[1] = colour.g;
      px[2] = colour.b;
    }
  }
  std::vector<uint8_t> png;
  stbi_write_png_to_func(&write_png, &png, r.width, r.height, 3, rgb.data(), r.width * 3);
  return png;
}

// The arrowheads of mission a's map.
std::string arrow_markers(size_t a) {
  std::string svg;
  // Two arrowheads: a short move gets the small one, so its line still shows.
  svg += "<defs><marker id=\"arrow" + std::to_string(a) +
         "\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"6\" markerHeight=\"6\" "
         "orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"#111\"/></marker>"
         "<marker id=\"arrow-small" + std::to_string(a) +
         "\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"3\" markerHeight=\"3\" "
         "orient=\"auto-start-reverse\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"#111\"/></marker></defs>\n";
  return svg;
}

// Each object's box, its id where it covers no other box or label, and an
// arrow from a move's place in a to its place in b.
std::string object_marks(const std::vector<Shown>& shown, const ReportModel& model, size_t a, size_t b,
                         const Frame& frame, double font) {
  const auto px = [&frame](const Eigen::Vector3f& p) { return frame.px(p); };
  std::string svg;
  // Every box in pixels first: a label goes where it covers no other box
  // and no label placed before it.
  struct Rect {
    double x0, y0, x1, y1;
    bool overlaps(const Rect& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
  };
  std::vector<Rect> boxes, labels;
  for (const auto& [v, status] : shown) {
    const auto [bx0, by0] = px(Eigen::Vector3f(v->object->bbox_min.x(), v->object->bbox_max.y(), 0));
    const auto [bx1, by1] = px(Eigen::Vector3f(v->object->bbox_max.x(), v->object->bbox_min.y(), 0));
    boxes.push_back({bx0, by0, bx1, by1});
  }
  for (size_t k = 0; k < shown.size(); ++k) {
    const auto& [v, status] = shown[k];
    const double x0 = boxes[k].x0, y0 = boxes[k].y0, x1 = boxes[k].x1, y1 = boxes[k].y1;
    const Rgb colour = status_colour(status);
    svg += "<rect x=\"" + fmt(x0, 1) + "\" y=\"" + fmt(y0, 1) + "\" width=\"" + fmt(x1 - x0, 1) +
           "\" height=\"" + fmt(y1 - y0, 1) + "\" fill=\"none\" stroke=\"" + colour.css() +
           "\" stroke-width=\"" + fmt(font / 6, 1) + "\"" +
           (v->confidence < kLowConfidence ? " stroke-dasharray=\"" + fmt(font / 2, 1) + " " + fmt(font / 3, 1) +
                                      "\" class=\"low-confidence\""
                                : std::string()) +
           "/>\n";
    // Right of the box's top, else left of it, above it, below it; the
    // first spot clear of other boxes and labels (else the first).
    const std::string id = std::to_string(v->object->id);
    const double w = 0.6 * font * double(id.size()), h = font;
    const std::pair<double, double> spots[] = {
        {x1 + 2, y0}, {x0 - 2 - w, y0}, {x0, y0 - 2 - h}, {x0, y1 + 2}};  // top-left corners
    Rect label{spots[0].first, spots[0].second, spots[0].first + w, spots[0].second + h};
    for (const auto& [sx, sy] : spots) {
      const Rect r{sx, sy, sx + w, sy + h};
      bool clear = true;
      for (size_t o = 0; o < boxes.size() && clear; ++o) clear = o == k || !r.overlaps(boxes[o]);
      for (size_t o = 0; o < labels.size() && clear; ++o) clear = !r.overlaps(labels[o]);
      if (clear) {
        label = r;
        break;
      }
    }
    labels.push_back(label);
    svg += "<text x=\"" + fmt(label.x0, 1) + "\" y=\"" + fmt(label.y0 + font * 0.8, 1) + "\" font-size=\"" +
           fmt(font, 1) + "\" fill=\"" + colour.css() + "\" class=\"object-label\">" + id + "</text>\n";
    if (status == "moved" && v->object->mission == a && v->match >= 0) {
      const ObjectView* partner = model.find(v->match);
      if (partner && partner->object->mission == b) {
        const auto [ax, ay] = px(v->object->centroid);
        const auto [bx, by] = px(partner->object->centroid);
        // The big head is 6 stroke widths long: under 3 heads of line, the small one.
        const double length = std::hypot(bx - ax, by - ay), head = 6.0 * font / 5.0;
        svg += "<line x1=\"" + fmt(ax, 1) + "\" y1=\"" + fmt(ay, 1) + "\" x2=\"" + fmt(bx, 1) +
               "\" y2=\"" + fmt(by, 1) + "\" stroke=\"#111\" stroke-width=\"" + fmt(font / 5, 1) +
               "\" marker-end=\"url(#" + (length < 3.0 * head ? "arrow-small" : "arrow") + std::to_string(a) +
               ")\"/>\n";
      }
    }
  }
  return svg;
}

// What moved during mission a or b (a person walking by) as a dotted grey
// box: shown so a user sees it was looked at, apart from the changes.
std::string dynamic_marks(const ReportModel& model, size_t a, size_t b, const Frame& frame, double font) {
  std::string svg;
  for (const Dynamic& d : model.dynamics) {
    if (d.mission != a && d.mission != b) continue;
    const auto [x0, y0] = frame.px(Eigen::Vector3f(d.bbox_min.x(), d.bbox_max.y(), 0));
    const auto [x1, y1] = frame.px(Eigen::Vector3f(d.bbox_max.x(), d.bbox_min.y(), 0));
    svg += "<rect x=\"" + fmt(x0, 1) + "\" y=\"" + fmt(y0, 1) + "\" width=\"" + fmt(x1 - x0, 1) + "\" height=\"" +
           fmt(y1 - y0, 1) + "\" fill=\"none\" stroke=\"#888\" stroke-width=\"" + fmt(font / 8, 1) +
           "\" stroke-dasharray=\"" + fmt(font / 4, 1) + "\" class=\"dynamic\"><title>moved during mission " +
           escape(d.mission < model.missions.size() ? model.missions[d.mission] : "") + " (" +
           std::to_string(d.points) + " points): dynamic, not a change</title></rect>\n";
  }
  return svg;
}

// Coordinates along the top and left edges and a scale bar of 1, 5 or 10 m.
std::string axes_and_scale(const Frame& frame, double font, const Eigen::Vector3d& origin) {
  const Raster& r = frame.r;
  const Eigen::Vector2d &lo = frame.lo, &hi = frame.hi;
  // Scale bar: 1 m, 5 m or 10 m depending on the map size.
  const double bar_m = frame.extent > 60 ? 10 : frame.extent > 15 ? 5 : 1;
  const double bar_px = bar_m / r.res;
  std::string svg;
  // Coordinates along the top and left edges, in the dataset's own frame
  // (the object table's), one tick per scale-bar length: a centroid from the
  // table can be found on the map.
  svg += "<g class=\"axes\" font-size=\"" + fmt(font * 0.8, 1) + "\" fill=\"#555\">";
  for (double x = std::ceil(lo.x() / bar_m) * bar_m; x <= hi.x(); x += bar_m) {
    const double c = (x - r.x0) / r.res;
    svg += "<line x1=\"" + fmt(c, 1) + "\" y1=\"0\" x2=\"" + fmt(c, 1) + "\" y2=\"" + fmt(font * 0.5, 1) +
           "\" stroke=\"#555\"/><text x=\"" + fmt(c + 2, 1) + "\" y=\"" + fmt(font * 1.2, 1) + "\">" +
           fmt(x + origin.x(), 0) + "</text>";
  }
  for (double y = std::ceil(lo.y() / bar_m) * bar_m; y <= hi.y(); y += bar_m) {
    const double w = (r.y1 - y) / r.res;
    svg += "<line x1=\"0\" y1=\"" + fmt(w, 1) + "\" x2=\"" + fmt(font * 0.5, 1) + "\" y2=\"" + fmt(w, 1) +
           "\" stroke=\"#555\"/><text x=\"" + fmt(font * 0.7, 1) + "\" y=\"" + fmt(w - 2, 1) + "\">" +
           fmt(y + origin.y(), 0) + "</text>";
  }
  svg += "<text x=\"" + fmt(r.width - 4, 1) + "\" y=\"" + fmt(r.height - 6, 1) +
         "\" text-anchor=\"end\">x (m) &rarr;, y (m) &uarr;</text></g>\n";
  svg += "<g class=\"scale\"><rect x=\"10\" y=\"" + fmt(r.height - 20, 1) + "\" width=\"" + fmt(bar_px, 1) +
         "\" height=\"4\" fill=\"#111\"/><text x=\"10\" y=\"" + fmt(r.height - 26, 1) +
         "\" font-size=\"" + fmt(font, 1) + "\">" + fmt(bar_m, 0) + " m</text></g>\n";
  return svg;
}

}  // namespace

std::string render_topdown(const MissionSet& missions, const ReportModel& model, size_t a, size_t b,
                           const TopdownOptions& options) {
  const auto map = static_map(missions, a, b, options.max_map_points);
  std::vector<Shown> shown;
  for (const auto& v : model.objects)
    if (std::string st = status_in_pair(v, model, a, b); !st.empty()) shown.push_back({&v, std::move(st)});
  const Frame frame = frame_of(map, shown, options);
  const Raster& r = frame.r;
  const std::vector<uint8_t> png = map_png(map, shown, r, b);
  std::string svg = "<svg class=\"topdown\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " +
                    std::to_string(r.width) + " " + std::to_string(r.height) + "\" data-pair=\"" +
                    escape(missions.missions[a].name + "-" + missions.missions[b].name) + "\">\n";
  svg += arrow_markers(a);
  svg += "<image width=\"" + std::to_string(r.width) + "\" height=\"" + std::to_string(r.height) +
         "\" href=\"data:image/png;base64," + base64(png) + "\"/>\n";
  const double font = std::max(10.0, r.width / 70.0);
  svg += dynamic_marks(model, a, b, frame, font);
  svg += object_marks(shown, model, a, b, frame, font);
  svg += axes_and_scale(frame, font, missions.origin);
  svg += "</svg>\n";
  return svg;
}

}  // namespace lista::report
