#include "charts.hpp"

#include "svg.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lista::report {

namespace {

// One marker shape per mission (circle, square, triangle, diamond, then
// round again), so the PCA plot tells every mission of a long patrol apart.
std::string mission_marker(size_t mission, double x, double y, const Rgb& colour, const std::string& title) {
  const std::string fill = "\" fill=\"" + colour.css() + "\">" + title;
  auto polygon = [&](const std::vector<std::pair<double, double>>& corners) {
    std::string pts;
    for (const auto& [dx, dy] : corners) pts += (pts.empty() ? "" : " ") + fmt(x + dx, 1) + "," + fmt(y + dy, 1);
    return "<polygon points=\"" + pts + fill + "</polygon>";
  };
  switch (mission % 4) {
    case 0: return "<circle cx=\"" + fmt(x, 1) + "\" cy=\"" + fmt(y, 1) + "\" r=\"6" + fill + "</circle>";
    case 1:
      return "<rect x=\"" + fmt(x - 5, 1) + "\" y=\"" + fmt(y - 5, 1) + "\" width=\"10\" height=\"10" + fill + "</rect>";
    case 2: return polygon({{0, -7}, {6, 5}, {-6, 5}});
    default: return polygon({{0, -7}, {7, 0}, {0, 7}, {-7, 0}});
  }
}

std::vector<const ObjectView*> of_mission(const ReportModel& model, size_t m) {
  std::vector<const ObjectView*> out;
  for (const auto& v : model.objects)
    if (v.object->mission == m) out.push_back(&v);
  return out;
}

}  // namespace

std::string render_match_matrix(const ReportModel& model, const DescriptorSet* descriptors, size_t a,
                                size_t b) {
  const auto rows = of_mission(model, a), cols = of_mission(model, b);
  if (rows.empty() || cols.empty()) return "<p class=\"empty\">No objects to compare in this pair.</p>\n";

  // Distances, then min-max normalised to a similarity in [0, 1]. With
  // descriptors, an object without a row (one a later stage added, such as
  // history.static's copies) gets no cell value: metres and descriptor
  // distances are not to be normalised together. NaN marks such cells.
  Eigen::MatrixXd dist(rows.size(), cols.size());
  double dmin = std::numeric_limits<double>::infinity(), dmax = -dmin;
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = 0; j < cols.size(); ++j) {
      if (descriptors) {
        const int ri = descriptors->row_of(rows[i]->object->id), rj = descriptors->row_of(cols[j]->object->id);
        dist(i, j) = ri >= 0 && rj >= 0 ? (descriptors->values.row(ri) - descriptors->values.row(rj)).norm()
                                        : std::numeric_limits<double>::quiet_NaN();
      } else {
        dist(i, j) = (rows[i]->object->centroid - cols[j]->object->centroid).norm();
      }
      if (!std::isnan(dist(i, j))) dmin = std::min(dmin, dist(i, j)), dmax = std::max(dmax, dist(i, j));
    }
  const double span = dmax - dmin > 1e-12 ? dmax - dmin : 1.0;

  const int cell = int(std::clamp(600.0 / std::max(rows.size(), cols.size()), 14.0, 40.0));
  const int margin = 48;
  const int w = margin + cell * int(cols.size()) + 10, h = margin + cell * int(rows.size()) + 10;
  std::string svg = "<svg class=\"match-matrix\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                    std::to_string(w) + "\" height=\"" + std::to_string(h) + "\">\n";
  const double font = std::min(12.0, cell * 0.45);
  std::string outlines;  // matched cells, drawn last
  for (size_t j = 0; j < cols.size(); ++j)
    svg += "<text x=\"" + fmt(margin + cell * (j + 0.5), 1) + "\" y=\"" + fmt(margin - 6, 1) +
           "\" font-size=\"" + fmt(font, 1) + "\" text-anchor=\"middle\">" +
           std::to_string(cols[j]->object->id) + "</text>\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    svg += "<text x=\"" + fmt(margin - 6, 1) + "\" y=\"" + fmt(margin + cell * (i + 0.5) + font / 3, 1) +
           "\" font-size=\"" + fmt(font, 1) + "\" text-anchor=\"end\">" +
           std::to_string(rows[i]->object->id) + "</text>\n";
    for (size_t j = 0; j < cols.size(); ++j) {
      const bool known = !std::isnan(dist(i, j));
      const double similarity = known ? 1.0 - (dist(i, j) - dmin) / span : 0.0;
      const bool matched = rows[i]->match == cols[j]->object->id;
      svg += "<rect x=\"" + std::to_string(margin + cell * int(j)) + "\" y=\"" +
             std::to_string(margin + cell * int(i)) + "\" width=\"" + std::to_string(cell) +
             "\" height=\"" + std::to_string(cell) + "\" fill=\"" + (known ? heat(similarity).css() : "#f4f4f4") +
             "\" stroke=\"#ddd\" stroke-width=\"0.5\"><title>" + std::to_string(rows[i]->object->id) + " vs " +
             std::to_string(cols[j]->object->id) + (known ? ": similarity " + fmt(similarity) : ": no descriptor") +
             (matched ? ", matched, confidence " + fmt(rows[i]->confidence) : "") + "</title></rect>\n";
      if (matched) {
        // Drawn after the cell, inset, so no neighbouring cell paints over it.
        outlines += "<rect class=\"matched\" x=\"" + fmt(margin + cell * double(j) + 1.5, 1) + "\" y=\"" +
                    fmt(margin + cell * double(i) + 1.5, 1) + "\" width=\"" + fmt(cell - 3.0, 1) + "\" height=\"" +
                    fmt(cell - 3.0, 1) + "\" fill=\"none\" stroke=\"#000\" stroke-width=\"2.5\"/>\n";
        if (cell >= 24)  // white on dark cells, black on light ones
          outlines += "<text x=\"" + fmt(margin + cell * (j + 0.5), 1) + "\" y=\"" +
                      fmt(margin + cell * (i + 0.5) + font / 3, 1) + "\" font-size=\"" + fmt(font * 0.8, 1) +
                      "\" text-anchor=\"middle\" fill=\"" + (similarity > 0.55 ? "#fff" : "#000") + "\">" +
                      fmt(rows[i]->confidence) + "</text>\n";
      }
    }
  }
  svg += outlines;
  svg += "<text x=\"4\" y=\"14\" font-size=\"11\">rows: " + escape(model.missions[a]) +
         ", columns: " + escape(model.missions[b]) + "</text>\n</svg>\n";
  return svg;
}

