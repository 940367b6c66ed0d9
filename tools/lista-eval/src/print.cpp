#include "print.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lista::eval {

namespace {

std::string num(double v, const char* fmt = "%.4f") {
  if (std::isnan(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}

nlohmann::ordered_json jnum(double v) { return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v); }

}  // namespace

std::string format_table(const Score& s, bool objects) {
  std::string out;
  char line[256];
  const PointScore& p = s.points;
  out += "per point (all missions, dynamic objects excluded)\n";
  std::snprintf(line, sizeof line, "  TP %llu  FP %llu  TN %llu  FN %llu\n", (unsigned long long)p.tp,
                (unsigned long long)p.fp, (unsigned long long)p.tn, (unsigned long long)p.fn);
  out += line;
  out += "  precision " + num(p.precision()) + "  recall " + num(p.recall()) + "  specificity " +
         num(p.specificity()) + "  F1 " + num(p.f1()) + "  IoU " + num(p.iou()) + "\n";
  if (p.swapped > 0) {
    std::snprintf(line, sizeof line,
                  "  swaps: %llu FN points lie on objects that exchanged places with one of their class "
                  "(unseen if identical); recall without them %s\n",
                  (unsigned long long)p.fn_swapped, num(p.recall_without_swaps()).c_str());
    out += line;
  }
  out += "per object (pairs: point-set IoU > 0.5)\n";
  std::snprintf(line, sizeof line, "  %-12s %8s %6s %6s %9s %7s %7s %8s %8s %10s %10s\n", "mission", "reported",
                "true", "pairs", "precision", "recall", "status", "match", "moved", "t_err_m", "r_err_deg");
  out += line;
  for (const auto& o : s.objects) {
    std::snprintf(line, sizeof line, "  %-12s %8zu %6zu %6zu %9s %7s %7s %8s %8zu %10s %10s\n", o.mission.c_str(),
                  o.reported, o.true_changed, o.paired, num(o.precision()).c_str(), num(o.recall()).c_str(),
                  num(o.status_accuracy()).c_str(), num(o.match_accuracy()).c_str(), o.moved,
                  num(median(o.translation_error_m)).c_str(), num(median(o.rotation_error_deg), "%.2f").c_str());
    out += line;
  }
  out += "  (t_err_m, r_err_deg: medians over correctly matched moved objects)\n";
  if (!s.objects.empty()) {
    const ObjectScore& all = s.objects.back();  // "all"
    std::snprintf(line, sizeof line,
                  "  transforms: %zu of %zu flagged ambiguous (alternative_transforms); %zu pose off (> %.0f deg or "
                  "%.2f m), %zu of them with the truth among the alternatives\n",
                  all.ambiguous, all.translation_error_m.size(), all.pose_off, kPoseOffDegrees, kPoseOffMeters,
                  all.pose_off_listed);
    out += line;
  }
  {
    const ConfidenceScore& c = s.confidence;
    out += "  confidence: AUC " + num(c.auc, "%.3f") + " (moved " + num(c.auc_moved, "%.3f") +
           ", removed/added " + num(c.auc_unpaired, "%.3f") + "; " + std::to_string(c.right) + " reports right, " +
           std::to_string(c.wrong) + " wrong)\n";
  }
  if (objects) {
    out += "per truly changed object (report -1: none paired; match: the report's / the right one)\n";
    std::snprintf(line, sizeof line, "  %-12s %6s %-16s %-14s %7s %6s %5s %-8s %13s %8s %9s  %s\n", "mission",
                  "truth", "class", "status", "points", "report", "iou", "reported", "match", "t_err_m", "r_err_deg",
                  "verdict");
    out += line;
    for (const auto& v : s.verdicts) {
      const std::string match = v.moved_elsewhere || v.truth_status == "moved"
          ? std::to_string(v.report_match) + " / " + std::to_string(v.expected_match) : "-";
      std::snprintf(line, sizeof line, "  %-12s %6u %-16.16s %-14s %7zu %6d %5s %-8s %13s %8s %9s  %s\n",
                    v.mission.c_str(), v.truth_id, v.class_name.c_str(), v.truth_statuses.c_str(), v.truth_points,
                    v.report_id, v.report_id >= 0 ? num(v.iou, "%.2f").c_str() : "-",
                    v.report_id >= 0 ? v.report_status.c_str() : "-", match.c_str(),
                    std::isnan(v.translation_error_m) ? "-" : num(v.translation_error_m, "%.3f").c_str(),
                    std::isnan(v.rotation_error_deg) ? "-" : num(v.rotation_error_deg, "%.1f").c_str(),
                    (v.verdict + (v.swapped ? " (swap)" : "")).c_str());
      out += line;
    }
  }
  if (!s.alignment.empty()) {
    const bool scan_poses = std::any_of(s.alignment.begin(), s.alignment.end(),
                                        [](const AlignmentScore& a) { return !std::isnan(a.scan_ate_rmse_m); });
    out += "alignment (ATE RMSE of sensor positions, first mission's frame";
    out += scan_poses ? "; then of the run's scan poses, poses/, after one rigid fit)\n" : ")\n";
    for (const auto& a : s.alignment) {
      std::snprintf(line, sizeof line, "  %-12s %6zu scans  %s m", a.mission.c_str(), a.scans,
                    num(a.ate_rmse_m).c_str());
      out += line;
      if (scan_poses) out += "  " + num(a.scan_ate_rmse_m) + " m";
      out += "\n";
    }
  }
  return out;
}

std::string format_json(const Score& s) {
  using json = nlohmann::ordered_json;
  json j;
  j["missions"] = s.missions;
  const PointScore& p = s.points;
  j["points"] = {{"tp", p.tp}, {"fp", p.fp}, {"tn", p.tn}, {"fn", p.fn}, {"precision", jnum(p.precision())},
                 {"recall", jnum(p.recall())}, {"specificity", jnum(p.specificity())}, {"f1", jnum(p.f1())},
                 {"iou", jnum(p.iou())}, {"swapped", p.swapped}, {"fn_swapped", p.fn_swapped},
                 {"recall_without_swaps", jnum(p.recall_without_swaps())}};
  json objects = json::array();
  for (const auto& o : s.objects)
    objects.push_back({{"mission", o.mission},
                       {"reported", o.reported},
                       {"true_changed", o.true_changed},
                       {"paired", o.paired},
                       {"precision", jnum(o.precision())},
                       {"recall", jnum(o.recall())},
                       {"status_accuracy", jnum(o.status_accuracy())},
                       {"moved", o.moved},
                       {"moved_matched", o.moved_matched},
                       {"match_accuracy", jnum(o.match_accuracy())},
                       {"translation_error_m", {{"median", jnum(median(o.translation_error_m))},
                                                {"mean", jnum(mean(o.translation_error_m))}}},
                       {"rotation_error_deg", {{"median", jnum(median(o.rotation_error_deg))},
                                               {"mean", jnum(mean(o.rotation_error_deg))}}},
                       {"transforms_ambiguous", o.ambiguous},
                       {"pose_off", o.pose_off},
                       {"pose_off_listed", o.pose_off_listed}});
  j["objects"] = objects;
  j["confidence"] = {{"right", s.confidence.right},
                     {"wrong", s.confidence.wrong},
                     {"auc", jnum(s.confidence.auc)},
                     {"auc_moved", jnum(s.confidence.auc_moved)},
                     {"auc_removed_added", jnum(s.confidence.auc_unpaired)}};
  json verdicts = json::array();
  for (const auto& v : s.verdicts)
    verdicts.push_back({{"mission", v.mission},
                        {"truth_id", v.truth_id},
                        {"class", v.class_name},
                        {"truth_status", v.truth_status},
                        {"truth_statuses", v.truth_statuses},
                        {"truth_points", v.truth_points},
                        {"report_id", v.report_id},
                        {"iou", v.iou},
                        {"report_status", v.report_status},
                        {"report_match", v.report_match},
                        {"expected_match", v.expected_match},
                        {"translation_error_m", jnum(v.translation_error_m)},
                        {"rotation_error_deg", jnum(v.rotation_error_deg)},
                        {"alternatives", v.alternatives},
                        {"swapped", v.swapped},
                        {"verdict", v.verdict}});
  j["object_verdicts"] = verdicts;
  json align = json::array();
  for (const auto& a : s.alignment)
    align.push_back({{"mission", a.mission}, {"scans", a.scans}, {"ate_rmse_m", jnum(a.ate_rmse_m)},
                     {"scan_ate_rmse_m", jnum(a.scan_ate_rmse_m)}});
  j["alignment"] = align;
  return j.dump(2) + "\n";
}

}  // namespace lista::eval
