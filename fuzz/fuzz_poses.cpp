// libFuzzer harness: poses.txt (TUM and KITTI layouts) through io::read_poses.
#include "fuzz_input.hpp"

#include <lista/error.hpp>
#include <lista_io/poses.hpp>

#include <cmath>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = lista_fuzz::scratch_file(".txt", data, size);
  try {
    for (const auto& record : lista::io::read_poses(path))
      if (!record.pose.matrix().allFinite()) std::abort();  // accepted poses are finite
  } catch (const lista::Error&) {
  }
  return 0;
}
