// Assembles the self-contained report page (no network, no external files).
#pragma once

#include "report_model.hpp"
#include "topdown.hpp"

#include <lista/context.hpp>
#include <lista/descriptors.hpp>

#include <string>

namespace lista::report {

// In every page's head: lista-run removes an earlier report.html before a
// run only when it carries this mark, never a page of someone else's.
inline constexpr const char* kGeneratorMeta = "<meta name=\"generator\" content=\"LiSTA report.html\">";

struct PageOptions {
  std::string title = "LiSTA change report";
  TopdownOptions topdown;
};

std::string render_page(const MissionSet& missions, const ReportModel& model,
                        const DescriptorSet* descriptors, const RunInfo& run, const PageOptions& options);

}  // namespace lista::report
