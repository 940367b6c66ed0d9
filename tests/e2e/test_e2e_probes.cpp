// The probe classes of docs/reliability.md as one table: each row breaks a
// copy of a small simulated dataset (or the pipeline, or the output path) the
// way a careless or hostile user would, and the run must end with exit 1, a
// one-line error that names the file and what is wrong, and no report. Then
// Ctrl-C during each stage of the default pipeline: cancelled (exit 130), no
// report, or a complete report when the signal came after the last stage.
#include "e2e_support.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

class Probes : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new e2e::TempDir("probes");
    clean_ = dir_->path() / "clean";
    sim_ = e2e::simulate("--preset tiny --seed 1 --scans 3", clean_);
  }
  static void TearDownTestSuite() { delete dir_; }

  static e2e::TempDir* dir_;
  static fs::path clean_;
  static e2e::Result sim_;
};

e2e::TempDir* Probes::dir_ = nullptr;
fs::path Probes::clean_;
e2e::Result Probes::sim_;

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

void cut_to(const fs::path& p, double fraction) { fs::resize_file(p, uintmax_t(double(fs::file_size(p)) * fraction)); }

// Replaces the first occurrence of `from` in a file's bytes.
void patch(const fs::path& p, const std::string& from, const std::string& to) {
  std::string s = e2e::read_file(p);
  const size_t at = s.find(from);
  ASSERT_NE(at, std::string::npos) << from << " not in " << p;
  s.replace(at, from.size(), to);
  write(p, s);
}

const char* kScan = "A/scans/000001.pcd";

struct Probe {
  const char* klass;   // the probe class of docs/reliability.md
  const char* name;
  std::function<void(const fs::path& data)> breaks;  // what to do to a copy of the dataset
  const char* needle;  // in the one-line error
  std::string args = "";  // extra lista-run arguments ({data} = the dataset copy)
};

const std::vector<Probe>& probes() {
  static const std::vector<Probe> table = {
      {"PCD", "truncated binary", [](const fs::path& d) { cut_to(d / kScan, 0.5); }, "000001.pcd"},
      {"PCD", "garbage", [](const fs::path& d) { write(d / kScan, std::string(4096, '\xA7')); }, "000001.pcd"},
      {"PCD", "points past the data", [](const fs::path& d) { patch(d / kScan, "POINTS ", "POINTS 9"); }, "000001.pcd"},
      {"PCD", "empty file", [](const fs::path& d) { write(d / kScan, ""); }, "000001.pcd"},
      {"PLY", "truncated binary",
       [](const fs::path& d) {
         std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\n"
                           "property float z\nend_header\n" + std::string(600, '\0');
         fs::remove(d / kScan);
         write(d / "A/scans/000001.ply", ply);
       },
       "000001.ply"},
      {"PLY", "vertex count beyond the file",
       [](const fs::path& d) {
         fs::remove(d / kScan);
         write(d / "A/scans/000001.ply", "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\n"
                                         "property float y\nproperty float z\nend_header\n1 2 3\n");
       },
       "000001.ply"},
      {"BIN", "size not a multiple of 16",
       [](const fs::path& d) {
         fs::remove(d / kScan);
         write(d / "A/scans/000001.bin", std::string(33, '\x01'));
       },
       "000001.bin"},
      {"poses", "a field that is no number", [](const fs::path& d) { write(d / "A/poses.txt", "0 0 0 0 0 0 0 1\n0 x 0 0 0 0 0 1\n0 0 0 0 0 0 0 1\n"); },
       "poses.txt:2"},
      {"poses", "a rotation that is not one", [](const fs::path& d) { write(d / "A/poses.txt", "0 0 0 0 0 0 0 1\n0 0 0 0 0 0 0 3\n0 0 0 0 0 0 0 1\n"); },
       "poses.txt:2"},
      {"poses", "fewer poses than scans", [](const fs::path& d) { write(d / "A/poses.txt", "0 0 0 0 0 0 0 1\n"); },
       "3 scan files in scans/ but 1 poses"},
      {"poses", "hexadecimal", [](const fs::path& d) { write(d / "A/poses.txt", "0 0x10 0 0 0 0 0 1\n0 0 0 0 0 0 0 1\n0 0 0 0 0 0 0 1\n"); },
       "poses.txt:1"},
      {"layout", "scans/ without poses.txt", [](const fs::path& d) { fs::remove(d / "A/poses.txt"); }, "has scans/ but no poses.txt"},
      {"layout", "a folder named like a scan", [](const fs::path& d) { fs::remove(d / kScan); fs::create_directory(d / kScan); },
       "is a folder, not a scan file"},
      {"layout", "a loop of links as a scan",
       [](const fs::path& d) {
         fs::remove(d / kScan);
         fs::create_symlink(d / kScan, d / kScan);
       },
       "a broken link or a loop of links"},
      {"layout", "a pipe as a scan",
       [](const fs::path& d) {
         fs::remove(d / kScan);
         ASSERT_EQ(mkfifo((d / kScan).c_str(), 0600), 0);
       },
       "is a pipe (FIFO), not a scan file"},
      {"layout", "a bag mission without poses",
       [](const fs::path& d) {
         fs::remove_all(d / "A");
         fs::create_directories(d / "A");
         write(d / "A/mission.bag", "#ROSBAG V2.0\nnot really");
       },
       "mission.bag"},
      {"TOML", "nesting 5000 deep", [](const fs::path& d) { write(d / "deep.toml", "x = " + std::string(5000, '[') + "\n"); },
       "deep.toml:1", "{data}/deep.toml"},
      {"TOML", "bytes that are not UTF-8", [](const fs::path& d) { write(d / "latin.toml", "# caf\xe9\n[stages.a]\nplugin = 'io.missions'\n"); },
       "latin.toml:1", "{data}/latin.toml"},
      {"TOML", "a folder as the pipeline", [](const fs::path& d) { fs::create_directories(d / "folder.toml"); },
       "folder.toml", "{data}/folder.toml"},
      {"TOML", "a 100 KB unknown key", [](const fs::path&) {}, "characters, cut)", "--set load." + std::string(100000, 'k') + "=1"},
      {"output", "--out is a file", [](const fs::path& d) { write(d / "taken", "mine"); }, "taken", "--out {data}/taken"},
      {"output", "--out under a file", [](const fs::path& d) { write(d / "taken", "mine"); }, "taken", "--out {data}/taken/out"},
  };
  return table;
}

}  // namespace

