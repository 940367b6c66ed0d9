// align.given: missions aligned by given transforms (identity, a file, or
// the ground-truth poses), so pipelines run before real alignment exists and
// alignment ablations have a drift-free reference.
#include "given_transforms.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lista::align {

namespace {

enum class Mode { identity, file, ground_truth, ground_truth_poses };

struct GivenConfig {
  Mode mode = Mode::identity;
  std::string file;
};

const ParamTable<GivenConfig>& param_table() {
  using C = GivenConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.choice("mode", &C::mode,
             {{"identity", Mode::identity}, {"file", Mode::file}, {"ground-truth", Mode::ground_truth},
              {"ground-truth-poses", Mode::ground_truth_poses}},
             "where the transforms come from");
    t.bind("file", &C::file, "transforms file for mode \"file\" (format in the doc)");
  });
}

class GivenStage : public Stage {
 public:
  explicit GivenStage(const Params& p) : GivenStage(param_table().read(p)) {}
  explicit GivenStage(const GivenConfig& c) : mode_(c.mode), file_(c.file) {
    if (mode_ == Mode::file && file_.empty()) throw Error("mode \"file\" needs the 'file' parameter");
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    // A shallow copy: scans' point data stay shared (shared_ptr<const PointSet>).
    MissionSet out = in.get<MissionSet>("missions");
    std::map<std::string, Eigen::Isometry3d> given;
    if (mode_ == Mode::file) {
      given = read_transform_file(file_);
      for (const auto& [name, T] : given)
        if (!out.find(name)) throw Error(file_ + ": mission '" + name + "' is not among the missions read");
    }
    for (auto& m : out.missions) {
      if (mode_ == Mode::identity) {
        m.to_common.setIdentity();
      } else if (mode_ == Mode::file) {
        auto it = given.find(m.name);
        if (it == given.end()) throw Error(file_ + ": no transform for mission '" + m.name + "'");
        m.to_common = it->second;
      } else {
        m.to_common = map_to_world_from_gt(m);
        // Residual of the fit: how well a rigid map->world explains the poses (drift shows here).
        double sq = 0;
        for (size_t i = 0; i < m.scans.size(); ++i)
          sq += (m.to_common * m.scans[i].pose.translation() - m.poses_gt[i].translation()).squaredNorm();
        const double rmse = std::sqrt(sq / double(std::max<size_t>(1, m.scans.size())));
        ctx.record(m.name + ".fit_rmse_m", rmse);
        char buf[160];
        std::snprintf(buf, sizeof buf, "mission '%s': map->world fit RMSE %.4f m over %zu scans", m.name.c_str(),
                      rmse, m.scans.size());
        ctx.info(buf);
        // Every scan placed at its true pose; to_common stays the fit, so the
        // map frame keeps its meaning and only the drift is taken out.
        if (mode_ == Mode::ground_truth_poses) {
          const Eigen::Isometry3d world_to_map = m.to_common.inverse();
          for (size_t i = 0; i < m.scans.size(); ++i) m.scans[i].pose = world_to_map * m.poses_gt[i];
        }
      }
    }
    return Outputs::of("missions", std::move(out));
  }

 private:
  Mode mode_;
  std::string file_;
};

StageInfo info() {
  StageInfo s;
  s.name = "align.given";
  s.version = "1.0.0";
  s.summary = "missions aligned by given transforms: identity, a file, or fitted to poses_gt.txt";
  s.doc =
      "Sets each mission's to_common without looking at the points: identity, a transforms file, or the rigid "
      "fit of poses.txt onto poses_gt.txt (ground-truth; ground-truth-poses also puts every scan at its true "
      "pose). For ablations and known setups. "
      "Details: docs/alignment.md, \"align.given\".";
  s.inputs = {{"missions", "missions", "missions as read"}};
  s.outputs = {{"missions", "missions", "the same missions with to_common set"}};
  s.params = param_table().specs();
  return s;
}

}  // namespace

}  // namespace lista::align

LISTA_STAGE_PLUGIN(lista::align::info, lista::align::GivenStage)
