// SPDX-License-Identifier: MIT
// The study runner: runs the catalogue for each backend and writes report.md, summary.csv, one
// CSV per table and one PNG per plot (drawn by gnuplot from a generated script).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/gnuplot.hpp"
#include "tumble/scene.hpp"
#include "tumble/validation/study.hpp"

namespace tumble::validation::study {

bool CaseResult::pass() const {
  return std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.pass; });
}

bool StudyReport::pass() const { return failedChecks() == 0; }

std::size_t StudyReport::failedChecks() const {
  std::size_t n = 0;
  for (const auto& r : runs)
    for (const auto& c : r.result.checks) n += c.pass ? 0 : 1;
  return n;
}

std::size_t StudyReport::totalChecks() const {
  std::size_t n = 0;
  for (const auto& r : runs) n += r.result.checks.size();
  return n;
}

std::size_t StudyReport::notSupported() const {
  return static_cast<std::size_t>(
      std::count_if(runs.begin(), runs.end(), [](const CaseRun& r) { return !r.notSupported.empty(); }));
}

std::vector<Case> allCases() {
  std::vector<Case> all = physicsCases();
  for (auto& c : stabilityCases()) all.push_back(std::move(c));
  return all;
}

namespace {

namespace fs = std::filesystem;

/// A number for tables and CSV: %.6g, "nan"/"inf" spelled out.
std::string num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

/// CSV field: quoted when it holds a comma, quote or newline.
std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

/// Markdown table cell: pipes escaped, newlines flattened.
std::string mdCell(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '|') o += "\\|";
    else if (c == '\n') o += ' ';
    else o += c;
  }
  return o;
}

std::string elapsed(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f s", s);
  return buf;
}

void writeFile(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  if (!f) throw Error("cannot write " + p.string());
  f << text;
  if (!f) throw Error("cannot write " + p.string());
}

std::string tableCsv(const Table& t) {
  std::ostringstream o;
  for (std::size_t k = 0; k < t.columns.size(); ++k) o << (k ? "," : "") << csvField(t.columns[k]);
  o << "\n";
  for (const auto& row : t.rows) {
    for (std::size_t k = 0; k < row.size(); ++k) o << (k ? "," : "") << num(row[k]);
    o << "\n";
  }
  return o.str();
}

std::string tableMarkdown(const Table& t) {
  std::ostringstream o;
  o << "|";
  for (const auto& c : t.columns) o << " " << mdCell(c) << " |";
  o << "\n|";
  for (std::size_t k = 0; k < t.columns.size(); ++k) o << "---|";
  o << "\n";
  for (const auto& row : t.rows) {
    o << "|";
    for (double v : row) o << " " << num(v) << " |";
    o << "\n";
  }
  return o.str();
}

std::string checksMarkdown(const std::vector<Check>& checks, bool withCase, const std::string& caseId) {
  std::ostringstream o;
  if (withCase) o << "| case ";
  o << "| check | compared with | measured | expected | error | tolerance | unit | result |\n|";
  for (int k = 0; k < (withCase ? 9 : 8); ++k) o << "---|";
  o << "\n";
  for (const auto& c : checks) {
    if (withCase) o << "| " << mdCell(caseId) << " ";
    o << "| " << mdCell(c.name) << " | " << mdCell(c.formula) << " | " << num(c.measured) << " | "
      << (std::isnan(c.expected) ? std::string("(bound)") : num(c.expected)) << " | " << num(c.error) << " | "
      << num(c.tolerance) << " | " << mdCell(c.unit) << " | " << (c.pass ? "pass" : "**FAIL**") << " |\n";
  }
  return o.str();
}

const Table* findTable(const CaseResult& r, const std::string& name) {
  for (const auto& t : r.tables)
    if (t.name == name) return &t;
  return nullptr;
}

int columnOf(const Table& t, const std::string& name) {
  for (std::size_t k = 0; k < t.columns.size(); ++k)
    if (t.columns[k] == name) return static_cast<int>(k);
  return -1;
}

/// Label of one group value: the rotation scheme by name, otherwise "column = value".
std::string groupLabel(const std::string& column, double v) {
  if (column == "scheme" && (v == 0.0 || v == 1.0))
    return toString(v == 0.0 ? RotationScheme::Report : RotationScheme::Splitting);
  return column + " = " + num(v);
}

