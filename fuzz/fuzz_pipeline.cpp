// libFuzzer harness: a pipeline TOML parsed, planned and validated against
// three in-process stages that declare every kind of parameter and port
// (the stages never run); every line is also tried as a --set override.
#include <lista/error.hpp>
#include <lista_core/plan.hpp>
#include <lista_core/registry.hpp>

#include <sstream>

namespace {

lista::core::Registry& registry() {
  static lista::core::Registry r = [] {
    using lista::ParamSpec;
    lista::core::Registry reg;
    auto none = [](const lista::Params&) -> std::unique_ptr<lista::Stage> { return nullptr; };
    lista::StageInfo source;
    source.name = "fuzz.source";
    source.version = "1.0.0";
    source.outputs = {{"missions", "missions", "missions"}};
    source.params = {ParamSpec::text("path", "", "a folder")};
    reg.add(source, none);
    lista::StageInfo filter;
    filter.name = "fuzz.filter";
    filter.version = "1.0.0";
    filter.inputs = {{"missions", "missions", "missions"}};
    filter.outputs = {{"missions", "missions", "missions"}};
    filter.params = {ParamSpec::real("radius", 0.5, "m").range(0.0, 10.0).unit("m"),
                     ParamSpec::integer("count", 3, "n").at_least(1),
                     ParamSpec::boolean("on", true, "switch"),
                     ParamSpec::text("mode", "a", "mode").one_of({"a", "b"}),
                     ParamSpec::real_list("weights", {1.0, 2.0}, "w"),
                     ParamSpec::text_list("names", {"x"}, "n")};
    reg.add(filter, none);
    lista::StageInfo sink;
    sink.name = "fuzz.sink";
    sink.version = "1.0.0";
    sink.inputs = {{"missions", "missions", "missions"}, {"points", "points", "points", true}};
    reg.add(sink, none);
    return reg;
  }();
  return r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<lista::core::Override> overrides;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    try {
      overrides.push_back(lista::core::parse_override(line));
    } catch (const lista::Error&) {
    }
  }
  try {
    lista::core::Diagnostics d;
    const auto spec = lista::core::parse_pipeline_text(text, "fuzz.toml", d);
    lista::core::build_plan(spec, overrides, registry(), d);
    for (const auto& e : d.errors) (void)e.str();
  } catch (const lista::Error&) {
  }
  return 0;
}
