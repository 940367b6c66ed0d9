#include "score.hpp"

#include <lista/error.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <tuple>
#include <utility>

namespace lista::eval {

namespace {

double ratio(double num, double den) { return den > 0 ? num / den : kUndefined; }

// What a run says about one mission: predicted points and reported objects' labels.
struct MissionRun {
  std::vector<std::vector<uint8_t>> predicted;          // [scan][index]
  std::map<int, std::map<uint32_t, size_t>> labels_of;  // reported id -> label -> points
  std::map<int, size_t> size_of;                        // reported id -> points in the cloud
};

MissionRun read_changes(const Truth& truth, size_t k, const std::string& run_dir, const io::Report& report) {
  const MissionTruth& mt = truth.labels[k];
  const std::string path = (std::filesystem::path(run_dir) / "changes" / (mt.name + ".pcd")).string();
  if (!std::filesystem::exists(path)) throw Error(path + ": missing (every mission of the report needs its change cloud)");
  const io::PcdTable t = io::read_pcd_table(path);
  const int cs = t.column("scan"), ci = t.column("index"), co = t.column("object");
  if (cs < 0 || ci < 0 || co < 0 || t.column("x") < 0 || t.column("y") < 0 || t.column("z") < 0)
    throw Error(path + ": needs the fields x y z scan index object");
  if (t.types[cs] != 'U' || t.types[ci] != 'U' || t.types[co] != 'I')
    throw Error(path + ": scan and index must be uint32 (U), object int32 (I)");
  std::map<int, bool> known;
  for (const auto& o : report.objects)
    if (o.mission == mt.name) known[o.id] = true;
  MissionRun run;
  run.predicted.resize(mt.labels.size());
  for (size_t s = 0; s < mt.labels.size(); ++s) run.predicted[s].assign(mt.labels[s].size(), 0);
  for (size_t r = 0; r < t.size; ++r) {
    const double sd = t.values[cs][r], id = t.values[ci][r];
    const int object = int(t.values[co][r]);
    const size_t s = size_t(sd), i = size_t(id);
    if (s >= mt.labels.size() || i >= mt.labels[s].size() || mt.labels[s][i] == kNoPoint)
      throw Error(path + ": row " + std::to_string(r) + ": scan " + std::to_string(s) + " index " + std::to_string(i) +
                  " is not a finite point of mission '" + mt.name + "'");
    if (object >= 0 && !known.count(object))
      throw Error(path + ": row " + std::to_string(r) + ": object " + std::to_string(object) +
                  " is not an object of mission '" + mt.name + "' in report.json");
    if (run.predicted[s][i]) continue;  // listed twice: counted once
    run.predicted[s][i] = 1;
    if (object >= 0) {
      ++run.labels_of[object][mt.labels[s][i]];
      ++run.size_of[object];
    }
  }
  return run;
}

Eigen::Isometry3d iso(const Eigen::Matrix4d& m) {
  Eigen::Isometry3d t;
  t.matrix() = m;
  return t;
}

}  // namespace

double PointScore::precision() const { return ratio(double(tp), double(tp + fp)); }
double PointScore::recall() const { return ratio(double(tp), double(tp + fn)); }
double PointScore::specificity() const { return ratio(double(tn), double(tn + fp)); }
double PointScore::f1() const { return ratio(2.0 * double(tp), double(2 * tp + fp + fn)); }
double PointScore::iou() const { return ratio(double(tp), double(tp + fp + fn)); }
double PointScore::recall_without_swaps() const {
  return ratio(double(tp - (swapped - fn_swapped)), double(tp + fn - swapped));
}
double ObjectScore::precision() const { return ratio(double(paired), double(reported)); }
double ObjectScore::recall() const { return ratio(double(paired), double(true_changed)); }
double ObjectScore::status_accuracy() const { return ratio(double(status_correct), double(paired)); }
double ObjectScore::match_accuracy() const { return ratio(double(moved_matched), double(moved)); }

double median(std::vector<double> v) {
  if (v.empty()) return kUndefined;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mean(const std::vector<double>& v) {
  return v.empty() ? kUndefined : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

namespace {

std::vector<ObjectVerdict> verdicts(const Truth& truth, const std::map<std::pair<size_t, uint32_t>, int>& report_of,
                                    const std::map<std::pair<size_t, uint32_t>, double>& pair_iou,
                                    const std::map<int, uint32_t>& truth_of,
                                    const std::map<int, const io::ReportObject*>& by_id) {
  std::vector<ObjectVerdict> out;
  const size_t nm = truth.labels.size();
  for (size_t k = 0; k < nm; ++k) {
    const std::string& m = truth.labels[k].name;
    for (const auto& [id, st] : truth.status) {
      auto it = st.find(m);
      auto pts = truth.labels[k].points_per_label.find(id);
      if (it == st.end() || pts == truth.labels[k].points_per_label.end()) continue;
      ObjectVerdict v;
      v.mission = m;
      v.truth_id = id;
      if (const io::TruthObject* o = truth.object(id)) v.class_name = o->class_name;
      v.truth_status = it->second;
      for (const std::string& a : truth.accepted.at(id).at(m))
        v.truth_statuses += (v.truth_statuses.empty() ? "" : "/") + a;
      v.truth_points = pts->second;
      if (const auto sw = truth.swapped.find(m); sw != truth.swapped.end()) v.swapped = sw->second.count(id) > 0;
      if (auto r = report_of.find({k, id}); r != report_of.end()) {
        v.report_id = r->second;
        v.iou = pair_iou.at({k, id});
        const io::ReportObject& rep = *by_id.at(r->second);
        v.report_status = rep.status;
        v.report_match = rep.match;
      }
      // The same object's report in another compared mission (the next one
      // first, as a report's match names), if paired.
      bool seen_elsewhere = false;
      std::vector<size_t> others;
      for (size_t j = k + 1; j < nm; ++j) others.push_back(j);
      for (size_t j = k; j-- > 0;) others.push_back(j);
      for (size_t j : others) {
        if (!st.count(truth.labels[j].name) || !truth.labels[j].points_per_label.count(id)) continue;
        seen_elsewhere = true;
        if (auto r = report_of.find({j, id}); r != report_of.end() && v.expected_match < 0) v.expected_match = r->second;
      }
      const auto t = truth_of.find(v.report_match);
      v.match_right = v.report_id >= 0 && t != truth_of.end() && t->second == id &&
                      by_id.at(v.report_match)->mission != m;
      const std::set<std::string>& accepted = truth.accepted.at(id).at(m);
      const bool status_right = accepted.count(v.report_status) > 0;
      // A move is scored by its match unless the report rightly gave the
      // object's other status (moved into C, then removed in D: 'removed').
      v.moved_elsewhere = accepted.count("moved") && seen_elsewhere && (v.report_status == "moved" || !status_right);
      if (v.report_id < 0) v.verdict = "missed";
      else if (!status_right) v.verdict = "status";
      else if (v.moved_elsewhere && v.expected_match < 0) v.verdict = "partner missed";
      else if (v.moved_elsewhere && !v.match_right) v.verdict = "match";
      else v.verdict = "ok";
      out.push_back(std::move(v));
    }
  }
  return out;
}

}  // namespace

namespace {

// The run's own scan poses (poses/<mission>.txt, written by io.report)
// against poses_gt.txt after one rigid fit over all missions (Umeyama, no
// scale): what ATE means in SLAM evaluation. Missing, or a count that does
// not match the mission's scans: left undefined (runs made before poses/
// existed, or by another writer).
void add_scan_pose_ate(const Truth& truth, const std::string& run_dir, std::vector<AlignmentScore>& alignment) {
  std::vector<Eigen::Vector3d> est, gt;
  std::vector<std::pair<std::string, size_t>> spans;  // mission, first index
  for (const Mission& m : truth.missions.missions) {
    if (m.poses_gt.empty()) continue;
    const std::string path = (std::filesystem::path(run_dir) / "poses" / (m.name + ".txt")).string();
    if (!std::filesystem::exists(path)) return;
    const std::vector<io::PoseRecord> run = io::read_poses(path);
    if (run.size() != m.poses_gt.size())
      throw Error(path + ": " + std::to_string(run.size()) + " poses for " + std::to_string(m.poses_gt.size()) +
                  " scans of mission '" + m.name + "'");
    spans.emplace_back(m.name, est.size());
    for (size_t i = 0; i < run.size(); ++i) {
      est.push_back(run[i].pose.translation());
      gt.push_back(m.poses_gt[i].translation());
    }
  }
  if (est.size() < 3) return;
  Eigen::Matrix3Xd src(3, est.size()), dst(3, gt.size());
  for (size_t i = 0; i < est.size(); ++i) src.col(long(i)) = est[i], dst.col(long(i)) = gt[i];
  const Eigen::Matrix4d fit = Eigen::umeyama(src, dst, false);
  const Eigen::Isometry3d f(fit);
  auto rmse = [&](size_t from, size_t to) {
    double sum = 0;
    for (size_t i = from; i < to; ++i) sum += (f * est[i] - gt[i]).squaredNorm();
    return std::sqrt(sum / double(std::max<size_t>(1, to - from)));
  };
  for (size_t k = 0; k < spans.size(); ++k) {
    const size_t to = k + 1 < spans.size() ? spans[k + 1].second : est.size();
    for (AlignmentScore& a : alignment)
      if (a.mission == spans[k].first) a.scan_ate_rmse_m = rmse(spans[k].second, to);
  }
  for (AlignmentScore& a : alignment)
    if (a.mission == "all") a.scan_ate_rmse_m = rmse(0, est.size());
}

// AUC of (score, right) pairs as ConfidenceScore defines it.
double auc_of(const std::vector<std::pair<double, bool>>& scored) {
  std::vector<double> right, wrong;
  for (const auto& [score, ok] : scored) (ok ? right : wrong).push_back(score);
  if (right.empty() || wrong.empty()) return kUndefined;
  std::sort(wrong.begin(), wrong.end());
  double sum = 0.0;  // per right report: wrong ones below it, ties half
  for (double r : right) {
    const auto lo = std::lower_bound(wrong.begin(), wrong.end(), r);
    const auto hi = std::upper_bound(lo, wrong.end(), r);
    sum += double(lo - wrong.begin()) + 0.5 * double(hi - lo);
  }
  return sum / (double(right.size()) * double(wrong.size()));
}

ConfidenceScore score_confidence(const io::Report& report, const std::vector<ObjectVerdict>& verdicts) {
  std::map<std::pair<std::string, int>, bool> right;  // (mission, report id) -> right
  for (const ObjectVerdict& v : verdicts)
    if (v.report_id >= 0)
      right[{v.mission, v.report_id}] = v.verdict == "ok" || v.verdict == "pose off" || v.verdict == "pose listed";
  ConfidenceScore c;
  std::vector<std::pair<double, bool>> all, moved, unpaired;
  for (const auto& o : report.objects) {
    const auto it = right.find({o.mission, o.id});
    const bool ok = it != right.end() && it->second;
    (ok ? c.right : c.wrong)++;
    all.push_back({o.confidence, ok});
    (o.status == "moved" ? moved : unpaired).push_back({o.confidence, ok});
  }
  c.auc = auc_of(all);
  c.auc_moved = auc_of(moved);
  c.auc_unpaired = auc_of(unpaired);
  return c;
}

}  // namespace

namespace {

// The run's reports paired with the true objects, per mission.
struct Pairing {
  std::map<std::pair<size_t, uint32_t>, int> report_of;  // (mission, true id) -> reported id
  std::map<int, uint32_t> truth_of;                      // reported id -> true id
  std::map<int, const io::ReportObject*> by_id;
  std::map<std::pair<size_t, uint32_t>, double> pair_iou;
};

// Per-point counts over all missions; dynamic objects' points left out.
void score_points(const Truth& truth, const std::vector<MissionRun>& runs, PointScore& points) {
  const size_t nm = truth.missions.missions.size();
  for (size_t k = 0; k < nm; ++k) {
    const MissionTruth& mt = truth.labels[k];
    const auto sw = truth.swapped.find(mt.name);
    for (size_t s = 0; s < mt.labels.size(); ++s)
      for (size_t i = 0; i < mt.labels[s].size(); ++i) {
        const uint32_t l = mt.labels[s][i];
        if (l == kNoPoint || truth.dynamic.count(l)) continue;
        const bool changed = l != 0 && truth.changed.count(l);
        const bool predicted = runs[k].predicted[s][i] != 0;
        if (changed) (predicted ? points.tp : points.fn)++;
        else (predicted ? points.fp : points.tn)++;
        if (changed && sw != truth.swapped.end() && sw->second.count(l)) {
          ++points.swapped;
          if (!predicted) ++points.fn_swapped;
        }
      }
  }

}

// Object pairing per mission: point-set IoU > 0.5, unique (greedy by IoU);
// one ObjectScore per mission into `objects`.
Pairing pair_objects(const Truth& truth, const io::Report& report, const std::vector<MissionRun>& runs,
                     std::vector<ObjectScore>& objects) {
  const size_t nm = truth.missions.missions.size();
  Pairing p;
  for (const auto& o : report.objects) p.by_id[o.id] = &o;
  for (size_t k = 0; k < nm; ++k) {
    const std::string& m = truth.labels[k].name;
    ObjectScore os;
    os.mission = m;
    for (const auto& o : report.objects) os.reported += o.mission == m;
    auto true_points = [&](uint32_t id) {
      auto it = truth.labels[k].points_per_label.find(id);
      return it == truth.labels[k].points_per_label.end() ? size_t(0) : it->second;
    };
    for (const auto& [id, st] : truth.status)
      if (st.count(m) && true_points(id) > 0) ++os.true_changed;
    struct Cand { double iou; int rep; uint32_t id; };
    std::vector<Cand> cands;
    for (const auto& [rep, labels] : runs[k].labels_of)
      for (const auto& [id, inter] : labels) {
        auto st = truth.status.find(id);
        if (id == 0 || st == truth.status.end() || !st->second.count(m)) continue;
        const double uni = double(runs[k].size_of.at(rep) + true_points(id) - inter);
        const double iou = double(inter) / uni;
        if (iou > 0.5) cands.push_back({iou, rep, id});
      }
    std::sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) {
      return a.iou != b.iou ? a.iou > b.iou : a.rep != b.rep ? a.rep < b.rep : a.id < b.id;
    });
    for (const Cand& c : cands) {
      if (p.truth_of.count(c.rep) || p.report_of.count({k, c.id})) continue;
      p.truth_of[c.rep] = c.id;
      p.report_of[{k, c.id}] = c.rep;
      p.pair_iou[{k, c.id}] = c.iou;
      ++os.paired;
      if (truth.accepted.at(c.id).at(m).count(p.by_id[c.rep]->status)) ++os.status_correct;
    }
    objects.push_back(os);
  }

  return p;
}

// Moved objects: does the match name the same true object's report
// elsewhere, and how far is its transform from the truth (in the run's
// common frame)? Fills score.verdicts and the objects' move counts.
void score_moves(const Truth& truth, const io::Report& report, const Pairing& p, Score& score) {
  auto world_to_common = [&](size_t k) {
    const std::string& m = truth.labels[k].name;
    return iso(report.alignment.at(m)) * iso(truth.gt.mission_to_world.at(m)).inverse();
  };
  score.verdicts = verdicts(truth, p.report_of, p.pair_iou, p.truth_of, p.by_id);
  for (ObjectVerdict& v : score.verdicts) {
    if (!v.moved_elsewhere) continue;
    const size_t k = truth.mission_index(v.mission);
    ObjectScore& os = score.objects[k];
    ++os.moved;
    if (!v.match_right) continue;
    ++os.moved_matched;
    const io::ReportObject& r = *p.by_id.at(v.report_id);
    if (!r.transform) continue;
    const io::ReportObject& partner = *p.by_id.at(r.match);
    const size_t j = truth.mission_index(partner.mission);
    const io::TruthObject* obj = truth.object(v.truth_id);
    const Eigen::Isometry3d truth_t = world_to_common(j) * iso(*obj->poses.at(partner.mission)) *
                                      iso(*obj->poses.at(v.mission)).inverse() * world_to_common(k).inverse();
    const Eigen::Isometry3d rep_t = iso(*r.transform);
    // Rotation error, and translation error at the object's centroid (so it
    // does not grow with the distance to the origin), of a reported pose.
    auto errors_of = [&](const Eigen::Isometry3d& t) {
      return std::pair{Eigen::AngleAxisd(t.rotation().transpose() * truth_t.rotation()).angle() * 180.0 / M_PI,
                       (t * r.centroid - truth_t * r.centroid).norm()};
    };
    auto off = [&](const Eigen::Isometry3d& t) {
      const auto [degrees, metres] = errors_of(t);
      return degrees > kPoseOffDegrees || metres > kPoseOffMeters;
    };
    std::tie(v.rotation_error_deg, v.translation_error_m) = errors_of(rep_t);
    v.alternatives = r.alternative_transforms.size();
    if (v.alternatives > 0) ++os.ambiguous;
    if (off(rep_t)) {
      ++os.pose_off;
      const bool listed = std::any_of(r.alternative_transforms.begin(), r.alternative_transforms.end(),
                                      [&](const Eigen::Matrix4d& a) { return !off(iso(a)); });
      if (listed) ++os.pose_off_listed;
      if (v.verdict == "ok") v.verdict = listed ? "pose listed" : "pose off";
    }
    os.translation_error_m.push_back(v.translation_error_m);
    os.rotation_error_deg.push_back(v.rotation_error_deg);
  }

}

// The missions' object scores summed.
ObjectScore all_missions(const std::vector<ObjectScore>& objects) {
  ObjectScore all;
  all.mission = "all";
  for (const auto& os : objects) {
    all.reported += os.reported;
    all.true_changed += os.true_changed;
    all.paired += os.paired;
    all.status_correct += os.status_correct;
    all.moved += os.moved;
    all.moved_matched += os.moved_matched;
    all.ambiguous += os.ambiguous;
    all.pose_off += os.pose_off;
    all.pose_off_listed += os.pose_off_listed;
    all.translation_error_m.insert(all.translation_error_m.end(), os.translation_error_m.begin(), os.translation_error_m.end());
    all.rotation_error_deg.insert(all.rotation_error_deg.end(), os.rotation_error_deg.begin(), os.rotation_error_deg.end());
  }
  return all;
}

// Alignment ATE: both trajectories in the first mission's map frame.
void score_alignment(const Truth& truth, const io::Report& report, std::vector<AlignmentScore>& alignment) {
  const size_t nm = truth.missions.missions.size();
  const std::string& first = truth.labels[0].name;
  const Eigen::Isometry3d est_to_first = iso(report.alignment.at(first)).inverse();
  const Eigen::Isometry3d world_to_first = iso(truth.gt.mission_to_world.at(first)).inverse();
  double sum_all = 0;
  size_t n_all = 0;
  for (size_t k = 0; k < nm; ++k) {
    const Mission& mission = truth.missions.missions[k];
    if (mission.poses_gt.empty()) continue;
    AlignmentScore a;
    a.mission = mission.name;
    double sum = 0;
    const Eigen::Isometry3d est = est_to_first * iso(report.alignment.at(mission.name));
    for (size_t i = 0; i < mission.scans.size(); ++i) {
      const Eigen::Vector3d e = (est * mission.scans[i].pose).translation();
      const Eigen::Vector3d g = (world_to_first * mission.poses_gt[i]).translation();
      sum += (e - g).squaredNorm();
    }
    a.scans = mission.scans.size();
    a.ate_rmse_m = std::sqrt(sum / double(std::max<size_t>(1, a.scans)));
    sum_all += sum;
    n_all += a.scans;
    alignment.push_back(a);
  }
  if (n_all > 0) alignment.push_back({"all", n_all, std::sqrt(sum_all / double(n_all))});
}

}  // namespace

Score score_run(const Truth& truth, const std::string& run_dir) {
  const std::string report_path = (std::filesystem::path(run_dir) / "report.json").string();
  if (!std::filesystem::exists(report_path)) throw Error(report_path + ": missing");
  const io::Report report = io::read_report(report_path);
  Score score;
  score.missions = report.missions;
  const size_t nm = truth.missions.missions.size();
  if (report.missions.size() != nm) throw Error(report_path + ": missions differ from the ones being scored");
  for (size_t k = 0; k < nm; ++k)
    if (report.missions[k] != truth.missions.missions[k].name)
      throw Error(report_path + ": mission " + std::to_string(k) + " is '" + report.missions[k] + "', expected '" +
                  truth.missions.missions[k].name + "'");

  std::vector<MissionRun> runs;
  for (size_t k = 0; k < nm; ++k) runs.push_back(read_changes(truth, k, run_dir, report));
  score_points(truth, runs, score.points);
  const Pairing pairing = pair_objects(truth, report, runs, score.objects);
  score_moves(truth, report, pairing, score);
  score.objects.push_back(all_missions(score.objects));
  score.confidence = score_confidence(report, score.verdicts);
  score_alignment(truth, report, score.alignment);
  add_scan_pose_ate(truth, run_dir, score.alignment);
  return score;
}

}  // namespace lista::eval
