// lista-run as users see it: exit codes, one-line errors, JSON verdicts.
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <thread>

namespace {

struct Result {
  int code = -1;
  std::string out, err;
};

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs lista-run with only the test plugins visible.
Result lista_run(const std::string& args) {
  lista_test::TempDir dir;
  const std::string cmd = "env -u LISTA_PLUGIN_PATH " LISTA_BIN_DIR "/lista-run --no-default-plugins --plugin-dir " +
                          lista_test::good_dir() + " " + args + " >" + (dir.path / "out").string() + " 2>" +
                          (dir.path / "err").string();
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(dir.path / "out");
  r.err = slurp(dir.path / "err");
  return r;
}

size_t lines(const std::string& s) { return std::count(s.begin(), s.end(), '\n'); }

const char* good_pipeline =
    "[pipeline]\nname = \"cli\"\nseed = 5\n"
    "[stages.src]\nplugin = \"test.source\"\n"
    "[stages.p]\nplugin = \"test.to_points\"\ninputs = { missions = \"src.missions\" }\n"
    "[stages.s]\nplugin = \"test.sink\"\ninputs = { points = \"p.points\" }\n";

}  // namespace

TEST(Cli, RunsAPipeline) {
  lista_test::TempDir dir;
  const auto r = lista_run(dir.write("ok.toml", good_pipeline) + " -j 2 --set src.count=3");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("sink saw 6 points"), std::string::npos) << r.err;
  const auto q = lista_run(dir.path.string() + "/ok.toml --quiet");
  EXPECT_EQ(q.code, 0);
  EXPECT_EQ(q.err, "");
}

TEST(Cli, PipelineErrorIsOneLineWithLocationAndExitOne) {
  lista_test::TempDir dir;
  const std::string file = dir.write("bad.toml", std::string(good_pipeline) + "[stages.x]\nplugin = \"test.sourse\"\n");
  const auto r = lista_run(file);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_EQ(r.err.rfind("lista-run: error: " + file + ":13:10: stage 'x': unknown plugin 'test.sourse'", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("did you mean 'test.source'"), std::string::npos);
}

TEST(Cli, SyntaxErrorAndMissingFile) {
  lista_test::TempDir dir;
  const auto r = lista_run(dir.write("syn.toml", "[pipeline]\nseed = = 1\n"));
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("syn.toml:2:"), std::string::npos) << r.err;
  const auto m = lista_run("/nonexistent/p.toml");
  EXPECT_EQ(m.code, 1);
  EXPECT_NE(m.err.find("cannot open pipeline file '/nonexistent/p.toml'"), std::string::npos) << m.err;
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(lista_run("--no-such-flag").code, 2);
  EXPECT_EQ(lista_run("").code, 2);
  lista_test::TempDir dir;
  const auto r = lista_run(dir.write("ok.toml", good_pipeline) + " --set nodot=3");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_EQ(lista_run("ok.toml -j 0").code, 2);
  const auto big = lista_run(dir.write("seed.toml", good_pipeline) + " --seed 99999999999999999999");
  EXPECT_EQ(big.code, 2);
  EXPECT_NE(big.err.find("--seed: is too large"), std::string::npos) << big.err;
}

