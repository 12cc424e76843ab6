// SPDX-License-Identifier: MIT
#include "tumble/gnuplot.hpp"

#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>

namespace tumble {

std::string gnuplotString(const std::string& s) {
  std::string o = "'";
  for (char c : s) {
    if (c == '\'') o += '\'';
    o += c;
  }
  return o + "'";
}

std::string shellQuote(const std::string& s) {
  std::string o = "'";
  for (char c : s) {
    if (c == '\'') o += "'\\''";
    else o += c;
  }
  return o + "'";
}

std::string gnuplotVersion() {
  std::FILE* f = popen("gnuplot --version 2>/dev/null", "r");
  if (!f) return {};
  char buf[256] = {};
  std::string line;
  if (std::fgets(buf, sizeof buf, f)) line = buf;
  const int rc = pclose(f);
  if (rc != 0) return {};
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return line;
}

std::string runGnuplot(const std::string& scriptPath, const std::string& logPath) {
  // exec: the wait status is gnuplot's own, so a signal that kills gnuplot is reported as such.
  const std::string cmd = "exec gnuplot " + shellQuote(scriptPath) + " > " + shellQuote(logPath) + " 2>&1";
  const int status = std::system(cmd.c_str());
  if (status == -1) return "the shell could not be started";
  if (WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    if (code == 0) return "";
    return "exit status " + std::to_string(code) + (code == 127 ? ", gnuplot not found" : "");
  }
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "wait status " + std::to_string(status);
}

}  // namespace tumble
