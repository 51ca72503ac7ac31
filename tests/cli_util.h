#pragma once
// Running the kerfab command line from a test: exit code, stdout, stderr, the report.
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace kerfab::test {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// `limits`: shell commands run before kerfab in the same shell, e.g. "ulimit -v 60000".
inline CliRun run_cli(const std::string& args, const fs::path& scratch,
                      const std::string& limits = "") {
  const fs::path out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  std::string cmd = limits.empty() ? std::string() : limits + "; ";
  cmd += std::string(KERFAB_CLI) + " " + args + " >" + out.string() + " 2>" + err.string() +
         " </dev/null";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

// The lines of stderr that are not progress lines ("[stage] ..." or indented details).
inline std::vector<std::string> message_lines(const std::string& err) {
  std::vector<std::string> lines;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '[' && line.rfind("  ", 0) != 0) lines.push_back(line);
  return lines;
}

inline nlohmann::json read_report(const fs::path& dir) {
  return nlohmann::json::parse(std::ifstream(dir / "report.json"));
}

/// How many of the resolve stage's changes in \p report are \p action ("plate", "outline", ...).
inline int resolve_changes(const nlohmann::json& report, const std::string& action) {
  int n = 0;
  for (const auto& c : report["resolve"]["changes"]) n += c["action"] == action ? 1 : 0;
  return n;
}

}  // namespace kerfab::test
