#include "e2e_support.hpp"

#include <array>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace e2e {

Result run(const std::string& command) {
  Result r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string bin(const std::string& program) { return std::string(LISTA_BIN_DIR) + "/" + program; }
std::string source(const std::string& path) { return std::string(LISTA_SOURCE_DIR) + "/" + path; }

Result simulate(const std::string& args, const std::filesystem::path& out) {
  return run(bin("lista-sim") + " " + args + " --threads 2 --out " + out.string() + " 2>&1");
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string python3() {
#ifdef LISTA_PYTHON3
  return LISTA_PYTHON3;
#else
  return {};
#endif
}

std::vector<std::vector<std::string>> markdown_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  std::string line;
  bool header_next = true;  // a table's first line is its header
  while (std::getline(lines, line)) {
    if (line.rfind("|", 0) != 0) {
      header_next = true;
      continue;
    }
    if (line.rfind("|---", 0) == 0) continue;
    if (header_next) {
      header_next = false;
      continue;
    }
    std::vector<std::string> cells;
    std::istringstream parts(line.substr(1));
    std::string cell;
    while (std::getline(parts, cell, '|')) {
      const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
      cells.push_back(b == std::string::npos ? std::string() : cell.substr(b, e - b + 1));
    }
    rows.push_back(cells);
  }
  return rows;
}

TempDir::TempDir(const std::string& tag) {
  std::random_device rd;
  path_ = std::filesystem::temp_directory_path() /
          ("lista-e2e-" + tag + "-" + std::to_string(getpid()) + "-" + std::to_string(rd() % 1000000));
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

}  // namespace e2e
