// complete_objects: the rules of completion.hpp, in order. Each rule is a
// step of CompletionPass (completion_pass.cpp, pair_completion.cpp); what
// they measure on the missions' points is in local_cloud.hpp and
// growth_checks.hpp, the rules that join objects in object_merges.hpp.
#include "completion.hpp"

#include "completion_pass.hpp"

#include <lista/error.hpp>

#include <cmath>

namespace lista::segment {

ObjectSet complete_objects(const ObjectSet& input, const MissionSet& missions, const CompletionConfig& c,
                           CompletionStats* stats) {
  using namespace completion;
  if (c.voxel <= 0) throw Error("segment.complete: voxel must be > 0");
  ObjectSet out = input;
  FloorsCameWith came_with;
  for (const auto& o : out.objects)
    if (!o.points.empty() && std::isfinite(o.floor_z))
      came_with[{o.mission, point_key(o.points.scan[0], o.points.index[0])}] = {o.points.size(), o.floor_z};
  for (auto& o : out.objects) o.update_geometry();
  std::vector<const Mission*> mission_of(out.missions.size(), nullptr);
  for (size_t m = 0; m < out.missions.size(); ++m) {
    mission_of[m] = missions.find(out.missions[m]);
    if (!mission_of[m])
      throw Error("segment.complete: objects name mission '" + out.missions[m] +
                  "', which the missions input does not hold; connect the missions the objects came from");
  }
  for (const auto& o : out.objects)
    if (o.mission >= out.missions.size())
      throw Error("segment.complete: object " + std::to_string(o.id) + " names mission index " +
                  std::to_string(o.mission) + " of " + std::to_string(out.missions.size()));

  CompletionPass pass(out, std::move(mission_of), c);
  pass.gather_clouds();
  pass.drop_floor_objects();  // 0
  pass.drop_thin_surfaces();  // 0b
  const std::vector<Pair> pairs = pass.candidate_pairs_to_try();  // 1
  pass.narrow_clouds(pairs);                                      // 2
  const std::vector<char> paired = pass.complete_pairs(pairs);    // 3-4
  pass.join_connected_objects(paired);                            // 4b
  pass.self_complete();                                           // 5
  pass.absorb_nested_objects();                                   // 6
  pass.set_floors(came_with);                                     // 7
  if (stats) *stats = pass.stats();
  return out;
}

}  // namespace lista::segment
