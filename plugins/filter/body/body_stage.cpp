// filter.body: drops the robot's own body (or the person carrying the
// scanner) from every scan before alignment, found from the data: points
// that keep their place near the sensor while it moves, and that the same
// mission's other scans see through (body_detector.hpp).
#include "body_detector.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>

#include <cstdio>

namespace lista::filter {

namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

const ParamTable<BodyConfig>& param_table();

class BodyStage : public Stage {
 public:
  explicit BodyStage(const Params& p) : config_(param_table().read(p)) {
    if (config_.depth <= config_.cell)
      throw Error("depth (" + number(config_.depth) + " m) must exceed cell (" + number(config_.cell) +
                  " m): a ray passing within a cell of a point so near behind a floor would graze the floor itself");
    if (config_.witness_max < config_.witness_min)
      throw Error("witness_max (" + number(config_.witness_max) + " m) is below witness_min (" +
                  number(config_.witness_min) + " m)");
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    MissionSet set = in.get<MissionSet>("missions");  // shallow: scans' points stay shared
    size_t dropped = 0, cells = 0;
    std::vector<size_t> stations;  // missions too short for the witness test
    ctx.progress().begin("looking for the robot's body", set.missions.size());
    for (auto& m : set.missions) {
      ctx.throw_if_cancelled();
      const BodyCells found = find_body_cells(m, config_, ctx.threads());
      const size_t n = drop_body_points(m, found, config_, ctx.threads());
      dropped += n;
      cells += found.drop.size();
      ctx.record(m.name + ".dropped", double(n));
      if (config_.max_range <= 0) {
      } else if (!found.checked && found.scans < size_t(config_.min_scans)) {
        if (found.scans > 0) stations.push_back(size_t(&m - set.missions.data()));
      } else if (!found.checked) {
        ctx.info("mission '" + m.name + "': no scan has another one " + number(config_.witness_min) + "-" +
                 number(config_.witness_max) + " m away to look from; nothing taken for a body");
      } else if (n > 0) {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "mission '%s': %zu points in %zu cells near the sensor move with it and are seen through "
                      "from elsewhere (the robot's body): dropped",
                      m.name.c_str(), n, found.drop.size());
        ctx.info(buf);
      }
      ctx.progress().advance();
    }
    ctx.progress().end();
    const size_t on_platform = drop_platform(set, stations, ctx);
    dropped += on_platform;
    ctx.record("dropped", double(dropped));
    ctx.record("platform_dropped", double(on_platform));
    ctx.record("cells", double(cells));
    return Outputs::of("missions", std::move(set));
  }

 private:
  // Missions of a few stations each (stop-and-go): the platform is what all
  // their scans hold at one place in the sensor frame (find_station_body_cells).
  size_t drop_platform(MissionSet& set, const std::vector<size_t>& stations, Context& ctx) const {
    std::vector<const PointSet*> scans;
    for (const size_t m : stations)
      for (const Scan& s : set.missions[m].scans) scans.push_back(s.points.get());
    const BodyCells found = find_station_body_cells(scans, config_, ctx.threads());
    std::string names;
    for (const size_t m : stations) names += (names.empty() ? "'" : ", '") + set.missions[m].name + "'";
    if (!found.checked) {
      for (const size_t m : stations)
        ctx.info("mission '" + set.missions[m].name + "': " + std::to_string(set.missions[m].scans.size()) +
                 " scans, and no other short mission to compare stations with: nothing taken for a body");
      return 0;
    }
    size_t total = 0;
    for (const size_t m : stations) {
      const size_t n = drop_body_points(set.missions[m], found, config_, ctx.threads());
      ctx.record(set.missions[m].name + ".dropped", double(n));
      total += n;
    }
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "stations of missions %s: %zu points in %zu cells stand at the same place near the sensor in %zu "
                  "station scans (the platform carrying it): dropped",
                  names.c_str(), total, found.drop.size(), found.scans);
    ctx.info(buf);
    return total;
  }

  BodyConfig config_;
};

StageInfo info() {
  StageInfo s;
  s.name = "filter.body";
  s.version = "1.2.0";
  s.summary = "drops the robot's own body from the scans: points that move with the sensor and are seen through";
  s.doc =
      "Drops the robot's own body (or a handheld scanner's operator) from every scan: what stays put near the "
      "sensor and is seen through from the mission's other scans, and the platform under a stop-and-go "
      "scanner's stations. max_range 0 turns it off. "
      "Details: docs/formats.md, \"The robot's body\".";
  s.inputs = {{"missions", "missions", "missions as read"}};
  s.outputs = {{"missions", "missions", "the same missions without the body's points"}};
  s.params = param_table().specs();
  return s;
}

const ParamTable<BodyConfig>& param_table() {
  using C = BodyConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("max_range", &C::max_range, "body points lie nearer their sensor than this; 0 turns the stage off")
        .range(0, 10)
        .unit("m");
    t.bind("cell", &C::cell, "sensor-frame cell size").range(0.01, 1).unit("m");
    t.bind("min_share", &C::min_share, "a candidate cell is occupied in at least this share of the scans")
        .range(0.05, 1);
    t.bind("see_through_share", &C::see_through_share, "share of a candidate's votes that must see through it").range(0.05, 1);
    t.bind("depth", &C::depth, "how far behind a patch a witness ray must pass to see through it (under a "
           "robot's thinnest part; more than `cell`)")
        .range(0.02, 2)
        .unit("m");
    t.bind("margin", &C::margin, "how far beyond that point the ray must end").range(0.01, 5).unit("m");
    t.bind("witness_min", &C::witness_min, "a witness scan is at least this far from the scan it checks")
        .range(0.1, 100)
        .unit("m");
    t.bind("witness_max", &C::witness_max, "a witness scan is at most this far from the scan it checks")
        .range(0.1, 1000)
        .unit("m");
    t.bind("probes", &C::probes, "scans, spread over the mission, whose candidate cells are checked")
        .range(1, 10000);
  });
}

}  // namespace

}  // namespace lista::filter

LISTA_STAGE_PLUGIN(lista::filter::info, lista::filter::BodyStage)
