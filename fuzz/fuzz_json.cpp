// libFuzzer harness: report.json or ground_truth.json (LISTA_FUZZ_JSON) as
// lista-eval reads them.
#include "fuzz_input.hpp"

#include <lista/error.hpp>
#include <lista_io/report.hpp>

#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = lista_fuzz::scratch_file(".json", data, size);
  try {
    if (std::string_view(LISTA_FUZZ_JSON) == "report") lista::io::read_report(path);
    else lista::io::read_ground_truth(path);
  } catch (const lista::Error&) {
  }
  return 0;
}