/// The gnuplot commands of one plot: datablocks per (y column, group), then the plot command.
/// Returns false (with a reason) when the plot names a missing table or column.
bool plotScript(const CaseResult& r, const Plot& p, const fs::path& png, std::string& script, std::string& why,
                int& blockCounter) {
  const Table* t = findTable(r, p.table);
  if (!t) {
    why = "table " + p.table + " not found";
    return false;
  }
  const int xc = columnOf(*t, p.x);
  const int gc = p.groupBy.empty() ? -1 : columnOf(*t, p.groupBy);
  if (xc < 0 || (!p.groupBy.empty() && gc < 0)) {
    why = "column " + (xc < 0 ? p.x : p.groupBy) + " not found in " + p.table;
    return false;
  }
  std::vector<double> groups;
  if (gc >= 0) {
    std::set<double> g;
    for (const auto& row : t->rows)
      if (gc < static_cast<int>(row.size()) && std::isfinite(row[gc])) g.insert(row[gc]);
    groups.assign(g.begin(), g.end());
  } else {
    groups.push_back(0.0);
  }
  std::ostringstream o;
  std::vector<std::pair<std::string, std::string>> series;  // block, title
  for (const auto& yname : p.y) {
    const int yc = columnOf(*t, yname);
    if (yc < 0) {
      why = "column " + yname + " not found in " + p.table;
      return false;
    }
    for (double g : groups) {
      const std::string block = "$d" + std::to_string(blockCounter++);
      o << block << " << EOD\n";
      std::size_t n = 0;
      for (const auto& row : t->rows) {
        if (gc >= 0 && row[gc] != g) continue;
        const double x = row[xc], y = row[yc];
        if (!std::isfinite(x) || !std::isfinite(y)) continue;
        if ((p.logx && x <= 0.0) || (p.logy && y <= 0.0)) continue;
        o << num(x) << " " << num(y) << "\n";
        ++n;
      }
      o << "EOD\n";
      if (n == 0) continue;
      std::string title = p.y.size() > 1 ? yname : std::string();
      if (gc >= 0) title += (title.empty() ? "" : ", ") + groupLabel(p.groupBy, g);
      if (title.empty()) title = yname;
      series.emplace_back(block, title);
    }
  }
  o << "set output " << gnuplotString(png.string()) << "\n";
  o << "set title " << gnuplotString(p.title) << " noenhanced\n";
  o << "set xlabel " << gnuplotString(p.xlabel) << " noenhanced\nset ylabel " << gnuplotString(p.ylabel) << " noenhanced\n";
  o << (p.logx ? "set logscale x\nset format x \"%.0e\"\n" : "unset logscale x\nset format x \"% g\"\n")
    << (p.logy ? "set logscale y\nset format y \"%.0e\"\n" : "unset logscale y\nset format y \"% g\"\n");
  if (series.empty()) {
    o << "set label 1 \"no finite data\" at graph 0.5, 0.5 center\nplot 2 notitle\nunset label 1\n";
  } else {
    o << "plot ";
    for (std::size_t k = 0; k < series.size(); ++k)
      o << (k ? ", " : "") << series[k].first << " using 1:2 with linespoints pt " << (k % 10 + 1)
        << " title " << gnuplotString(series[k].second) << " noenhanced";
    o << "\n";
  }
  script += o.str();
  return true;
}

std::string backendDir(Backend b) { return toString(b); }

}  // namespace

void printSummary(const StudyReport& report, std::FILE* out) {
  std::fprintf(out, "| backend | case | check | measured | expected | error | tolerance | unit | result |\n");
  std::fprintf(out, "|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& run : report.runs) {
    if (!run.notSupported.empty())
      std::fprintf(out, "| %s | %s | (not run) | | | | | | not supported: %s |\n", toString(run.backend),
                   run.result.id.c_str(), mdCell(run.notSupported).c_str());
    for (const auto& c : run.result.checks)
      std::fprintf(out, "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", toString(run.backend),
                   run.result.id.c_str(), mdCell(c.name).c_str(), num(c.measured).c_str(),
                   std::isnan(c.expected) ? "(bound)" : num(c.expected).c_str(), num(c.error).c_str(),
                   num(c.tolerance).c_str(), c.unit.c_str(), c.pass ? "pass" : "FAIL");
  }
}

