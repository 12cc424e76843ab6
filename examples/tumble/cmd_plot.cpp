// SPDX-License-Identifier: MIT
// `tumble plot FILE.csv`: draws a time series (`tumble run --thermo`, docs/thermo.md) with
// gnuplot into a PNG. Default: three panels (the energies; the mechanical energy; the contacts
// and the largest overlap); --columns draws the named columns in one panel.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

#include "commands.hpp"
#include "tumble/error.hpp"
#include "tumble/gnuplot.hpp"
#include "tumble/output_file.hpp"

namespace tumble::cli {
namespace {

struct PlotOptions {
  std::string file;
  std::string out;
  std::vector<std::string> columns;
  std::string x = "time";
  std::string size = "1000x900";
};

// The header's column names; `rows` counts the data lines after it.
std::vector<std::string> headerOf(const std::string& path, std::size_t& rows, std::string& last) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open the time series (write one with tumble run --thermo FILE.csv)");
  std::string line;
  if (!std::getline(in, line) || line.empty())
    throw InputError(path, 1, "empty: expected a header line such as " + std::string("step,time,..."));
  std::vector<std::string> cols;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, ',');) cols.push_back(c);
  rows = 0;
  for (std::string row; std::getline(in, row);)
    if (!row.empty()) {
      ++rows;
      last = row;
    }
  return cols;
}

// A path as gnuplot must get it: it reads a name starting with '<' as a command to run and one
// starting with '|' (for `set output`) as a pipe, and '-' as inline data, so a relative path
// gets "./" in front.
std::string gnuplotPath(const std::string& p) { return gnuplotString(!p.empty() && p[0] == '/' ? p : "./" + p); }

struct Panel {
  std::string ylabel;
  std::vector<std::string> columns;
  std::vector<std::string> y2;  // on the right-hand axis
  std::string y2label;
};

