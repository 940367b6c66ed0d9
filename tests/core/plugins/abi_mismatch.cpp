// Compiled with LISTA_FINGERPRINT_OVERRIDE="bogus": the core must refuse it
// before calling register_stages.
#include <lista/plugin.hpp>

#include <cstdlib>

namespace {
void register_stages(lista::Registrar&) { std::abort(); }  // must never run
}  // namespace

LISTA_PLUGIN(register_stages)
