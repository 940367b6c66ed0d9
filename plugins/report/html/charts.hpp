// The report's charts as inline SVG: the match matrix of a mission pair with
// confidence as a heat map (paper Fig. 7) and the descriptors reduced to 2-D
// by PCA, coloured by group (paper Fig. 6).
#pragma once

#include "report_model.hpp"

#include <lista/descriptors.hpp>

#include <string>

namespace lista::report {

// Rows: objects of mission a; columns: objects of mission b. A cell shows the
// similarity of the two objects (1 - min-max normalised descriptor distance,
// or physical distance without descriptors); matched pairs are outlined and
// carry their confidence.
std::string render_match_matrix(const ReportModel& model, const DescriptorSet* descriptors, size_t a,
                                size_t b);

// Empty string if there are fewer than two descriptors.
std::string render_pca(const ReportModel& model, const DescriptorSet& descriptors);

}  // namespace lista::report
