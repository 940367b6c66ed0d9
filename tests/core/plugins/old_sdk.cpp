// Built against SDK headers that declare a function this core's SDK lacks
// (as a plugin built against other headers, or with the old string ABI,
// whose std::string symbols differ): dlopen fails on a lista:: symbol
// before the fingerprint can be read.
#include <lista/plugin.hpp>

namespace lista {
int sdk_function_this_core_lacks(int);
}  // namespace lista

namespace {
void register_stages(lista::Registrar&) { (void)lista::sdk_function_this_core_lacks(1); }
}  // namespace

LISTA_PLUGIN(register_stages)
