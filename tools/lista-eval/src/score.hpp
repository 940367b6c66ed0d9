// Scoring a run (report.json + changes/<mission>.pcd) against the truth, as
// defined in the data contract, sect. 3 (details in docs/datasets.md).
#pragma once

#include "truth.hpp"

#include <limits>
#include <string>
#include <vector>

namespace lista::eval {

constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();

struct PointScore {
  uint64_t tp = 0, fp = 0, tn = 0, fn = 0;
  // Of the truly changed points: those on swapped objects (Truth::swapped),
  // and of the missed ones, those.
  uint64_t swapped = 0, fn_swapped = 0;
  // Recall over the truly changed points that are not on swapped objects.
  double recall_without_swaps() const;
  double precision() const;
  double recall() const;
  double specificity() const;
  double f1() const;
  double iou() const;
};

struct ObjectScore {
  std::string mission;  // "all" for the totals
  size_t reported = 0;      // reported objects in the mission
  size_t true_changed = 0;  // truly changed objects with points in the mission
  size_t paired = 0;        // pairs with point-set IoU > 0.5
  size_t status_correct = 0;
  size_t moved = 0;          // truly moved objects also seen in another compared mission
  size_t moved_matched = 0;  // ... whose match names the report of the same object there
  std::vector<double> translation_error_m, rotation_error_deg;  // of the matched moved ones
  // Of the matched moves with a transform: how many list alternative_transforms
  // (the report says the pose is ambiguous), how many are "pose off", and how
  // many of those list the true pose among their alternatives.
  size_t ambiguous = 0, pose_off = 0, pose_off_listed = 0;
  double precision() const;
  double recall() const;
  double status_accuracy() const;
  double match_accuracy() const;
};

// A correctly matched move whose transform is further than this from the
// truth gets the verdict "pose off" (three times the contract's 5 degrees / 5 cm
// that make a move).
constexpr double kPoseOffDegrees = 15.0;
constexpr double kPoseOffMeters = 0.15;

// What became of one truly changed object in one mission: which report it
// was paired with and whether status and match are right. For finding out
// why a run scores as it does (lista-eval --objects).
struct ObjectVerdict {
  std::string mission;
  uint32_t truth_id = 0;
  std::string class_name;
  std::string truth_status;  // moved / removed / added
  // Every status the truth accepts here (Truth::accepted), e.g.
  // "moved/removed" for an object moved into this mission and gone in the next.
  std::string truth_statuses;
  size_t truth_points = 0;   // the object's points in this mission
  int report_id = -1;        // -1: no report paired (IoU <= 0.5)
  double iou = 0.0;          // of the pair; 0 if none
  std::string report_status;
  int expected_match = -1;  // moved: the report paired with the object in the other mission (-1: none)
  int report_match = -1;
  bool moved_elsewhere = false;  // truly moved and seen in another compared mission: counts in match accuracy
  bool match_right = false;      // the report's match is the same object's report in another mission
  // Of a correctly matched move with a transform: its errors, else NaN.
  double translation_error_m = kUndefined, rotation_error_deg = kUndefined;
  size_t alternatives = 0;  // the report's alternative_transforms
  bool swapped = false;     // exchanged places with another object of its class (Truth::swapped)
  // "ok", "missed" (no report paired), "status" (wrong status), "match"
  // (moved, its match names another report), "partner missed" (moved, the
  // other view was not paired with any report), "pose off" (matched right,
  // but its transform is more than kPoseOffDegrees or kPoseOffMeters from
  // the truth: a symmetric object registered half-turned, say), "pose
  // listed" (pose off, but one of the report's alternative_transforms is
  // within those limits: the report said it could not tell).
  std::string verdict;
};

struct AlignmentScore {
  std::string mission;
  size_t scans = 0;
  // Sensor positions as alignment[m] * poses.txt places them, in the first
  // mission's frame (no fit: the first mission's own drift is its floor).
  double ate_rmse_m = kUndefined;
  // Sensor positions as the run placed every scan (poses/<mission>.txt, the
  // aligner's per-scan corrections included) after ONE rigid fit of all
  // missions' positions onto the true ones; NaN when the run has no poses/.
  double scan_ate_rmse_m = kUndefined;
};

// How well the reports' confidence sorts right reports above wrong ones.
// A report is right when it is paired with a truly changed object and its
// verdict is ok, pose off or pose listed (status accepted and, for a move,
// the right partner); an unpaired report is wrong. AUC = the chance that a
// right report's confidence is above a wrong one's (ties count half): 1 =
// sorted perfectly, 0.5 = no better than chance, NaN without both kinds.
struct ConfidenceScore {
  size_t right = 0, wrong = 0;
  double auc = kUndefined;           // all reports
  double auc_moved = kUndefined;     // reports with status moved
  double auc_unpaired = kUndefined;  // removed and added reports
};

struct Score {
  std::vector<std::string> missions;
  PointScore points;
  std::vector<ObjectScore> objects;  // per mission, then the totals ("all")
  std::vector<AlignmentScore> alignment;  // missions with poses_gt.txt, then "all"
  std::vector<ObjectVerdict> verdicts;    // per mission, by true id
  ConfidenceScore confidence;
};

// Reads <run>/report.json and <run>/changes/<mission>.pcd; throws lista::Error
// (naming the file) when they break the contract.
Score score_run(const Truth& truth, const std::string& run_dir);

double median(std::vector<double> v);
double mean(const std::vector<double>& v);

}  // namespace lista::eval
