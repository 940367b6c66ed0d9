// The executor: order, parallelism, failures with their stage, cancellation,
// and the run's facts.
#include "test_support.hpp"

#include <lista_core/executor.hpp>

#include <gtest/gtest.h>

#include <sstream>
#include <thread>

using namespace lista::core;
using lista_test::plan_of;
using lista::RunInfo;

namespace {

Plan checked_plan(const std::string& toml, const std::vector<std::string>& sets = {}) {
  Diagnostics d;
  Plan plan = plan_of(toml, d, sets);
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.errors[0].str());
  return plan;
}

RunInfo run(const Plan& plan, int jobs, std::ostringstream* log = nullptr, const std::atomic<bool>* cancel = nullptr) {
  static std::atomic<bool> never{false};
  static std::ostringstream sink;
  RunOptions o;
  o.jobs = jobs;
  o.threads = 4;
  o.log = log ? log : &sink;
  o.cancel = cancel ? cancel : &never;
  return execute(plan, o);
}

const std::string diamond =
    "[pipeline]\nseed = 11\n"
    "[stages.src]\nplugin = \"test.source\"\ncount = 10\n"                                              // 3-5
    "[stages.a]\nplugin = \"test.passthrough\"\ninputs = { missions = \"src.missions\" }\nsleep_ms = 300\n"  // 6-9
    "[stages.b]\nplugin = \"test.passthrough\"\ninputs = { missions = \"src.missions\" }\nsleep_ms = 300\n"  // 10-13
    "[stages.j]\nplugin = \"test.join\"\ninputs = { a = \"a.missions\", b = \"b.missions\" }\n"         // 14-16
    "[stages.p]\nplugin = \"test.to_points\"\ninputs = { missions = \"j.missions\" }\n"
    "[stages.s]\nplugin = \"test.sink\"\ninputs = { points = \"p.points\" }\n";

double metric(const RunInfo& info, const std::string& stage, const std::string& key) {
  return info.metrics.at(stage).at(key);
}

}  // namespace

TEST(Executor, RunsDiamondInDependencyOrderWithData) {
  const RunInfo info = run(checked_plan(diamond), 1);
  ASSERT_EQ(info.finished.size(), 6u);
  EXPECT_EQ(info.finished.front().id, "src");
  EXPECT_EQ(info.finished.back().id, "s");
  EXPECT_EQ(metric(info, "s", "points"), 40.0);  // 2 missions x 10 points, twice
  EXPECT_EQ(metric(info, "s", "seed"), 11.0);
  EXPECT_EQ(metric(info, "s", "finished_before"), 5.0);
  for (const auto& r : info.finished) {
    EXPECT_GE(r.seconds, 0.0);
    EXPECT_GT(r.peak_rss_bytes, 0u);
  }
  EXPECT_GE(info.finished[1].seconds, 0.29);
  ASSERT_EQ(info.plugins.size(), 5u);
  EXPECT_NE(info.plugins[0].library.find("liblista_test_stages.so"), std::string::npos);
  EXPECT_NE(info.pipeline_resolved.find("sleep_ms = 300"), std::string::npos);
  EXPECT_FALSE(info.git_revision.empty());
  EXPECT_FALSE(info.lista_version.empty());
}

TEST(Executor, IndependentStagesOverlapWithTwoJobsOnly) {
  const RunInfo parallel = run(checked_plan(diamond), 2);
  // a and b each sleep 300 ms: with -j 2 they overlap, with -j 1 they do not.
  EXPECT_LT(metric(parallel, "a", "start_ms"), metric(parallel, "b", "end_ms"));
  EXPECT_LT(metric(parallel, "b", "start_ms"), metric(parallel, "a", "end_ms"));
  EXPECT_EQ(metric(parallel, "a", "threads"), 2.0);  // budget 4 shared by 2 jobs
  const RunInfo serial = run(checked_plan(diamond), 1);
  const bool a_first = metric(serial, "a", "start_ms") < metric(serial, "b", "start_ms");
  if (a_first) EXPECT_LE(metric(serial, "a", "end_ms"), metric(serial, "b", "start_ms"));
  else EXPECT_LE(metric(serial, "b", "end_ms"), metric(serial, "a", "start_ms"));
  EXPECT_EQ(metric(serial, "a", "threads"), 4.0);
  // The join starts only after both of its inputs are done.
  EXPECT_GE(metric(parallel, "j", "start_ms"), std::max(metric(parallel, "a", "end_ms"), metric(parallel, "b", "end_ms")));
}

TEST(Executor, SameSeedSameData) {
  const RunInfo one = run(checked_plan(diamond, {"a.sleep_ms=0", "b.sleep_ms=0"}), 2);
  const RunInfo two = run(checked_plan(diamond, {"a.sleep_ms=0", "b.sleep_ms=0"}), 1);
  EXPECT_EQ(one.metrics.at("s"), two.metrics.at("s"));
}

TEST(Executor, StageErrorCarriesStageIdPluginAndLocation) {
  const Plan plan = checked_plan(diamond, {"b.fail=true", "a.sleep_ms=0"});
  try {
    run(plan, 2);
    FAIL() << "no error";
  } catch (const lista::Cancelled&) {
    FAIL() << "cancelled instead of failed";
  } catch (const lista::Error& e) {
    EXPECT_EQ(e.stage_id(), "b");
    EXPECT_EQ(e.plugin(), "test.passthrough");
    EXPECT_EQ(e.location().file, "p.toml");
    EXPECT_EQ(e.location().line, 10);
    EXPECT_EQ(std::string(e.what()), "p.toml:10:1: stage 'b' (test.passthrough): asked to fail");
  }
}

