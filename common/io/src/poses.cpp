// poses.txt / poses_gt.txt: TUM (8 fields) or KITTI (12 fields) per line.
#include "rotation_check.hpp"
#include "text_util.hpp"

#include <lista/error.hpp>
#include <lista_io/atomic_file.hpp>
#include <lista_io/poses.hpp>

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>

namespace lista::io {

namespace {
constexpr double kMaxPosition = 1e8;  // m
}

std::vector<PoseRecord> read_poses(const std::string& path, PoseFormat* format) {
  std::string text = detail::read_whole_file(path);
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // a UTF-8 byte-order mark some editors add
  std::vector<PoseRecord> out;
  int layout = 0;  // fields per line, fixed by the first pose line
  int line_no = 0;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    const std::vector<std::string> tok = detail::split_ws(line);
    if (tok.empty()) continue;
    auto fail = [&](const std::string& what) {
      return Error(path + ":" + std::to_string(line_no) + ": " + what);
    };
    const int n = static_cast<int>(tok.size());
    if (n != 8 && n != 12)
      throw fail("expected 8 fields (TUM: t tx ty tz qx qy qz qw) or 12 (KITTI: 3x4 [R|t]), got " + std::to_string(n) +
                 (line.find(',') != std::string::npos ? "; fields are separated by spaces, not commas" : ""));
    if (layout == 0) layout = n;
    if (n != layout)
      throw fail("mixed pose layouts: " + std::to_string(n) + " fields after lines of " + std::to_string(layout));
    double v[12];
    for (int k = 0; k < n; ++k)
      if (!detail::parse_double(tok[k], v[k]) || !std::isfinite(v[k]))
        throw fail("field " + std::to_string(k + 1) + " '" + tok[k] + "' is not a finite number" +
                   (tok[k].find(',') != std::string::npos ? "; fields are separated by spaces, not commas"
                    : tok[k].find_first_of("xX") != std::string::npos ? " (decimal numbers only)"
                                                                        : ""));
    PoseRecord rec;
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    if (n == 8) {
      rec.timestamp = v[0];
      t = Eigen::Vector3d(v[1], v[2], v[3]);
      Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
      if (std::abs(q.norm() - 1.0) > detail::kOrthoTolerance)
        throw fail("rotation quaternion has norm " + std::to_string(q.norm()) + ", expected 1");
      R = q.normalized().toRotationMatrix();
    } else {
      rec.timestamp = static_cast<double>(out.size());
      R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
      t = Eigen::Vector3d(v[3], v[7], v[11]);
      if (const std::string why = detail::rotation_problem(R); !why.empty()) throw fail(why);
      // Re-orthonormalise: nearest rotation via SVD.
      Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
      R = svd.matrixU() * svd.matrixV().transpose();
    }
    // Geocentric (ECEF) and UTM coordinates stay within 1e7 m; beyond 1e8 m
    // a position is a corrupt value, whose squares overflow float later.
    if (t.cwiseAbs().maxCoeff() > kMaxPosition)
      throw fail("position (" + tok[n == 8 ? 1 : 3] + ", " + tok[n == 8 ? 2 : 7] + ", " + tok[n == 8 ? 3 : 11] +
                 ") lies more than 1e8 m from zero: not a place on Earth; a corrupt pose?");
    rec.pose.setIdentity();
    rec.pose.linear() = R;
    rec.pose.translation() = t;
    out.push_back(rec);
  }
  if (format) *format = layout == 12 ? PoseFormat::kitti : PoseFormat::tum;
  return out;
}

void write_poses(const std::string& path, const std::vector<PoseRecord>& poses, PoseFormat format) {
  std::string text;
  text.reserve(poses.size() * 160);
  char buf[512];
  for (const auto& p : poses) {
    const Eigen::Vector3d t = p.pose.translation();
    if (format == PoseFormat::tum) {
      const Eigen::Quaterniond q(p.pose.rotation());
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", p.timestamp, t.x(), t.y(),
                    t.z(), q.x(), q.y(), q.z(), q.w());
    } else {
      const Eigen::Matrix3d R = p.pose.rotation();
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                    R(0, 0), R(0, 1), R(0, 2), t.x(), R(1, 0), R(1, 1), R(1, 2), t.y(), R(2, 0), R(2, 1), R(2, 2),
                    t.z());
    }
    text += buf;
  }
  write_file_atomic(path, text);
}

}  // namespace lista::io
