#include "presets.hpp"

#include "shapes.hpp"

#include <lista/error.hpp>

namespace lista::sim {

const std::vector<std::string>& preset_names() {
  static const std::vector<std::string> n = {"tiny", "demo", "exp1", "exp2", "exp3", "hall", "fsc"};
  return n;
}

Preset make_preset(const std::string& name) {
  Preset p;
  p.name = name;
  p.changes.classes = indoor_classes();
  auto& c = p.changes;
  auto& r = p.route;
  if (name == "tiny") {
    p.description = "one small room, a handful of objects, 2 missions of 10 scans (unit tests)";
    p.layout = {"office", 10.0, 8.0, 2.6};
    p.sensor = "xt32";
    p.columns = 500;
    r.scans = 10;
    c.objects = 7;
    c.duplicates = 2;
    c.moves = 2;
    c.short_moves = 1;
    c.swaps = 1;
    c.removals = 1;
    c.additions = 1;
    c.people = 1;
  } else if (name == "demo") {
    p.description = "small office, a few changes of each kind, ~250k points per mission";
    p.layout = {"office", 14.0, 10.0, 2.8};
    p.sensor = "xt32";
    p.columns = 1000;
    r.scans = 8;
    c.objects = 18;
    c.moves = 3;
    c.short_moves = 1;
    c.swaps = 1;
    c.removals = 2;
    c.additions = 2;
    c.people = 1;
  } else if (name == "exp1" || name == "exp2" || name == "exp3") {
    p.layout = {"office", 26.0, 18.0, 3.0};
    p.sensor = "os0-128";
    r.scans = 64;  // ~8.25 M points per mission with the OS0-128
    c.people = 2;
    if (name == "exp1") {
      p.description = "OS0-128 office after the paper's Exp. 1: many changes";
      c.objects = 50;
      c.moves = 8;
      c.short_moves = 3;
      c.swaps = 1;
      c.removals = 5;
      c.additions = 5;
    } else if (name == "exp2") {
      p.description = "OS0-128 office after Exp. 2: fewer changes, none near another";
      c.objects = 40;
      c.moves = 4;
      c.short_moves = 1;
      c.swaps = 1;
      c.removals = 2;
      c.additions = 2;
      c.spacing = ChangeSpacing::separate;
    } else {
      p.description = "OS0-128 office after Exp. 3: many changes on top of each other";
      c.objects = 50;
      c.moves = 8;
      c.short_moves = 4;
      c.swaps = 2;
      c.removals = 5;
      c.additions = 5;
      c.spacing = ChangeSpacing::overlap;
    }
  } else if (name == "hall") {
    p.description = "industrial hall with racking and pillars, XT32";
    p.layout = {"hall", 36.0, 22.0, 7.0};
    p.sensor = "xt32";
    r.scans = 50;
    c.classes = {"crate", "barrel", "pallet", "cart", "box", "cabinet", "shelf"};
    c.objects = 35;
    c.moves = 5;
    c.short_moves = 2;
    c.swaps = 1;
    c.removals = 3;
    c.additions = 3;
    c.people = 2;
  } else if (name == "fsc") {
    p.description = "outdoor training yard, ~250 m route, cars, crates, containers, XT32";
    p.layout = {"yard", 91.0, 66.0, 10.0};  // loop inset 8 m: 2 * (75 + 50) = 250 m
    p.sensor = "xt32";
    r.scans = 125;
    r.deviation = 0.15;
    c.classes = outdoor_classes();
    c.objects = 40;
    c.moves = 5;
    c.short_moves = 2;
    c.swaps = 1;
    c.removals = 3;
    c.additions = 3;
    c.people = 3;
  } else {
    std::string known;
    for (const auto& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("lista-sim: unknown preset '" + name + "' (known: " + known + ")");
  }
  return p;
}

}  // namespace lista::sim
