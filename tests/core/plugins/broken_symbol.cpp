// Links but cannot load with RTLD_NOW: it calls a function no library defines.
#include <lista/plugin.hpp>

extern "C" int lista_test_symbol_that_does_not_exist(int);

namespace {
void register_stages(lista::Registrar&) { (void)lista_test_symbol_that_does_not_exist(1); }
}  // namespace

LISTA_PLUGIN(register_stages)
