// Registers a name the good test library also registers.
#include <lista/plugin.hpp>

namespace {
class Nothing : public lista::Stage {
 public:
  lista::Outputs run(const lista::Inputs&, lista::Context&) override { return {}; }
};
void register_stages(lista::Registrar& r) {
  lista::StageInfo i;
  i.name = "test.source";
  i.version = "9.9.9";
  i.summary = "impostor";
  r.add(i, [](const lista::Params&) { return std::make_unique<Nothing>(); });
}
}  // namespace

LISTA_PLUGIN(register_stages)
