// Small stages on SDK types for the core's tests: sources, pass-throughs,
// sinks and stages that misbehave on purpose. Never installed.
#include <filesystem>
#include <chrono>
#include <csignal>
#include <limits>
#include <lista/plugin.hpp>
#include <random>
#include <thread>

namespace {

using namespace lista;

// A test stage's declaration: version 1.0.0, the given ports and parameters.
StageInfo declare(std::string name, std::string summary, std::vector<PortSpec> inputs, std::vector<PortSpec> outputs,
                  std::vector<ParamSpec> params = {}, std::vector<ParamRename> renamed = {}) {
  StageInfo i;
  i.name = std::move(name);
  i.version = "1.0.0";
  i.summary = std::move(summary);
  i.inputs = std::move(inputs);
  i.outputs = std::move(outputs);
  i.params = std::move(params);
  i.renamed = std::move(renamed);
  return i;
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

MissionSet make_missions(int missions, int points, uint64_t seed) {
  MissionSet set;
  set.dataset = "synthetic";
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int m = 0; m < missions; ++m) {
    Mission mission;
    mission.name = "m" + std::to_string(m);
    auto cloud = std::make_shared<PointSet>();
    for (int i = 0; i < points; ++i) {
      cloud->xyz.emplace_back(u(rng), u(rng), u(rng));
      cloud->scan.push_back(0);
      cloud->index.push_back(uint32_t(i));
    }
    Scan scan;
    scan.points = cloud;
    scan.points_in_file = uint32_t(points);
    mission.scans.push_back(scan);
    set.missions.push_back(std::move(mission));
  }
  return set;
}

class Source : public Stage {
 public:
  explicit Source(const Params& p) : p_(p) {}
  static StageInfo info() {
    return declare("test.source", "synthetic missions of random points", {}, {{"missions", "missions", "the missions"}},
                   {ParamSpec::integer("count", 100, "points per mission").at_least(0),
                    ParamSpec::integer("missions", 2, "how many missions").range(1, 100),
                    ParamSpec::real("scale", 1.0, "edge length").range(0.001, 1000).unit("m"),
                    ParamSpec::text("mode", "fast", "how to work").one_of({"fast", "exact"}),
                    ParamSpec::boolean("verbose", false, "log more"),
                    ParamSpec::real_list("weights", {1.0, 2.0}, "weights").at_least(0),
                    ParamSpec::text_list("tags", {}, "free tags"),
                    ParamSpec::boolean("noise.enabled", false, "a parameter group: add noise"),
                    ParamSpec::real("noise.sigma", 0.0, "its spread").at_least(0).unit("m")},
                   renames());
  }
  // Names of before the noise group: `sigma` as is, `noise_level` 0 meant off.
  static std::vector<ParamRename> renames() {
    ParamRename level{"noise_level", "noise.sigma", [](const ParamValue& v) {
                        if (v.index() != 1 && v.index() != 2) throw Error("parameter 'noise_level' must be float");
                        const double x = v.index() == 1 ? double(std::get<int64_t>(v)) : std::get<double>(v);
                        return x == 0.0 ? ParamAssignments{{"noise.enabled", false}}
                                        : ParamAssignments{{"noise.enabled", true}, {"noise.sigma", x}};
                      }};
    return {{"sigma", "noise.sigma", {}}, level};
  }
  Outputs run(const Inputs&, Context& ctx) override {
    ctx.record("start_ms", now_ms());
    ctx.progress().begin("making points", 4);
    for (int i = 0; i < 4; ++i) ctx.progress().advance();
    ctx.progress().end();
    Outputs out;
    out.put("missions", make_missions(p_.get<int>("missions"), p_.get<int>("count"), ctx.seed()));
    ctx.record("end_ms", now_ms());
    return out;
  }

 private:
  Params p_;
};

// Copies missions; sleeps to make overlap measurable; can fail on request.
class Passthrough : public Stage {
 public:
  explicit Passthrough(const Params& p) : p_(p) {}
  static StageInfo info() {
    return declare("test.passthrough", "missions in, the same missions out", {{"missions", "missions", "any missions"}},
                   {{"missions", "missions", "the same missions"}},
                   {ParamSpec::integer("sleep_ms", 0, "time to spend").range(0, 60000),
                    ParamSpec::boolean("fail", false, "throw a lista::Error"),
                    ParamSpec::boolean("fail_std", false, "throw a std::runtime_error")});
  }
  Outputs run(const Inputs& in, Context& ctx) override {
    ctx.record("start_ms", now_ms());
    ctx.record("threads", ctx.threads());
    std::this_thread::sleep_for(std::chrono::milliseconds(p_.get<int>("sleep_ms")));
    if (p_.get<bool>("fail")) throw Error("asked to fail");
    if (p_.get<bool>("fail_std")) throw std::runtime_error("plain failure");
    Outputs out;
    out.put("missions", in.at("missions"));
    ctx.record("end_ms", now_ms());
    return out;
  }

