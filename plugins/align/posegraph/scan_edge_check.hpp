// The scan-to-scan edges of the joint pose graph, and the check that they
// agree with the loop closures (JointAlignmentOptions::scan_disagreement).
// Internal to align.posegraph; the rules it applies are declared in
// joint_alignment.hpp, where the tests reach them.
#pragma once

#include "mission_graph.hpp"
#include "stopwatch.hpp"

#include <vector>

namespace lista::align {

// Each mission's scans registered onto their neighbours (or local maps),
// with progress lines and a warning per mission where few register; fills
// the report's scan-edge counts.
std::vector<PoseGraphEdge> scan_edges_with_notes(const MissionSet& set, const std::vector<size_t>& offsets,
                                                 const JointAlignmentOptions& o, Context& ctx,
                                                 JointAlignmentReport& report, ScanEdgeReport& scan_report,
                                                 const Stopwatch& clock);

// Scan-to-scan edges are tight (millimetres) and outnumber the closures:
// were they biased (a sparse scanner's rings register ring onto ring, not
// surface onto surface), the graph would bend the verified closures to fit
// them. Solved again without them (from `odometry_only`), on the same
// closures: if they raise the closures' residual several-fold, they are
// left out: with three or more missions only those of a mission whose
// removal alone brings the residual down as far (one sparsely scanned
// mission among dense ones leaves the others their edges), else all. The
// missions left out try local maps instead. `g` (solved with every scan
// edge) takes the graph kept; the report records residuals and cost.
void vet_scan_edges(const MissionSet& set, const std::vector<Keyframe>& kf, const std::vector<Closure>& closures,
                    const std::vector<PoseGraphEdge>& scan_edges, const ScanEdgeReport& scan_report,
                    const Graph& odometry_only, const JointAlignmentOptions& o, Context& ctx,
                    JointAlignmentReport& report, Graph& g);

}  // namespace lista::align
