// segment.carve: cuts out of a change cluster another mission's object that
// fits inside it (rule in carve_rule.hpp).
#include "carve_rule.hpp"

#include <lista/data.hpp>
#include <lista/error.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

#include <sstream>
#include <string>

namespace lista::segment {
namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

const ParamTable<CarveConfig>& param_table() {
  using C = CarveConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("voxel", &C::voxel, "search step (translation) and grid cell").range(0.01, 0.5).unit("m");
    t.bind("tolerance", &C::tolerance, "a template point fits within this of a host point (at most 4 x voxel)").range(0.01, 0.5).unit("m");
    t.bind("yaw_step", &C::yaw_step, "yaw search step").range(0.5, 90).unit("deg");
    t.bind("min_fit", &C::min_fit, "share of the template's points that must fit").range(0.1, 1);
    t.bind("min_share", &C::min_share, "least share of the host's points on each side of the cut").range(0.01, 0.5);
    t.bind("min_height_step", &C::min_height_step, "least difference between the tops of the two sides (and how much taller a host of a smaller footprint must be than its template)").range(0, 5).unit("m");
    t.bind("max_overlap", &C::max_overlap, "most of the smaller side's floor cells (2 x voxel) also under the other").range(0, 1);
    t.bind("min_width", &C::min_width, "narrowest template footprint (shorter side): a leg or a panel fits almost anywhere").range(0, 5).unit("m");
    t.bind("min_points", &C::min_points, "smallest template, and smallest separate part of the rest").range(1, 1e9);
  });
}

class CarveStage : public Stage {
 public:
  explicit CarveStage(const Params& p) : c_(param_table().read(p)) {
    // The search marks a ball of (tolerance / voxel)^3 cells per host point.
    if (c_.tolerance > 4.0 * c_.voxel)
      throw Error("tolerance " + fmt(c_.tolerance) + " m is over 4 x voxel (" + fmt(c_.voxel) +
                  " m); raise voxel or lower tolerance");
  }

  static StageInfo info() {
    StageInfo i;
    i.name = "segment.carve";
    i.version = "1.0.0";
    i.summary = "Cuts out of a cluster another mission's object that fits inside it (touching objects)";
    i.doc =
        "Cuts out of a change cluster another mission's object that fits inside it (two touching objects "
        "reported as one): the template is turned and slid over the cluster, and a cut is kept only when both "
        "sides are substantial and stand beside each other. "
        "Details: docs/segmentation.md, \"segment.carve\".";
    i.inputs = {{"objects", "objects", "per-mission clusters (after segment.complete)"}};
    i.outputs = {{"objects", "objects", "clusters with touching objects cut apart"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    CarveConfig c = c_;
    c.threads = context.threads();
    c.cancelled = [&context] { return context.cancelled(); };
    CarveStats st;
    ObjectSet objects = carve_objects(in.get<ObjectSet>("objects"), c, &st);
    context.throw_if_cancelled();
    context.record("candidates", double(st.candidates));
    context.record("fitted", double(st.fitted));
    context.record("carved", double(st.carved));
    context.record("parts", double(st.parts));
    context.record("objects", double(objects.objects.size()));
    if (st.carved)
      context.info(std::to_string(st.carved) + " clusters cut where another mission's object fits");
    for (const Carve& k : st.carves)
      context.debug("object " + std::to_string(k.host) + " cut where object " + std::to_string(k.tmpl) + " fits (" +
                    std::to_string(int(100 * k.fit + 0.5)) + " %): " + std::to_string(k.carved) + " + " +
                    std::to_string(k.rest) + " points");
    return Outputs::of("objects", std::move(objects));
  }

 private:
  CarveConfig c_;
};

}  // namespace
}  // namespace lista::segment

LISTA_STAGE_PLUGIN(lista::segment::CarveStage::info, lista::segment::CarveStage)
