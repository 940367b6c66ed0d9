#include "mission_graph.hpp"

#include <cmath>

namespace lista::align {

Graph odometry_graph(const MissionSet& set, const std::vector<Eigen::Isometry3d>& to_common,
                     const JointAlignmentOptions& o) {
  const size_t n = set.missions.size();
  Graph g;
  for (size_t m = 0; m < n; ++m) {
    const Mission& mission = set.missions[m];
    g.offset.push_back(g.nodes.size());
    for (size_t s = 0; s < mission.scans.size(); ++s) {
      g.nodes.push_back(to_common[m] * mission.scans[s].pose);
      g.fixed.push_back(m == 0 && (o.fix_reference_mission || s == 0));
      if (s == 0) continue;
      PoseGraphEdge e;
      e.from = g.offset[m] + s - 1;
      e.to = g.offset[m] + s;
      e.measurement = mission.scans[s - 1].pose.inverse() * mission.scans[s].pose;
      e.sigma_translation = o.odometry_sigma_translation;
      e.sigma_rotation = o.odometry_sigma_rotation;
      g.within.push_back(e);
    }
  }
  return g;
}

Eigen::Isometry3d closure_measurement(const MissionSet& set, const std::vector<Keyframe>& kf, const Closure& c) {
  const Keyframe& r = kf[c.reference];
  const Keyframe& q = kf[c.query];
  const auto& pose_r = set.missions[r.mission].scans[r.scan].pose;
  const auto& pose_q = set.missions[q.mission].scans[q.scan].pose;
  return pose_r.inverse() * r.frame * c.reference_T_query * q.frame.inverse() * pose_q;
}

Eigen::Isometry3d frame_in_common(const MissionSet& set, const Graph& g, const Keyframe& k) {
  return g.nodes[node_of(g, k)] * set.missions[k.mission].scans[k.scan].pose.inverse() * k.frame;
}

std::vector<PoseGraphEdge> closure_edges(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                                         const std::vector<Closure>& closures, const JointAlignmentOptions& o) {
  std::vector<PoseGraphEdge> edges;
  for (const auto& c : closures) {
    PoseGraphEdge e;
    e.from = node_of(g, kf[c.reference]);
    e.to = node_of(g, kf[c.query]);
    e.measurement = closure_measurement(set, kf, c);
    e.sigma_translation = o.closure_sigma_translation;
    e.sigma_rotation = o.closure_sigma_rotation;
    e.robust = true;
    edges.push_back(e);
  }
  return edges;
}

PoseGraphSummary solve(Graph& g, const std::vector<PoseGraphEdge>& closures, PoseGraphOptions options) {
  std::vector<PoseGraphEdge> edges = g.within;
  edges.insert(edges.end(), closures.begin(), closures.end());
  return optimise_pose_graph(g.nodes, g.fixed, edges, options);
}

std::vector<Closure> agreeing(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                              const std::vector<Closure>& closures, const ConsistencyOptions& o) {
  std::vector<Closure> out;
  for (const auto& c : closures) {
    const Eigen::Isometry3d est = g.nodes[node_of(g, kf[c.reference])].inverse() * g.nodes[node_of(g, kf[c.query])];
    const Eigen::Isometry3d err = closure_measurement(set, kf, c).inverse() * est;
    if (err.translation().norm() <= o.distance / 4 &&
        rotation_angle(err.linear()) <= o.angle / 2)
      out.push_back(c);
  }
  return out;
}

double closure_rms(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                   const std::vector<Closure>& closures) {
  if (closures.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& c : closures) {
    const Eigen::Isometry3d est = g.nodes[node_of(g, kf[c.reference])].inverse() * g.nodes[node_of(g, kf[c.query])];
    sum += (closure_measurement(set, kf, c).inverse() * est).translation().squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(closures.size()));
}

MissionSet with_graph_poses(const MissionSet& set, const Graph& g) {
  MissionSet out = set;  // scans' point data is shared, not copied
  for (size_t m = 0; m < out.missions.size(); ++m) {
    Mission& mission = out.missions[m];
    const Eigen::Isometry3d tc =
        m == 0 ? Eigen::Isometry3d::Identity() : g.nodes[g.offset[m]] * set.missions[m].scans[0].pose.inverse();
    mission.to_common = tc;
    const Eigen::Isometry3d tc_inv = tc.inverse();
    for (size_t s = 0; s < mission.scans.size(); ++s) mission.scans[s].pose = tc_inv * g.nodes[g.offset[m] + s];
  }
  return out;
}

}  // namespace lista::align
