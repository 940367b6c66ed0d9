// Writing a built report into an output folder atomically: everything goes to
// a temp folder inside it first, then is renamed into place, report.json last,
// so an interrupted or failed run never leaves a report.json that looks complete.
#pragma once

#include "report_build.hpp"

namespace lista::io {

void write_output(const std::string& out_dir, const Built& built);

}  // namespace lista::io
