#pragma once
// Runs the built icobrdf program in a child process and captures exit code, stdout and stderr.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace icobrdf::test {

struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs a shell command line with stdout and stderr captured to temporary files (stdin is /dev/null).
inline CliResult run_shell(const std::string& command) {
  char out_tmpl[] = "/tmp/icobrdf_cli_outXXXXXX";
  char err_tmpl[] = "/tmp/icobrdf_cli_errXXXXXX";
  const int fo = mkstemp(out_tmpl), fe = mkstemp(err_tmpl);
  close(fo);
  close(fe);
  const std::string cmd = command + " >" + std::string(out_tmpl) + " 2>" + std::string(err_tmpl) + " </dev/null";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out_tmpl);
  r.err = slurp(err_tmpl);
  std::remove(out_tmpl);
  std::remove(err_tmpl);
  return r;
}

// `icobrdf args...`, each argument quoted, after `prefix` (e.g. "mpirun -np 2").
inline std::string cli_command(const std::vector<std::string>& args, const std::string& prefix = "") {
  std::string cmd = prefix.empty() ? "" : prefix + " ";
  cmd += shell_quote(ICOBRDF_CLI_PATH);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  return cmd;
}

// Runs `icobrdf args...` with stdout and stderr captured.
inline CliResult run_cli(const std::vector<std::string>& args) { return run_shell(cli_command(args)); }

// The first value column of `icobrdf eval SOURCE --at PAIRS_CSV` (one value per pair); empty on failure.
inline std::vector<double> eval_first_column(const std::string& source, const std::string& pairs_csv) {
  const CliResult r = run_cli({"eval", source, "--at", pairs_csv});
  std::vector<double> v;
  if (r.exit_code != 0) return v;
  size_t pos = r.out.find('\n');  // header
  while (pos != std::string::npos && pos + 1 < r.out.size()) {
    const size_t next = r.out.find('\n', pos + 1);
    v.push_back(std::stod(r.out.substr(pos + 1, r.out.find(',', pos + 1) - pos - 1)));
    pos = next;
  }
  return v;
}

// A CSV of numbers as `icobrdf eval` prints it: the header line goes to `header`, the rows are returned.
inline std::vector<std::vector<double>> parse_value_csv(const std::string& text, std::string& header) {
  std::istringstream in(text);
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> row;
    std::istringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

// A fresh temporary directory, removed with its content on destruction.
struct TempDir {
  std::string path;
  TempDir() {
    char tmpl[] = "/tmp/icobrdf_testXXXXXX";
    path = mkdtemp(tmpl);
  }
  ~TempDir() { std::system(("rm -rf " + shell_quote(path)).c_str()); }
  std::string file(const std::string& name) const { return path + "/" + name; }
};

}  // namespace icobrdf::test