StudyReport runStudy(const std::vector<Case>& cases, const std::vector<Backend>& backends, const StudyOptions& o) {
  std::vector<const Case*> chosen;
  for (const auto& id : o.caseIds) {
    if (std::none_of(cases.begin(), cases.end(), [&](const Case& c) { return c.id == id; })) {
      std::string known;
      for (const auto& c : cases) known += (known.empty() ? "" : ", ") + c.id;
      throw Error("unknown case \"" + id + "\"; known cases: " + known);
    }
  }
  for (const auto& c : cases)
    if (o.caseIds.empty() || std::find(o.caseIds.begin(), o.caseIds.end(), c.id) != o.caseIds.end())
      chosen.push_back(&c);

  StudyReport report;
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  for (Backend b : backends) {
    for (const Case* c : chosen) {
      CaseContext ctx;
      ctx.backend = b;
      ctx.depth = o.depth;
      ctx.seed = o.seed;
      if (o.progress) {
        std::fprintf(stderr, "validate: %-22s %-4s ...", c->id.c_str(), toString(b));
        std::fflush(stderr);
      }
      const auto c0 = clock::now();
      CaseRun run;
      run.backend = b;
      try {
        run.result = c->run(ctx);
      } catch (const NotSupported& e) {
        run.result = CaseResult{};
        run.notSupported = e.what();
      } catch (const std::exception& e) {
        run.result = CaseResult{};
        Check k;
        k.name = "case ran to completion";
        k.formula = std::string("threw: ") + e.what();
        k.expected = std::nan("");
        k.measured = k.error = 1.0;
        k.tolerance = 0.0;
        k.unit = "-";
        k.pass = false;
        run.result.checks.push_back(k);
      }
      if (run.result.id.empty()) run.result.id = c->id;
      if (run.result.title.empty()) run.result.title = c->id;
      run.seconds = std::chrono::duration<double>(clock::now() - c0).count();
      if (o.progress) {
        std::size_t failed = 0;
        for (const auto& k : run.result.checks) failed += k.pass ? 0 : 1;
        if (!run.notSupported.empty())
          std::fprintf(stderr, " not supported on %s: %s\n", toString(b), run.notSupported.c_str());
        else
          std::fprintf(stderr, " %s, %zu checks, %zu failed\n", elapsed(run.seconds).c_str(), run.result.checks.size(),
                       failed);
      }
      report.runs.push_back(std::move(run));
    }
  }
  report.seconds = std::chrono::duration<double>(clock::now() - t0).count();
  if (!o.outDir.empty()) writeReport(report, o);
  return report;
}

