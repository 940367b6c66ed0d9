// lista-bench <topic> [args...]: runs the benchmark program lista-bench-<topic>
// that sits next to this executable (bench/<topic>/ builds it).
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  const fs::path self = fs::canonical("/proc/self/exe");
  const fs::path dir = self.parent_path();
  auto topics = [&] {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string n = e.path().filename().string();
      if (n.rfind("lista-bench-", 0) == 0) names.push_back(n.substr(12));
    }
    std::sort(names.begin(), names.end());
    return names;
  };
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::cerr << "usage: lista-bench <topic> [args...]\ntopics:";
    for (const auto& t : topics()) std::cerr << " " << t;
    std::cerr << "\n";
    return argc < 2 ? 2 : 0;
  }
  const fs::path target = dir / ("lista-bench-" + std::string(argv[1]));
  if (!fs::exists(target)) {
    std::cerr << "lista-bench: error: no benchmark '" << argv[1] << "' (known:";
    for (const auto& t : topics()) std::cerr << " " << t;
    std::cerr << ")\n";
    return 2;
  }
  std::vector<char*> args;
  const std::string target_str = target.string();
  args.push_back(const_cast<char*>(target_str.c_str()));
  for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  execv(target_str.c_str(), args.data());
  std::cerr << "lista-bench: error: cannot run " << target_str << "\n";
  return 1;
}
