#include "report_output.hpp"

#include <lista_io/atomic_file.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <unistd.h>

namespace fs = std::filesystem;

namespace lista::io {

void write_output(const std::string& out_dir, const Built& built) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec || !fs::is_directory(out_dir))
    throw Error(out_dir + ": cannot create the output folder (" +
                (ec ? ec.message() : std::string("it exists and is not a folder")) + ")");
  const fs::path out(out_dir);
  // An older report must not survive a failed run looking current.
  fs::remove(out / "report.json", ec);
  // Temp folders of runs killed while writing go too.
  io::remove_dead_temps(out_dir);
  const fs::path tmp = out / (".lista-report.tmp." + std::to_string(::getpid()));
  fs::remove_all(tmp, ec);
  fs::create_directories(tmp / "changes", ec);
  if (!ec) fs::create_directories(tmp / "poses", ec);
  if (ec) throw Error(tmp.string() + ": cannot create a temp folder (" + ec.message() + ")");
  try {
    for (const ChangeCloud& c : built.clouds) {
      if (c.mission.find('/') != std::string::npos) throw Error("mission name '" + c.mission + "' contains '/'");
      io::write_pcd((tmp / "changes" / (c.mission + ".pcd")).string(), c.size(),
                    {{"x", 'F', c.x.data()}, {"y", 'F', c.y.data()}, {"z", 'F', c.z.data()},
                     {"scan", 'U', c.scan.data()}, {"index", 'U', c.index.data()}, {"object", 'I', c.object.data()}},
                    io::PcdEncoding::binary);
    }
    for (const ScanPoses& p : built.poses)
      io::write_poses((tmp / "poses" / (p.mission + ".txt")).string(), p.poses, io::PoseFormat::tum);
    io::write_report((tmp / "report.json").string(), built.report);
    for (const char* folder : {"changes", "poses"}) {
      fs::create_directories(out / folder, ec);
      if (ec || !fs::is_directory(out / folder)) throw Error((out / folder).string() + ": cannot create the folder");
    }
    std::set<std::string> written;
    for (const ChangeCloud& c : built.clouds) {
      io::commit_file((tmp / "changes" / (c.mission + ".pcd")).string(), (out / "changes" / (c.mission + ".pcd")).string());
      written.insert(c.mission + ".pcd");
    }
    for (const ScanPoses& p : built.poses) {
      io::commit_file((tmp / "poses" / (p.mission + ".txt")).string(), (out / "poses" / (p.mission + ".txt")).string());
      written.insert(p.mission + ".txt");
    }
    // Change clouds and poses of missions an earlier run had and this one
    // has not would read as this run's.
    for (const auto& [folder, ext] : {std::pair{"changes", ".pcd"}, std::pair{"poses", ".txt"}})
      for (const auto& entry : fs::directory_iterator(out / folder, ec))
        if (entry.path().extension() == ext && !written.count(entry.path().filename().string()))
          fs::remove(entry.path(), ec);
    io::commit_file((tmp / "report.json").string(), (out / "report.json").string());
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
  fs::remove_all(tmp, ec);
}

}  // namespace lista::io