void writeReport(StudyReport& report, const StudyOptions& o) {
  const fs::path dir(o.outDir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw Error("cannot create report folder " + o.outDir + ": " + ec.message());

  std::vector<Backend> backends;
  for (const auto& r : report.runs)
    if (std::find(backends.begin(), backends.end(), r.backend) == backends.end()) backends.push_back(r.backend);
  for (Backend b : backends) {
    fs::create_directories(dir / backendDir(b), ec);
    if (ec) throw Error("cannot create " + (dir / backendDir(b)).string() + ": " + ec.message());
  }

  // summary.csv: every check.
  {
    std::ostringstream s;
    s << "case,backend,check,measured,expected,error,tolerance,unit,pass,formula\n";
    for (const auto& r : report.runs)
      for (const auto& c : r.result.checks)
        s << csvField(r.result.id) << "," << toString(r.backend) << "," << csvField(c.name) << "," << num(c.measured)
          << "," << num(c.expected) << "," << num(c.error) << "," << num(c.tolerance) << "," << csvField(c.unit) << ","
          << (c.pass ? 1 : 0) << "," << csvField(c.formula) << "\n";
    writeFile(dir / "summary.csv", s.str());
  }
  // Tables.
  for (const auto& r : report.runs)
    for (const auto& t : r.result.tables)
      writeFile(dir / backendDir(r.backend) / (r.result.id + "_" + t.name + ".csv"), tableCsv(t));

  // Plots: one gnuplot script for the whole report.
  const std::string version = gnuplotVersion();
  std::map<std::string, std::string> plotProblems;  // png relative path -> why it is missing
  std::set<std::string> drawn;
  report.plotsDrawn = false;
  if (version.empty()) {
    report.plotNote = "plots skipped: the gnuplot program was not found or did not run (install gnuplot-nox)";
  } else {
    std::string script =
        "set terminal pngcairo size 900,600 noenhanced font \"sans,11\"\nset grid\nset key outside right top\n";
    int blocks = 0;
    std::vector<std::string> wanted;
    for (const auto& r : report.runs)
      for (const auto& p : r.result.plots) {
        const std::string rel = backendDir(r.backend) + "/" + r.result.id + "_" + p.name + ".png";
        std::string why;
        if (plotScript(r.result, p, dir / rel, script, why, blocks)) wanted.push_back(rel);
        else plotProblems[rel] = why;
      }
    const fs::path gp = dir / "plots.gp";
    writeFile(gp, script);
    // A PNG counts as drawn only if this gnuplot run wrote it: remove any left by an earlier
    // report in the same folder.
    std::vector<std::string> fresh;
    for (const auto& rel : wanted) {
      fs::remove(dir / rel, ec);
      if (ec) plotProblems[rel] = "cannot remove the old " + rel + ": " + ec.message();
      else fresh.push_back(rel);
    }
    wanted = std::move(fresh);
    const std::string status = runGnuplot(gp.string(), (dir / "plots.log").string());
    for (const auto& rel : wanted)
      if (fs::exists(dir / rel, ec) && fs::file_size(dir / rel, ec) > 0 && !ec) drawn.insert(rel);
      else plotProblems[rel] = "gnuplot did not write it (see plots.log)";
    report.plotsDrawn = !drawn.empty();
    report.plotNote = version + (status.empty() ? "" : " (" + status + ", see plots.log)") + "; script plots.gp";
  }

  // report.md
  std::ostringstream m;
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  m << "# tumble validation study\n\n";
  m << "- date: " << date << "\n";
  if (!o.command.empty()) m << "- command: `" << o.command << "`\n";
  m << "- depth: " << (o.depth == Depth::Quick ? "quick" : "full") << ", seed " << o.seed << "\n";
  m << "- pipelines:";
  for (Backend b : backends) m << " " << toString(b);
  m << "\n- wall time: " << elapsed(report.seconds) << "\n";
  m << "- plots: " << (version.empty() ? report.plotNote : "drawn by " + report.plotNote) << "\n";
  m << "- result: **" << (report.pass() ? "PASSED" : "FAILED") << "**, " << report.totalChecks() - report.failedChecks()
    << " of " << report.totalChecks() << " checks within tolerance";
  if (report.notSupported() > 0)
    m << "; " << report.notSupported() << " case runs not supported by their pipeline yet (not run)";
  m << "\n\n";
  m << "Every number is in `summary.csv` (checks) and in `<pipeline>/<case>_<table>.csv` (tables). "
       "The tolerance of each check is stated with it; `error` is the quantity compared with it.\n\n";
  for (Backend b : backends) {
    m << "## Summary: " << toString(b) << "\n\n";
    m << "| case | checks | failed | wall time |\n|---|---|---|---|\n";
    for (const auto& r : report.runs) {
      if (r.backend != b) continue;
      std::size_t failed = 0;
      for (const auto& c : r.result.checks) failed += c.pass ? 0 : 1;
      m << "| [" << mdCell(r.result.title) << "](#" << toString(b) << "-" << r.result.id << ") | "
        << r.result.checks.size() << " | "
        << (r.notSupported.empty() ? std::to_string(failed) : "not supported: " + mdCell(r.notSupported)) << " | "
        << elapsed(r.seconds) << " |\n";
    }
    m << "\n";
  }
  for (Backend b : backends) {
    for (const auto& r : report.runs) {
      if (r.backend != b) continue;
      m << "<a id=\"" << toString(b) << "-" << r.result.id << "\"></a>\n";
      m << "## " << r.result.title << " (" << toString(b) << ", `" << r.result.id << "`)\n\n";
      if (!r.result.summary.empty()) m << r.result.summary << "\n\n";
      if (!r.notSupported.empty()) m << "Not run: " << mdCell(r.notSupported) << "\n\n";
      m << checksMarkdown(r.result.checks, false, r.result.id) << "\n";
      for (const auto& t : r.result.tables) {
        const std::string rel = backendDir(b) + "/" + r.result.id + "_" + t.name + ".csv";
        m << "Table `" << t.name << "` ([CSV](" << rel << ")):\n\n";
        if (t.rows.size() <= 60) m << tableMarkdown(t) << "\n";
        else m << "(" << t.rows.size() << " rows; see the CSV)\n\n";
      }
      for (const auto& p : r.result.plots) {
        const std::string rel = backendDir(b) + "/" + r.result.id + "_" + p.name + ".png";
        if (drawn.count(rel)) {
          m << "![" << mdCell(p.title) << "](" << rel << ")\n\n";
        } else {
          const auto it = plotProblems.find(rel);
          m << "(plot `" << p.name << "` not drawn: " << (it != plotProblems.end() ? it->second : report.plotNote)
            << ")\n\n";
        }
      }
    }
  }
  writeFile(dir / "report.md", m.str());
}

}  // namespace tumble::validation::study