std::string render_pca(const ReportModel& model, const DescriptorSet& descriptors) {
  const Eigen::Index n = descriptors.values.rows();
  if (n < 2 || descriptors.values.cols() < 1) return {};
  Eigen::MatrixXd X = descriptors.values.cast<double>();
  X.rowwise() -= X.colwise().mean();
  const Eigen::MatrixXd cov = X.transpose() * X / double(n - 1);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  // Eigenvalues ascend: the last two columns are the principal axes.
  const Eigen::Index d = cov.rows();
  Eigen::MatrixXd axes(d, 2);
  axes.col(0) = eig.eigenvectors().col(d - 1);
  axes.col(1) = d > 1 ? Eigen::VectorXd(eig.eigenvectors().col(d - 2)) : Eigen::VectorXd::Zero(d);
  const Eigen::MatrixXd P = X * axes;

  const double w = 560, h = 420, pad = 40;
  const Eigen::Vector2d lo = P.colwise().minCoeff(), hi = P.colwise().maxCoeff();
  auto sx = [&](double v) { return pad + (v - lo.x()) / std::max(1e-12, hi.x() - lo.x()) * (w - 2 * pad); };
  auto sy = [&](double v) { return h - pad - (v - lo.y()) / std::max(1e-12, hi.y() - lo.y()) * (h - 2 * pad); };
  std::string svg = "<svg class=\"pca\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt(w, 0) +
                    "\" height=\"" + fmt(h, 0) + "\">\n<rect x=\"0\" y=\"0\" width=\"" + fmt(w, 0) +
                    "\" height=\"" + fmt(h, 0) + "\" fill=\"#fafafa\" stroke=\"#ccc\"/>\n";
  svg += "<text x=\"" + fmt(w / 2, 0) + "\" y=\"" + fmt(h - 8, 0) +
         "\" font-size=\"12\" text-anchor=\"middle\">PC 1</text><text x=\"12\" y=\"" + fmt(h / 2, 0) +
         "\" font-size=\"12\" transform=\"rotate(-90 12 " + fmt(h / 2, 0) + ")\">PC 2</text>\n";
  for (Eigen::Index i = 0; i < n; ++i) {
    const int id = descriptors.object_ids[i];
    const ObjectView* v = model.find(id);
    const int group = v ? v->group : -1;
    const Rgb colour = palette(group);
    const double x = sx(P(i, 0)), y = sy(P(i, 1));
    const size_t mission = v ? v->object->mission : 0;
    const std::string title = "<title>object " + std::to_string(id) + ", " +
                              escape(v ? model.missions[mission] : std::string("?")) + ", group " +
                              std::to_string(group) + "</title>";
    svg += mission_marker(mission, x, y, colour, title) + "\n";
    svg += "<text x=\"" + fmt(x + 7, 1) + "\" y=\"" + fmt(y - 6, 1) + "\" font-size=\"10\">" +
           std::to_string(id) + "</text>\n";
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace lista::report
