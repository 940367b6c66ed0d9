// Checks on the folders a program reads and writes, shared by the tools.
#pragma once

#include <filesystem>
#include <iterator>
#include <string>

namespace lista::cli {

// An output folder at or inside the dataset adds files to it (changes/ and
// poses/ of a run, whole missions of a perfect run) that the next read takes
// for missions. Returns the one-line error, empty when `out` lies elsewhere.
// `option` names the flag the user gave `out` with (e.g. "--out").
inline std::string output_inside_dataset(const std::string& dataset, const std::string& out,
                                         const std::string& option) {
  if (dataset.empty() || out.empty()) return {};
  std::error_code ec;
  const std::filesystem::path d = std::filesystem::weakly_canonical(dataset, ec);
  if (ec) return {};
  const std::filesystem::path o = std::filesystem::weakly_canonical(out, ec);
  if (ec) return {};
  auto di = d.begin(), oi = o.begin();
  while (di != d.end() && oi != o.end() && *di == *oi) ++di, ++oi;
  const bool inside = di == d.end() || (std::next(di) == d.end() && di->empty());  // a trailing "/"
  if (!inside) return {};
  return option + " " + out + " lies inside the dataset " + dataset +
         ": what is written there would be read as missions next time; choose a folder outside it";
}

}  // namespace lista::cli
