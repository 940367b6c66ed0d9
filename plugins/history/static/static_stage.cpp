// history.static: a changed object's history extended into the neighbouring
// missions where it stood still (see still_history.hpp).
#include "still_history.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>

#include <cctype>
#include <map>

namespace lista::history {

namespace {

const ParamTable<StillConfig>& param_table();

class StaticStage : public Stage {
 public:
  explicit StaticStage(const Params& p) : cfg_(param_table().read(p)) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& missions = in.get<MissionSet>("missions");
    const auto& objects = in.get<ObjectSet>("objects");
    const auto& matches = in.get<Matches>("matches");
    const Groups* groups = in.has("groups") ? &in.get<Groups>("groups") : nullptr;
    StillResult r = extend_histories(missions, objects, matches, groups, cfg_, ctx.threads());
    std::map<std::string, int> verdicts;
    for (const StillCandidate& c : r.candidates) {
      ++verdicts[c.verdict];
      ctx.debug("object " + std::to_string(c.source) + " in mission '" + objects.missions[c.mission] +
                "': " + c.verdict + " (shown again " + std::to_string(c.still_share) + ", where it changed " +
                std::to_string(c.gone_share) + ", reported there " + std::to_string(c.reported_share) + ")" +
                (c.copy >= 0 ? ", object " + std::to_string(c.copy) : ""));
    }
    if (r.copies > 0)
      ctx.info(std::to_string(r.copies) + " appearances added where a changed object stood still in another mission");
    for (int id : r.corrected) {
      const ObjectChange* c = r.matches.find(id);
      ctx.info("object " + std::to_string(id) + ": now " + to_string(c->status) +
               ", standing still on the side it was said to have changed against");
    }
    ctx.record("copies", double(r.copies));
    ctx.record("corrected", double(r.corrected.size()));
    ctx.record("looked_for", double(r.candidates.size()));
    for (const auto& [v, n] : verdicts) {
      std::string key;  // "still, added" -> "still_added"
      for (char ch : v)
        if (std::isalnum(static_cast<unsigned char>(ch))) key += ch;
        else if (!key.empty() && key.back() != '_') key += '_';
      ctx.record(key, double(n));
    }
    r.matches.method = matches.method + "+history.static";
    Outputs o;
    o.put("objects", std::move(r.objects));
    o.put("matches", std::move(r.matches));
    if (groups) o.put("groups", std::move(r.groups));
    else o.put("groups", Groups{});
    return o;
  }

 private:
  StillConfig cfg_;
};

StageInfo info() {
  StageInfo s;
  s.name = "history.static";
  s.version = "1.2.0";
  s.summary = "Follows each changed object into the neighbouring missions where it stood still";
  s.doc =
      "Follows each changed object into the neighbouring missions where it stood still and reports it there too "
      "(the data contract counts it changed in every mission), and corrects an added or removed status that the "
      "missions contradict. Adds nothing with two missions. "
      "Details: docs/history.md, \"What it does\".";
  s.inputs = {{"missions", "missions", "aligned missions, whose full clouds are searched"},
              {"objects", "objects", "changed objects of all missions"},
              {"matches", "matches", "status, partner, transform and history of every object"},
              {"groups", "groups", "descriptor groups; a copy joins its object's", true}};
  s.outputs = {{"objects", "objects", "the objects, then the copies (new ids)"},
               {"matches", "matches", "an entry for every object; histories include the copies"},
               {"groups", "groups", "the groups with the copies (empty when none came in)"}};
  s.params = param_table().specs();
  return s;
}

const ParamTable<StillConfig>& param_table() {
  using C = StillConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("radius", &C::radius, "a point of the other mission within this distance shows the same surface")
        .range(0.01, 1.0)
        .unit("m");
    t.bind("min_still_share", &C::min_still_share, "share of the object's points shown again to call it still there")
        .range(0.0, 1.0);
    t.bind("min_share_gap", &C::min_share_gap,
           "by how much that share must exceed the one in the mission the object changed against")
        .range(0.0, 1.0);
    t.bind("max_reported_share", &C::max_reported_share,
           "share of the object already covered by that mission's own objects at which the search stops")
        .range(0.0, 1.0);
    t.bind("follow_contradictions", &C::follow_contradictions,
           "also follow an added or removed object that stands still in the mission it was said to have changed against, and correct its status");
  });
}

}  // namespace

}  // namespace lista::history

LISTA_STAGE_PLUGIN(lista::history::info, lista::history::StaticStage)
