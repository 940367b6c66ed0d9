// A shared library that is not a LiSTA plugin (no LISTA_PLUGIN entry point).
extern "C" int lista_test_not_a_plugin() { return 42; }
