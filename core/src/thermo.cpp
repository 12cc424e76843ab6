// SPDX-License-Identifier: MIT
#include "tumble/thermo.hpp"

#include <array>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "tumble/error.hpp"
#include "tumble/output_file.hpp"

namespace tumble {

const char* thermoHeader() {
  return "step,time,kinetic_translation,kinetic_rotation,potential_gravity,potential_pulls,potential_contacts,"
         "energy,pull_work,contacts,max_overlap,max_speed,px,py,pz,lx,ly,lz";
}

ThermoWriter::ThermoWriter(const std::string& path) : m_path(path), m_out(std::make_unique<OutputFile>(path)) {
  std::string h = thermoHeader();
  h += '\n';
  if (!writeFully(m_out->file(), h.data(), h.size()) || std::fflush(m_out->file()) != 0)
    throw Error("cannot write " + path + ": " + std::strerror(errno != 0 ? errno : EIO));
}

ThermoWriter::~ThermoWriter() {
  if (!m_out) return;
  try {
    m_out->commit();
  } catch (const Error&) {  // the rows stay in the temporary; nothing better to do here
  }
}

std::array<double, kThermoColumns> thermoRow(const ThermoSample& s) {
  const double nan = std::nan("");
  auto v = [&](double x) { return s.finite ? x : nan; };
  return {static_cast<double>(s.step), s.time, v(s.kineticTranslation), v(s.kineticRotation), v(s.gravity),
          v(s.pullPotential), v(s.springs), v(s.energy()), v(s.pullWork), static_cast<double>(s.contacts),
          v(s.maxOverlap), v(s.maxSpeed), v(s.momentum[0]), v(s.momentum[1]), v(s.momentum[2]),
          v(s.angularMomentum[0]), v(s.angularMomentum[1]), v(s.angularMomentum[2])};
}

void ThermoWriter::write(const ThermoSample& s) {
  if (!m_out) throw Error("thermo file already closed");
  const std::array<double, kThermoColumns> row = thermoRow(s);
  std::string line;
  char buf[40];
  for (std::size_t c = 0; c < kThermoColumns; ++c) {
    // The counts as integers; the rest with ten significant digits (%.10g), enough for
    // differences of a part in 10^9.
    if (c == kThermoStepColumn) std::snprintf(buf, sizeof buf, "%llu", static_cast<unsigned long long>(s.step));
    else if (c == kThermoContactsColumn) std::snprintf(buf, sizeof buf, "%llu", static_cast<unsigned long long>(s.contacts));
    else std::snprintf(buf, sizeof buf, "%.10g", row[c]);
    if (c > 0) line += ',';
    line += buf;
  }
  line += '\n';
  if (!writeFully(m_out->file(), line.data(), line.size()) || std::fflush(m_out->file()) != 0)
    throw Error("cannot write " + m_out->path() + ": " + std::strerror(errno != 0 ? errno : EIO));
  ++m_rows;
}

void ThermoWriter::close() {
  if (!m_out) return;
  std::unique_ptr<OutputFile> out = std::move(m_out);
  out->commit();
}

}  // namespace tumble