TEST(Cli, ValidatePrintsJsonVerdict) {
  lista_test::TempDir dir;
  const auto ok = lista_run(dir.write("ok.toml", good_pipeline) + " --validate");
  EXPECT_EQ(ok.code, 0);
  EXPECT_NE(ok.out.find("\"valid\": true"), std::string::npos) << ok.out;
  // A misspelt parameter on line 6, in stage src (test.source declares count).
  std::string text = good_pipeline;
  const std::string after = "plugin = \"test.source\"\n";
  text.insert(text.find(after) + after.size(), "cuont = 3\n");
  const auto bad = lista_run(dir.write("bad.toml", text) + " --validate");
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.out.find("\"valid\": false"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("\"line\": 6"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("\"stage\": \"src\""), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("did you mean"), std::string::npos) << bad.out;
}

// --validate accepts an old parameter name and says the new one.
TEST(Cli, ValidateAcceptsAnOldParameterNameWithAWarning) {
  lista_test::TempDir dir;
  std::string text = good_pipeline;
  const std::string after = "plugin = \"test.source\"\n";
  text.insert(text.find(after) + after.size(), "sigma = 0.2\n");
  const auto r = lista_run(dir.write("old.toml", text) + " --validate --set src.noise_level=0");
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("\"valid\": true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("parameter 'sigma' is now 'noise.sigma' (the old name works until the next release)"),
            std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"line\": 6"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--set src.noise_level=0: parameter 'noise_level' is now 'noise.sigma'"), std::string::npos)
      << r.out;
  // A run prints it once, and the value arrives.
  const auto plan = lista_run(dir.path.string() + "/old.toml --dry-run");
  EXPECT_EQ(plan.code, 0) << plan.err;
  EXPECT_EQ(lines(plan.err), 1u) << plan.err;
  EXPECT_NE(plan.err.find("lista-run: warning: "), std::string::npos) << plan.err;
  EXPECT_NE(plan.out.find("noise.sigma = 0.2\n"), std::string::npos) << plan.out;
}

TEST(Cli, DryRunPrintsThePlanAndRunsNothing) {
  lista_test::TempDir dir;
  const auto r = lista_run(dir.write("ok.toml", good_pipeline) + " --dry-run --set src.count=7");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("3 stages in 3 levels"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("count = 7"), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("sink saw"), std::string::npos);
}

TEST(Cli, ListAndDescribePlugins) {
  const auto list = lista_run("--list-plugins");
  EXPECT_EQ(list.code, 0);
  EXPECT_NE(list.out.find("test.passthrough"), std::string::npos) << list.out;
  const auto text = lista_run("--describe test.source");
  EXPECT_EQ(text.code, 0);
  EXPECT_NE(text.out.find("scale : float = 1.0 m  range [0.001, 1000.0]"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("missions : int = 2  range [1, 100]"), std::string::npos) << text.out;
  const auto json = lista_run("--describe test.source --json");
  EXPECT_EQ(json.code, 0);
  EXPECT_NE(json.out.find("\"choices\": [\n        \"fast\",\n        \"exact\"\n      ]"), std::string::npos) << json.out;
  // Old names are no parameters: a note under them.
  EXPECT_NE(text.out.find("renamed (the old names work until the next release):\n  sigma -> noise.sigma\n"),
            std::string::npos) << text.out;
  EXPECT_NE(json.out.find("\"renamed\": [\n    {\n      \"new\": \"noise.sigma\",\n      \"old\": \"sigma\""),
            std::string::npos) << json.out;
  const auto unknown = lista_run("--describe test.sourc");
  EXPECT_EQ(unknown.code, 1);
  EXPECT_NE(unknown.err.find("did you mean 'test.source'"), std::string::npos);
}

TEST(Cli, BrokenPluginsAreWarningsNotFatal) {
  const auto r = lista_run("--plugin-dir " + lista_test::bad_dir() + " --list-plugins");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("test.source"), std::string::npos);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 3) << r.err;
}

// The output folder (and the parents made for it) is removed when the run
// fails with it still empty; a folder that existed before stays.
TEST(Cli, AFailedRunRemovesTheEmptyOutputFolderItMade) {
  lista_test::TempDir dir;
  const std::string file = dir.write(
      "make.toml", "[stages.src]\nplugin = \"test.source\"\n"
                   "[stages.m]\nplugin = \"test.make_output_then_fail\"\ninputs = { missions = \"src.missions\" }\n");
  const std::filesystem::path out = dir.path / "new" / "out";
  const auto r = lista_run(file + " --out " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir.path / "new")) << r.err;
  EXPECT_NE(r.err.find("removed the empty output folder " + out.string() + " and the 1 folder(s) made for it"),
            std::string::npos)
      << r.err;
  const auto q = lista_run(file + " --out " + out.string() + " -q");
  EXPECT_FALSE(std::filesystem::exists(dir.path / "new"));
  EXPECT_EQ(q.err.find("removed the empty output folder"), std::string::npos) << "-q: " << q.err;
  std::filesystem::create_directories(dir.path / "mine");
  lista_run(file + " --out " + (dir.path / "mine").string() + " -q");
  EXPECT_TRUE(std::filesystem::is_directory(dir.path / "mine")) << "a folder the user made is theirs";
}

// Ctrl-C, and SIGTERM as timeout, systemd and docker send it: the run is
// cancelled (exit 130, no report left), not killed midway.
TEST(Cli, CtrlCAndSigtermCancelWithExit130) {
  for (int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig);
    lista_test::TempDir dir;
    const std::string file = dir.write(
        "wait.toml", "[stages.src]\nplugin = \"test.source\"\n"
                     "[stages.w]\nplugin = \"test.wait_cancel\"\ninputs = { missions = \"src.missions\" }\n");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      unsetenv("LISTA_PLUGIN_PATH");
      const std::string good = lista_test::good_dir();
      execl(LISTA_BIN_DIR "/lista-run", "lista-run", "--no-default-plugins", "--quiet", "--plugin-dir", good.c_str(),
            file.c_str(), static_cast<char*>(nullptr));
      _exit(99);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    kill(pid, sig);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status)) << "killed by the signal instead of cancelling";
    EXPECT_EQ(WEXITSTATUS(status), 130);
  }
}

