// libFuzzer harness: one scan file (PCD ascii / binary / binary_compressed,
// PLY ascii / both binary byte orders, KITTI .bin) through io::read_scan, by
// the extension this binary was built for (LISTA_FUZZ_EXTENSION). A
// lista::Error is the expected answer to bad input; anything else (a crash,
// a sanitizer report, another exception) is a finding.
#include "fuzz_input.hpp"

#include <lista/error.hpp>
#include <lista_io/pcd.hpp>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = lista_fuzz::scratch_file(LISTA_FUZZ_EXTENSION, data, size);
  try {
    const lista::io::ScanFile scan = lista::io::read_scan(path);
    scan.points.check_consistent();
    if (scan.points.size() > scan.points_in_file) std::abort();  // more points than the file holds
  } catch (const lista::Error&) {
  }
  return 0;
}
