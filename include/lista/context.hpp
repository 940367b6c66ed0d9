// What a running stage may use besides its inputs and parameters: a logger, a
// progress reporter, the thread budget, the seed, cancellation, and facts
// about the run (for writers of reports). The core implements it;
// lista::BasicContext (lista/basic_context.hpp) is a ready one for tests.
#pragma once

#include <lista/error.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace lista {

enum class LogLevel { debug, info, warning, error };

// Thread-safe progress of one long task. Shown as a bar on a TTY, plain lines
// otherwise, nothing with --quiet.
class Progress {
 public:
  virtual ~Progress() = default;
  virtual void begin(const std::string& what, uint64_t total) = 0;
  virtual void advance(uint64_t n = 1) = 0;  // callable from any thread
  virtual void end() = 0;
};

struct StageRecord {
  std::string id, plugin;
  double seconds = 0.0;
  uint64_t peak_rss_bytes = 0;  // process peak resident set when the stage ended
};

struct PluginRecord {
  std::string name, version, library;
};

// Facts about the whole run, for stages that write reports.
struct RunInfo {
  std::string lista_version, git_revision;
  std::string pipeline_file;      // as given on the command line
  std::string pipeline_resolved;  // the pipeline as run (defaults and --set applied), TOML
  std::string dataset;            // --dataset / [pipeline].dataset, absolute ("" if none)
  std::string output_dir;         // --out / [pipeline].output ("" if none)
  uint64_t seed = 0;
  int threads = 1;                // total thread budget (--threads)
  int jobs = 1;                   // stages run at once (-j); each gets threads / jobs
  std::vector<PluginRecord> plugins;  // plugins used by the pipeline
  std::vector<StageRecord> finished;  // stages finished so far, in finishing order
  // Numbers stages chose to record (Context::record), by stage id then key.
  std::map<std::string, std::map<std::string, double>> metrics;
  // Texts stages chose to note (Context::note), by stage id then key: what a
  // run depended on that its parameters do not show (a resolved file, its hash).
  std::map<std::string, std::map<std::string, std::string>> notes;
  // Every warning stages logged so far, "<stage id>: <message>", in order:
  // the report keeps them, since a log scrolls away.
  std::vector<std::string> warnings;
};

class Context {
 public:
  virtual ~Context() = default;

  virtual const std::string& stage_id() const = 0;
  virtual void log(LogLevel level, const std::string& message) = 0;
  void debug(const std::string& m) { log(LogLevel::debug, m); }
  void info(const std::string& m) { log(LogLevel::info, m); }
  void warn(const std::string& m) { log(LogLevel::warning, m); }

  virtual Progress& progress() = 0;
  virtual int threads() const = 0;     // >= 1: how many threads this stage may use
  virtual uint64_t seed() const = 0;   // the run's seed; derive all randomness from it
  virtual bool cancelled() const = 0;  // true after Ctrl-C: stop soon
  void throw_if_cancelled() const {
    if (cancelled()) throw Cancelled();
  }
  // Records a named number (voxel count, ATE, ...) in the report's metrics.
  virtual void record(const std::string& key, double value) = 0;
  // Notes a named text (the weights file a default resolved to, its SHA-256)
  // in the report's provenance, so a run can be traced to what it read.
  virtual void note(const std::string& key, const std::string& text) = 0;
  // A snapshot of the run's facts (timings of the stages finished so far).
  virtual RunInfo run_info() const = 0;
};

}  // namespace lista