// The folder a plugin author builds into is easy to get wrong; a --plugin-dir
// that is missing or is a file says so instead of "unknown plugin" later.
// A plugin that crashes kills the run, but not silently: the last line
// names the stage and plugin that were running.
TEST(Cli, ACrashNamesTheStageThatWasRunning) {
  lista_test::TempDir dir;
  const std::string file = dir.write(
      "crash.toml", "[stages.src]\nplugin = \"test.source\"\n"
                    "[stages.boom]\nplugin = \"test.crash\"\ninputs = { missions = \"src.missions\" }\n");
  const auto r = lista_run(file + " --quiet");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("lista-run: crashed (signal 11) while running: boom (test.crash); a bug in that stage's plugin"),
            std::string::npos)
      << r.err;
}

// An unknown plugin whose library failed to load is told that library's
// error (liblista_test_no_manifest.so for test.no_manifest), not the first
// failure's.
TEST(Cli, UnknownPluginQuotesItsOwnLibrarysLoadError) {
  lista_test::TempDir dir;
  const std::string file = dir.write("nm.toml", "[stages.a]\nplugin = \"test.no_manifest\"\n");
  const auto r = lista_run("--plugin-dir " + lista_test::bad_dir() + " " + file + " --validate");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("failed to load: " + lista_test::bad_dir() + "/liblista_test_no_manifest.so: not a LiSTA plugin"),
            std::string::npos)
      << r.out;
}

TEST(Cli, PluginDirMustBeAFolder) {
  lista_test::TempDir dir;
  const auto missing = lista_run("--plugin-dir " + dir.path.string() + "/nope --list-plugins");
  EXPECT_EQ(missing.code, 2);
  EXPECT_EQ(missing.err, "lista-run: error: --plugin-dir " + dir.path.string() + "/nope: no such folder\n");
  const auto file = lista_run("--plugin-dir " + lista_test::good_library() + " --list-plugins");
  EXPECT_EQ(file.code, 2);
  EXPECT_NE(file.err.find("is a file; give the folder that holds the plugin libraries"), std::string::npos) << file.err;
}

// --validate always answers with its JSON verdict, even for a malformed
// --set (still exit 2, a usage error); a run without it keeps the one line.
TEST(Cli, ValidateGivesAVerdictForAMalformedSet) {
  lista_test::TempDir dir;
  const std::string file = dir.write("ok.toml", good_pipeline);
  const auto r = lista_run(file + " --validate --set '=3' --set src.cuont=1");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("\"valid\": false"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--set '=3' is not of the form <stage>.<param>=<value>"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("unknown parameter 'cuont'"), std::string::npos) << "the rest is still checked: " << r.out;
  const auto missing = lista_run("--validate --set '=3'");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.out.find("no pipeline given"), std::string::npos) << missing.out;
  const auto plain = lista_run(file + " --set '=3'");
  EXPECT_EQ(plain.code, 2);
  EXPECT_EQ(plain.out, "");
  EXPECT_EQ(plain.err, "lista-run: error: --set '=3' is not of the form <stage>.<param>=<value>\n");
}

// Parameters a stage refuses together are found by --validate, and a run
// stops before its first stage starts.
TEST(Cli, AStageRefusingItsParametersFailsBeforeAnyStageRuns) {
  lista_test::TempDir dir;
  const std::string file = dir.write(
      "iv.toml", "[stages.src]\nplugin = \"test.source\"\n"
                 "[stages.p]\nplugin = \"test.to_points\"\ninputs = { missions = \"src.missions\" }\n"
                 "[stages.s]\nplugin = \"test.sink\"\ninputs = { points = \"p.points\" }\n"
                 "[stages.iv]\nplugin = \"test.interval\"\n");
  const std::string sets = " --set iv.lo=0.9 --set iv.hi=0.1";
  const auto v = lista_run(file + sets + " --validate");
  EXPECT_EQ(v.code, 1);
  EXPECT_NE(v.out.find("\"line\": 9"), std::string::npos) << v.out;
  EXPECT_NE(v.out.find("parameters refused by test.interval: lo must be < hi"), std::string::npos) << v.out;
  const auto r = lista_run(file + sets);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("lista-run: error: " + file + ":9:1: stage 'iv': parameters refused by test.interval"),
            std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("started"), std::string::npos) << r.err;
}