void plot(const PlotOptions& o) {
  // A run writing FILE has its rows in the live name FILE.part (next to FILE's target, links
  // followed; docs/thermo.md): those are plotted, newer than a FILE of an earlier run.
  std::error_code ec;
  const std::string livePath = outputTarget(o.file) + ".part";
  const bool live = std::filesystem::is_regular_file(livePath, ec);
  const std::string data = live ? livePath : o.file;
  std::size_t rows = 0;
  std::string lastRow;  // the file's last row
  const std::vector<std::string> header = headerOf(data, rows, lastRow);
  std::string list;
  for (const auto& c : header) list += (list.empty() ? "" : ", ") + c;
  auto need = [&](const std::string& c, const char* what) {
    for (const auto& h : header)
      if (h == c) return;
    throw InputError(data, 1, std::string("no column '") + c + "' (" + what + "); the columns are: " + list);
  };
  need(o.x, "--x");
  if (rows == 0) throw InputError(data, 2, "no data rows after the header: nothing to draw");
  std::vector<Panel> panels;
  if (!o.columns.empty()) {
    panels.push_back(Panel{"", o.columns, {}, ""});
  } else {
    // The balance beside the energy where the file has it as a number (a series written
    // without --energy-balance has nan there; one written before it has no such column).
    bool balance = false;
    if (const auto at = std::find(header.begin(), header.end(), "balance"); at != header.end()) {
      std::stringstream ss(lastRow);
      std::vector<std::string> fields;
      for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
      const auto k = static_cast<std::size_t>(at - header.begin());
      balance = k < fields.size() && !fields[k].empty() && fields[k] != "nan";
    }
    panels = {Panel{"energy (J)", {"kinetic_translation", "kinetic_rotation", "potential_contacts", "pull_work"}, {}, ""},
              balance ? Panel{"energy and balance (J)", {"energy", "balance"}, {}, ""}
                      : Panel{"mechanical energy (J)", {"energy"}, {}, ""},
              Panel{"contacts", {"contacts"}, {"max_overlap"}, "largest overlap / radius"}};
  }
  for (const Panel& p : panels) {
    for (const auto& c : p.columns) need(c, o.columns.empty() ? "a thermo file from tumble run --thermo has it" : "--columns");
    for (const auto& c : p.y2) need(c, "a thermo file from tumble run --thermo has it");
  }
  const std::size_t xAt = o.size.find('x');
  const auto width = parseCount(o.size.substr(0, xAt), 100, 10000);
  const auto height = xAt == std::string::npos ? std::nullopt : parseCount(o.size.substr(xAt + 1), 100, 10000);
  if (!width || !height) throw Error("--size " + o.size + ": expected WIDTHxHEIGHT, each from 100 to 10000, e.g. 1000x900");
  if (gnuplotVersion().empty()) throw Error("tumble plot needs gnuplot (Debian: apt-get install gnuplot-nox)");

  const std::string out = o.out.empty() ? (o.file.size() > 4 && o.file.substr(o.file.size() - 4) == ".csv"
                                               ? o.file.substr(0, o.file.size() - 4) + ".png"
                                               : o.file + ".png")
                                        : o.out;
  refuseSameFile({{"time series", data}, {"-o", out}});
  OutputFile png(out);  // gnuplot writes the temporary; commit() renames it into place
  std::ostringstream gp;
  gp << "set terminal pngcairo size " << *width << "," << *height << " noenhanced font 'sans,10'\n"
     << "set output " << gnuplotPath(png.writingTo()) << "\n"
     << "set datafile separator ','\nset datafile columnheaders\nset grid\nset key top right\n"
     << "set autoscale xfix\n";
  if (panels.size() > 1) gp << "set multiplot layout " << panels.size() << ",1 title " << gnuplotString(o.file) << "\n";
  else gp << "set title " << gnuplotString(o.file) << "\n";
  const std::string xlabel = o.x == "time" ? "time (s)" : o.x;
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const Panel& p = panels[k];
    gp << "set ylabel " << gnuplotString(p.ylabel) << "\n";
    if (k + 1 == panels.size()) gp << "set xlabel " << gnuplotString(xlabel) << "\n";
    if (!p.y2.empty()) gp << "set y2label " << gnuplotString(p.y2label) << "\nset y2tics\nset ytics nomirror\n";
    gp << "plot ";
    bool first = true;
    auto series = [&](const std::string& c, const char* axes) {
      gp << (first ? "" : ", ") << gnuplotPath(data) << " using (column(" << gnuplotString(o.x) << ")):(column("
         << gnuplotString(c) << ")) axes " << axes << " with lines lw 1.5 title " << gnuplotString(c);
      first = false;
    };
    for (const auto& c : p.columns) series(c, "x1y1");
    for (const auto& c : p.y2) series(c, "x1y2");
    gp << "\n";
    if (!p.y2.empty()) gp << "unset y2label\nunset y2tics\nset ytics mirror\n";
  }
  if (panels.size() > 1) gp << "unset multiplot\n";
  gp << "set output\n";

  // The script and gnuplot's log go next to the PNG's temporary and are removed afterwards.
  const std::string script = png.writingTo() + ".gp", log = png.writingTo() + ".log";
  {
    std::ofstream s(script);
    s << gp.str();
    if (!s) throw Error("cannot write the gnuplot script " + script);
  }
  const std::string status = runGnuplot(script, log);
  std::string why;
  if (!status.empty()) {
    std::ifstream l(log);
    std::getline(l, why, '\0');
  }
  std::remove(script.c_str());
  std::remove(log.c_str());
  if (!status.empty()) throw Error("gnuplot failed (" + status + ") drawing " + data + ":\n" + why);
  png.commit();
  if (live)
    std::fprintf(stderr, "tumble plot: %s (the %zu rows of %s: a run writing %s, or one stopped before it finished)\n",
                 out.c_str(), rows, data.c_str(), o.file.c_str());
  else
    std::fprintf(stderr, "tumble plot: %s\n", out.c_str());
}

}  // namespace

void addPlot(CLI::App& app) {
  auto o = std::make_shared<PlotOptions>();
  CLI::App* c = app.add_subcommand("plot", "Draw a time series (tumble run --thermo FILE.csv) into a PNG with gnuplot");
  c->add_option("thermo", o->file, "The time series, e.g. thermo.csv (docs/thermo.md)")->required();
  c->add_option("-o,--output", o->out, "PNG to write (default: the CSV's name with .png)");
  c->add_option("--columns", o->columns,
                "Columns to draw in one panel, e.g. energy,kinetic_rotation (default: three panels: the energies, "
                "the mechanical energy, the contacts and the largest overlap)")
      ->delimiter(',');
  c->add_option("--x", o->x, "Column on the horizontal axis: time (default) or step");
  c->add_option("--size", o->size, "Image size WIDTHxHEIGHT in pixels (default 1000x900)");
  c->callback([o] { plot(*o); });
}

}  // namespace tumble::cli