TEST(Executor, PlainExceptionBecomesError) {
  try {
    run(checked_plan(diamond, {"a.fail_std=true"}), 1);
    FAIL() << "no error";
  } catch (const lista::Error& e) {
    EXPECT_EQ(e.stage_id(), "a");
    EXPECT_NE(std::string(e.what()).find("plain failure"), std::string::npos);
  }
}

// Running `plan` fails in stage `stage` with a message holding `text`.
void expect_stage_failure(const Plan& plan, const std::string& stage, const std::string& text) {
  try {
    run(plan, 1);
    ADD_FAILURE() << "accepted; expected: " << text;
  } catch (const lista::Error& e) {
    EXPECT_EQ(e.stage_id(), stage) << e.what();
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST(Executor, OutputsMustMatchTheDeclaration) {
  const std::string base = "[stages.src]\nplugin = \"test.source\"\n"
                           "[stages.bad]\nplugin = \"test.bad_output\"\ninputs = { missions = \"src.missions\" }\n";
  for (const auto& [mode, text] : std::vector<std::pair<std::string, std::string>>{
           {"missing", "declared output 'missions' was not produced"},
           {"undeclared", "does not declare"},
           {"wrong_type", "is 'points' but is declared 'missions'"}}) {
    expect_stage_failure(checked_plan(base, {"bad.mode=" + mode}), "bad", text);
  }
}

// A descriptors output that breaks its contract fails the stage that made
// it, not the grouping or matching stage that would read it.
TEST(Executor, DescriptorsMustKeepTheirContract) {
  const std::string base = "[stages.src]\nplugin = \"test.source\"\nmissions = 3\n"
                           "[stages.obj]\nplugin = \"test.to_objects\"\ninputs = { missions = \"src.missions\" }\n"
                           "[stages.desc]\nplugin = \"test.describe\"\ninputs = { objects = \"obj.objects\" }\n";
  EXPECT_NO_THROW(run(checked_plan(base), 1));
  for (const auto& [mode, text] : std::vector<std::pair<std::string, std::string>>{
           {"missing_row", "descriptors cover 2 of 3 input objects"},
           {"extra_id", "descriptors have 3 rows but 4 object ids"},
           {"unknown_id", "descriptors name object 99, which is not among the input objects"},
           {"twice", "descriptors name object 0 twice"},
           {"not_finite", "the descriptor of object 0 holds a NaN"},
           {"not_unit", "descriptors are marked normalized but the row of object 0 has norm 2"},
           {"no_columns", "descriptors have no columns (0-d)"}}) {
    expect_stage_failure(checked_plan(base, {"desc.mode=" + mode}), "desc", "output 'descriptors': " + text);
  }
  expect_stage_failure(checked_plan(base, {"desc.mode=extra_output"}), "desc",
                       "produced output 'extra' that test.describe does not declare");
}

TEST(Executor, CancellationStopsCleanly) {
  const std::string toml = "[stages.src]\nplugin = \"test.source\"\n"
                           "[stages.w]\nplugin = \"test.wait_cancel\"\ninputs = { missions = \"src.missions\" }\n"
                           "[stages.after]\nplugin = \"test.to_points\"\ninputs = { missions = \"w.missions\" }\n";
  std::atomic<bool> cancel{false};
  std::thread ctrl_c([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    cancel = true;
  });
  std::ostringstream log;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(run(checked_plan(toml), 2, &log, &cancel), lista::Cancelled);
  ctrl_c.join();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 5.0);  // the stage would wait 10 s
  EXPECT_EQ(log.str().find("after (test.to_points) started"), std::string::npos) << log.str();
}

// Progress is drawn only for a person at a terminal: a log (not a TTY) gets
// the stages' info lines and no progress, and quiet silences both.
TEST(Executor, LogsInfoLinesWithoutProgressAndQuietSilences) {
  std::ostringstream log;
  run(checked_plan(diamond, {"a.sleep_ms=0", "b.sleep_ms=0"}), 1, &log);
  EXPECT_EQ(log.str().find("making points"), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("info: s: sink saw 40 points"), std::string::npos) << log.str();
  EXPECT_EQ(log.str().find('\r'), std::string::npos);

  std::ostringstream quiet_log;
  RunOptions o;
  o.quiet = true;
  o.log = &quiet_log;
  static std::atomic<bool> never{false};
  o.cancel = &never;
  execute(checked_plan(diamond, {"a.sleep_ms=0", "b.sleep_ms=0"}), o);
  EXPECT_EQ(quiet_log.str(), "");
}

// A report must say which folder it was made from wherever it is read, and
// how the run was spread: -j and the thread budget.
TEST(Executor, RecordsTheAbsoluteDatasetJobsAndThreads) {
  static std::atomic<bool> never{false};
  std::ostringstream log;
  RunOptions o;
  o.jobs = 2;
  o.threads = 6;
  o.log = &log;
  o.cancel = &never;
  o.dataset = "some/relative/data/";
  const RunInfo info = execute(checked_plan(diamond), o);
  const std::string absolute = (std::filesystem::current_path() / "some/relative/data").string();
  EXPECT_EQ(info.dataset, absolute);
  EXPECT_NE(info.pipeline_resolved.find("dataset = \"" + absolute + "\""), std::string::npos) << info.pipeline_resolved;
  EXPECT_EQ(info.jobs, 2);
  EXPECT_EQ(info.threads, 6);
  EXPECT_EQ(run(checked_plan("[pipeline]\ndataset = \"/abs/data\"\n" + diamond.substr(diamond.find("[stages"))), 1)
                .dataset,
            "/abs/data");
}