TEST_F(Probes, EachBadInputIsOneLocatedLineExit1AndNoReport) {
  ASSERT_EQ(sim_.status, 0) << sim_.output;
  std::set<std::string> classes;
  int k = 0;
  for (const Probe& p : probes()) {
    SCOPED_TRACE(std::string(p.klass) + ": " + p.name);
    classes.insert(p.klass);
    const fs::path data = dir_->path() / ("data-" + std::to_string(k++));
    fs::copy(clean_, data, fs::copy_options::recursive);
    p.breaks(data);
    std::string args = p.args;
    for (size_t at; (at = args.find("{data}")) != std::string::npos;) args.replace(at, 6, data.string());
    const bool own_pipeline = args.rfind(data.string(), 0) == 0;
    const bool own_out = args.find("--out") != std::string::npos;
    const fs::path out = dir_->path() / ("out-" + std::to_string(k));
    const std::string command = e2e::bin("lista-run") + " " + (own_pipeline ? "" : e2e::source("pipelines/lista.toml") + " ") +
                                args + " --dataset " + data.string() + (own_out ? "" : " --out " + out.string()) +
                                " --threads 2 -q 2>&1";
    const auto r = e2e::run("timeout 60 " + command);
    EXPECT_EQ(r.status, 1) << r.output.substr(0, 2000);
    EXPECT_NE(r.output.find(p.needle), std::string::npos) << r.output.substr(0, 2000);
    size_t lines = 0;
    for (char c : r.output) lines += c == '\n';
    EXPECT_LE(lines, 2u) << "one line (and, at most, the removed folder's): " << r.output.substr(0, 2000);
    EXPECT_LE(r.output.size(), 1200u) << "no echo of the input";
    EXPECT_FALSE(fs::exists(out)) << "a failed run leaves no output folder";
  }
  EXPECT_EQ(classes, (std::set<std::string>{"PCD", "PLY", "BIN", "poses", "layout", "TOML", "output"}));
}

namespace {

// Runs the default pipeline and sends SIGINT once stderr says `stage` has
// started; returns the exit status (-1: killed by a signal).
int interrupted_at(const std::string& stage, const fs::path& data, const fs::path& out) {
  int err[2];
  if (pipe(err) != 0) return -2;
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(err[1], 2);
    close(err[0]);
    close(err[1]);
    const std::string run = e2e::bin("lista-run"), pipeline = e2e::source("pipelines/lista.toml");
    execl(run.c_str(), "lista-run", pipeline.c_str(), "--dataset", data.c_str(), "--out", out.c_str(), "--threads", "2",
          static_cast<char*>(nullptr));
    _exit(99);
  }
  close(err[1]);
  std::string seen;
  char buf[4096];
  bool sent = false;
  for (ssize_t n; (n = read(err[0], buf, sizeof buf)) > 0;) {
    seen.append(buf, size_t(n));
    if (!sent && seen.find("info: " + stage + " (") != std::string::npos) {
      kill(pid, SIGINT);
      sent = true;
    }
  }
  close(err[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_F(Probes, CtrlCDuringEachStageCancelsCleanly) {
  ASSERT_EQ(sim_.status, 0) << sim_.output;
  // The stages in the order the default pipeline runs them.
  const auto listed = e2e::run(e2e::bin("lista-run") + " " + e2e::source("pipelines/lista.toml") + " --dataset " +
                               clean_.string() + " --out " + (dir_->path() / "listed").string() + " --threads 2 2>&1");
  ASSERT_EQ(listed.status, 0) << listed.output;
  std::vector<std::string> stages;
  const std::regex started("info: ([a-z_0-9]+) \\([a-z.\\-_]+\\) started");
  for (std::sregex_iterator it(listed.output.begin(), listed.output.end(), started), end; it != end; ++it)
    stages.push_back((*it)[1]);
  ASSERT_GE(stages.size(), 10u) << listed.output;
  size_t cancelled = 0;
  for (const std::string& stage : stages) {
    SCOPED_TRACE(stage);
    const fs::path out = dir_->path() / ("cancel-" + stage);
    const int status = interrupted_at(stage, clean_, out);
    if (status == 130) {
      ++cancelled;
      EXPECT_FALSE(fs::exists(out / "report.json")) << "a cancelled run left a report";
    } else {
      // The signal came after the last stage had finished: a complete run.
      EXPECT_EQ(status, 0);
      EXPECT_TRUE(fs::exists(out / "report.json"));
    }
    if (fs::exists(out)) {
      for (const auto& e : fs::directory_iterator(out)) {
        EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
      }
    }
  }
  EXPECT_GE(cancelled + 2, stages.size()) << "all but the last stages' signals cancel the run";
}