 private:
  Params p_;
};

// Two inputs and an optional third: fan-in.
class Join : public Stage {
 public:
  explicit Join(const Params&) {}
  static StageInfo info() {
    return declare("test.join", "concatenates missions",
                   {{"a", "missions", "first"}, {"b", "missions", "second"}, {"c", "missions", "third", true}},
                   {{"missions", "missions", "all missions"}});
  }
  Outputs run(const Inputs& in, Context& ctx) override {
    ctx.record("start_ms", now_ms());
    MissionSet all;
    for (const char* port : {"a", "b", "c"})
      if (in.has(port))
        for (const auto& m : in.get<MissionSet>(port).missions) all.missions.push_back(m);
    return Outputs::of("missions", std::move(all));
  }
};

class ToPoints : public Stage {
 public:
  explicit ToPoints(const Params&) {}
  static StageInfo info() {
    return declare("test.to_points", "all points of each mission", {{"missions", "missions", "missions"}},
                   {{"points", "points", "points per mission"}});
  }
  Outputs run(const Inputs& in, Context&) override {
    MissionPoints mp;
    for (const auto& m : in.get<MissionSet>("missions").missions) {
      mp.missions.push_back(m.name);
      PointSet s;
      for (const auto& scan : m.scans) s.append(*scan.points);
      mp.sets.push_back(std::move(s));
    }
    return Outputs::of("points", std::move(mp));
  }
};

// Records what it received: point count, seed and the run's facts.
class Sink : public Stage {
 public:
  explicit Sink(const Params&) {}
  static StageInfo info() { return declare("test.sink", "counts points", {{"points", "points", "points"}}, {}); }
  Outputs run(const Inputs& in, Context& ctx) override {
    ctx.record("points", double(in.get<MissionPoints>("points").total()));
    ctx.record("seed", double(ctx.seed()));
    const RunInfo info = ctx.run_info();
    ctx.record("finished_before", double(info.finished.size()));
    ctx.info("sink saw " + std::to_string(in.get<MissionPoints>("points").total()) + " points");
    return {};
  }
};

// A plugin bug: dies of SIGSEGV inside run().
class Crash : public Stage {
 public:
  explicit Crash(const Params&) {}
  static StageInfo info() {
    return declare("test.crash", "crashes (a plugin bug)", {{"missions", "missions", "missions"}},
                   {{"missions", "missions", "never produced"}}, {});
  }
  Outputs run(const Inputs&, Context&) override {
    std::raise(SIGSEGV);
    return {};
  }
};

// Waits until cancelled (at most `timeout_ms`), then honours it.
class WaitCancel : public Stage {
 public:
  explicit WaitCancel(const Params& p) : p_(p) {}
  static StageInfo info() {
    return declare("test.wait_cancel", "runs until Ctrl-C", {{"missions", "missions", "missions"}},
                   {{"missions", "missions", "the same missions"}},
                   {ParamSpec::integer("timeout_ms", 10000, "give up after").at_least(0)});
  }
  Outputs run(const Inputs& in, Context& ctx) override {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(p_.get<int>("timeout_ms"));
    while (std::chrono::steady_clock::now() < end) {
      ctx.throw_if_cancelled();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return Outputs::of("missions", in.at("missions"));
  }

 private:
  Params p_;
};

// Makes the run's output folder, as a writer stage does, then fails before
// writing into it.
class MakeOutputThenFail : public Stage {
 public:
  explicit MakeOutputThenFail(const Params&) {}
  static StageInfo info() {
    return declare("test.make_output_then_fail", "makes the output folder, then fails",
                   {{"missions", "missions", "missions"}}, {}, {});
  }
  Outputs run(const Inputs&, Context& ctx) override {
    std::filesystem::create_directories(ctx.run_info().output_dir);
    throw Error("failed after making the output folder");
  }
};

// Breaks its output contract in the way `mode` says.
class BadOutput : public Stage {
 public:
  explicit BadOutput(const Params& p) : mode_(p.get<std::string>("mode")) {}
  static StageInfo info() {
    return declare(
        "test.bad_output", "misbehaves", {{"missions", "missions", "missions"}}, {{"missions", "missions", "missions"}},
        {ParamSpec::text("mode", "missing", "how to misbehave").one_of({"missing", "undeclared", "wrong_type"})});
  }
  Outputs run(const Inputs& in, Context&) override {
    Outputs out;
    if (mode_ == "undeclared") {
      out.put("missions", in.at("missions"));
      out.put("extra", in.at("missions"));
    } else if (mode_ == "wrong_type") {
      out.put("missions", MissionPoints{});
    }
    return out;
  }

