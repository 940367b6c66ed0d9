// What lista-run prints about plugins and pipelines, from the same
// declarations that validation uses.
#pragma once

#include <lista_core/diagnostic.hpp>
#include <lista_core/registry.hpp>

#include <string>

namespace lista_run {

std::string list_plugins(const lista::core::Registry& registry);
std::string describe_text(const lista::core::RegisteredStage& stage);
std::string describe_json(const lista::core::RegisteredStage& stage);
// {"valid":bool,"errors":[{"file","line","column","stage","message"}],"warnings":[...]}
std::string verdict_json(const lista::core::Diagnostics& diagnostics);

}  // namespace lista_run
