// io.missions: reads a dataset of missions (data contract, sect. 1).
#include <lista/lista.hpp>
#include <lista_io/dataset.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

namespace lista::io {

namespace {

// The origin of the run's local frame (MissionSet::origin): the first pose's
// position rounded to whole kilometres, zero when it lies within a km of zero.
Eigen::Vector3d local_origin(const MissionSet& set) {
  for (const auto& m : set.missions)
    if (!m.scans.empty()) {
      const Eigen::Vector3d t = m.scans.front().pose.translation();
      if (t.cwiseAbs().maxCoeff() < 1000.0) return Eigen::Vector3d::Zero();
      return (t / 1000.0).array().round().matrix() * 1000.0;
    }
  return Eigen::Vector3d::Zero();
}

// "scan_2.pcd", "scan_10.pcd": numbers of different widths sort by character,
// not by value, and poses.txt pairs its lines with scans in file-name order.
// The first pair out of numeric order, or "" when the names agree.
std::string misordered_scan_names(const Mission& m) {
  long long last = -1;
  std::string last_name;
  for (const auto& scan : m.scans) {
    const std::string name = std::filesystem::path(scan.file).filename().string();
    const std::string stem = std::filesystem::path(scan.file).stem().string();
    size_t end = stem.size(), begin = end;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(stem[begin - 1]))) --begin;
    if (begin == end || end - begin > 18) return {};  // no number to judge by
    const long long value = std::stoll(stem.substr(begin));
    if (value < last) return last_name + " sorts before " + name;
    last = value;
    last_name = name;
  }
  return {};
}

class MissionsStage : public Stage {
 public:
  explicit MissionsStage(const Params& p)
      : path_(p.get<std::string>("path")), missions_(p.get<std::vector<std::string>>("missions")) {}

  Outputs run(const Inputs&, Context& ctx) override {
    const std::string dataset = path_.empty() ? ctx.run_info().dataset : path_;
    if (dataset.empty())
      throw Error("no dataset: set 'path' or give the run a dataset (lista-run --dataset DIR)");
    const std::vector<std::string> names = missions_.empty() ? list_missions(dataset) : missions_;
    if (names.size() < 2) ctx.warn(dataset + ": only one mission; change detection needs two or more");
    DatasetOptions opt;
    opt.threads = ctx.threads();
    MissionSet set;
    set.dataset = dataset;
    ctx.progress().begin("reading missions", names.size());
    for (const auto& name : names) {
      ctx.throw_if_cancelled();
      DatasetOptions one = opt;
      one.missions = {name};
      MissionSet part = read_dataset(dataset, one);
      for (const auto& seen : set.missions)
        if (seen.name == part.missions[0].name) throw Error("mission '" + name + "' listed twice in 'missions'");
      set.missions.push_back(std::move(part.missions[0]));
      ctx.progress().advance();
    }
    ctx.progress().end();
    set.origin = local_origin(set);
    if (!set.origin.isZero()) {
      for (auto& m : set.missions) {
        for (auto& s : m.scans) s.pose.translation() -= set.origin;
        for (auto& g : m.poses_gt) g.translation() -= set.origin;
      }
      char text[160];
      std::snprintf(text, sizeof text, "poses lie far from zero: working around (%.0f, %.0f, %.0f) m, added back in the report",
                    set.origin.x(), set.origin.y(), set.origin.z());
      ctx.info(text);
    }
    size_t points = 0, skipped = 0, scans = 0;
    for (const auto& m : set.missions) {
      // Map-frame .pcd scans carry their pose in VIEWPOINT; PCL writes an
      // identity there by default, so identity everywhere means no poses.
      if (m.scans.size() > 1 && !std::filesystem::exists(std::filesystem::path(m.dir) / "poses.txt") &&
          std::all_of(m.scans.begin(), m.scans.end(), [](const Scan& s) { return s.pose.isApprox(Eigen::Isometry3d::Identity()); }))
        ctx.warn("mission '" + m.name + "': every scan's VIEWPOINT is the identity; if the scans are in the sensor "
                 "frame, give their poses in poses.txt and put them in scans/ (docs/formats.md)");
      std::vector<std::string> empty;
      for (const auto& scan : m.scans)
        if (scan.points && scan.points->empty()) empty.push_back(std::filesystem::path(scan.file).filename().string());
      if (!empty.empty())
        ctx.warn("mission '" + m.name + "': " + std::to_string(empty.size()) + " scan" + (empty.size() > 1 ? "s" : "") +
                 " with no finite point (" + empty.front() + (empty.size() > 1 ? ", ..." : "") + ")");
      if (const std::string pair = misordered_scan_names(m); !pair.empty())
        ctx.warn("mission '" + m.name + "': " + pair +
                 " by name, and scans take their poses in file-name order: zero-pad the numbers (scan_002.pcd)");
      const size_t n = m.point_count();
      ctx.info("mission '" + m.name + "': " + std::to_string(m.scans.size()) + " scans, " + std::to_string(n) +
               " points" + (m.skipped_nonfinite ? ", " + std::to_string(m.skipped_nonfinite) + " non-finite skipped" : "") +
               (m.poses_gt.empty() ? "" : ", poses_gt.txt"));
      points += n;
      skipped += m.skipped_nonfinite;
      scans += m.scans.size();
    }
    ctx.record("missions", double(set.missions.size()));
    ctx.record("scans", double(scans));
    ctx.record("points", double(points));
    ctx.record("skipped_nonfinite", double(skipped));
    Outputs out;
    out.put("missions", std::move(set));
    return out;
  }

 private:
  std::string path_;
  std::vector<std::string> missions_;
};

StageInfo info() {
  StageInfo s;
  s.name = "io.missions";
  s.version = "1.0.0";
  s.summary = "reads a dataset of missions (poses.txt + scans/, or the VIEWPOINT layout)";
  s.doc =
      "Reads the missions of a dataset folder as in the data contract, section 1: per mission poses.txt "
      "(TUM or KITTI layout) and scans/ (.pcd ascii/binary/binary_compressed, .ply, KITTI .bin) sorted by "
      "name, or a folder of map-frame .pcd scans carrying the sensor pose in VIEWPOINT; poses_gt.txt when "
      "present. Scans are read in parallel. Non-finite points are skipped and counted. Errors: scan count "
      "!= pose count, unreadable or malformed file (with its line), non-orthonormal rotation, empty "
      "mission. Poses more than a km from zero (georeferenced) are moved by a whole number of km so float "
      "points keep millimetres; io.report adds the offset back. See docs/formats.md.";
  s.outputs = {{"missions", "missions", "the missions, each in its own map frame (to_common = identity)"}};
  s.params = {
      ParamSpec::text("path", "", "dataset folder; empty = the run's dataset (lista-run --dataset)"),
      ParamSpec::text_list("missions", {}, "mission folder names in the order to use; empty = all, sorted")};
  return s;
}

void register_stages(Registrar& r) {
  r.add(info(), [](const Params& p) { return std::make_unique<MissionsStage>(p); });
}

}  // namespace

}  // namespace lista::io

LISTA_PLUGIN(lista::io::register_stages)