 private:
  std::string mode_;
};

// One object per mission (ids 0, 1, ...), three points each.
class ToObjects : public Stage {
 public:
  explicit ToObjects(const Params&) {}
  static StageInfo info() {
    return declare("test.to_objects", "one object per mission", {{"missions", "missions", "missions"}},
                   {{"objects", "objects", "one object per mission"}});
  }
  Outputs run(const Inputs& in, Context&) override {
    ObjectSet set;
    for (const auto& m : in.get<MissionSet>("missions").missions) {
      set.missions.push_back(m.name);
      Object o;
      o.id = int(set.objects.size());
      o.mission = uint32_t(set.objects.size());
      o.points.xyz = {{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
      o.update_geometry();
      set.objects.push_back(std::move(o));
    }
    return Outputs::of("objects", std::move(set));
  }
};

// Describes each object by a unit row, or breaks the descriptors contract
// in the way `mode` says.
class Describe : public Stage {
 public:
  explicit Describe(const Params& p) : mode_(p.get<std::string>("mode")) {}
  static StageInfo info() {
    return declare("test.describe", "unit rows, or a broken contract", {{"objects", "objects", "objects"}},
                   {{"descriptors", "descriptors", "one row per object"}},
                   {ParamSpec::text("mode", "ok", "how to misbehave")
                        .one_of({"ok", "missing_row", "extra_id", "unknown_id", "twice", "not_finite", "not_unit", "no_columns", "extra_output"})});
  }
  Outputs run(const Inputs& in, Context&) override {
    DescriptorSet d;
    d.method = "test.describe";
    d.normalized = true;
    for (const auto& o : in.get<ObjectSet>("objects").objects) d.object_ids.push_back(o.id);
    d.values = DescriptorSet::Matrix::Zero(long(d.object_ids.size()), 2);
    d.values.col(0).setOnes();
    if (mode_ == "missing_row") {
      d.object_ids.pop_back();
      d.values.conservativeResize(long(d.object_ids.size()), 2);
    }
    if (mode_ == "extra_id") d.object_ids.push_back(99);
    if (mode_ == "unknown_id") d.object_ids.back() = 99;
    if (mode_ == "twice") d.object_ids.back() = d.object_ids.front();
    if (mode_ == "not_finite") d.values(0, 1) = std::numeric_limits<float>::quiet_NaN();
    if (mode_ == "not_unit") d.values(0, 0) = 2.f;
    if (mode_ == "no_columns") {
      d.normalized = false;
      d.values.resize(long(d.object_ids.size()), 0);
    }
    Outputs out;
    out.put("descriptors", std::move(d));
    if (mode_ == "extra_output") out.put("extra", DescriptorSet());
    return out;
  }

 private:
  std::string mode_;
};

// A source whose constructor refuses inconsistent parameters, as the
// volumetric stages refuse clamping_min >= clamping_max.
class Interval : public Stage {
 public:
  explicit Interval(const Params& p) : lo_(p.get<double>("lo")), hi_(p.get<double>("hi")) {
    if (!(lo_ < hi_)) throw Error("lo must be < hi, got " + std::to_string(lo_) + " and " + std::to_string(hi_));
  }
  static StageInfo info() {
    return declare("test.interval", "checks lo < hi when created", {}, {{"missions", "missions", "no missions"}},
                   {ParamSpec::real("lo", 0.0, "lower end").range(0, 1), ParamSpec::real("hi", 1.0, "upper end").range(0, 1)});
  }
  Outputs run(const Inputs&, Context& ctx) override {
    ctx.record("ran", 1.0);
    return Outputs::of("missions", MissionSet{});
  }

 private:
  double lo_, hi_;
};

template <class S>
void add(Registrar& r) {
  r.add(S::info(), [](const Params& p) { return std::make_unique<S>(p); });
}

void register_stages(Registrar& r) {
  add<Source>(r);
  add<Passthrough>(r);
  add<Join>(r);
  add<ToPoints>(r);
  add<Sink>(r);
  add<WaitCancel>(r);
  add<MakeOutputThenFail>(r);
  add<Crash>(r);
  add<BadOutput>(r);
  add<ToObjects>(r);
  add<Describe>(r);
  add<Interval>(r);
}

}  // namespace

LISTA_PLUGIN(register_stages)
