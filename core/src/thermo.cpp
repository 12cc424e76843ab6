// SPDX-License-Identifier: MIT
#include "tumble/thermo.hpp"

#include <array>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

#include "tumble/error.hpp"
#include "tumble/output_file.hpp"

namespace tumble {

const char* thermoHeader() {
  return "step,time,kinetic_translation,kinetic_rotation,potential_gravity,potential_pulls,potential_contacts,"
         "energy,pull_work,contacts,max_overlap,max_speed,px,py,pz,lx,ly,lz,dissipated_normal,dissipated_tangential,"
         "dissipated_friction,dissipated_cohesion,wall_work,balance";
}

std::string formatTime(double time, float dt) {
  char buf[48];
  int decimals = -1;
  for (int d = 0; d <= 12 && decimals < 0; ++d) {
    const double scale = std::pow(10.0, d);
    if (static_cast<float>(std::round(double(dt) * scale) / scale) == dt) decimals = d;
  }
  if (decimals < 0 || !std::isfinite(time) || std::fabs(time) >= 1e15) {
    std::snprintf(buf, sizeof buf, "%.10g", time);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%.*f", decimals, time);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

ThermoWriter::ThermoWriter(const std::string& path, float dt)
    : m_path(path), m_out(std::make_unique<OutputFile>(path, OutputFile::Temporary::Live)), m_dt(dt) {
  std::setvbuf(m_out->file(), nullptr, _IONBF, 0);  // each row is one write; a failed one leaves nothing buffered
  std::string h = thermoHeader();
  h += '\n';
  int error = 0;
  if (appendWhole(*m_out, h.data(), h.size(), m_complete, error) != Appended::Whole)
    throw Error("cannot write " + path + ": " + std::strerror(error));
}

ThermoWriter::~ThermoWriter() {
  if (!m_out) return;
  try {
    close();
  } catch (const Error&) {  // the rows stay in the temporary; nothing better to do here
  }
}

std::array<double, kThermoColumns> thermoRow(const ThermoSample& s) {
  const double nan = std::nan("");
  auto v = [&](double x) { return s.finite ? x : nan; };
  return {static_cast<double>(s.step), s.time, v(s.kineticTranslation), v(s.kineticRotation), v(s.gravity),
          v(s.pullPotential), v(s.springs), v(s.energy()), v(s.pullWork), static_cast<double>(s.contacts),
          v(s.maxOverlap), v(s.maxSpeed), v(s.momentum[0]), v(s.momentum[1]), v(s.momentum[2]),
          v(s.angularMomentum[0]), v(s.angularMomentum[1]), v(s.angularMomentum[2]), v(s.dissipatedNormal),
          v(s.dissipatedTangential), v(s.dissipatedFriction), v(s.dissipatedCohesion), v(s.wallWork), v(s.balance())};
}

void ThermoWriter::write(const ThermoSample& s) {
  if (!m_out) throw Error("thermo file already closed");
  const std::array<double, kThermoColumns> row = thermoRow(s);
  std::string line;
  char buf[40];
  for (std::size_t c = 0; c < kThermoColumns; ++c) {
    // The counts as integers, the time at the step's precision; the rest with ten significant
    // digits (%.10g), enough for differences of a part in 10^9.
    if (c == kThermoStepColumn) std::snprintf(buf, sizeof buf, "%llu", static_cast<unsigned long long>(s.step));
    else if (c == kThermoContactsColumn) std::snprintf(buf, sizeof buf, "%llu", static_cast<unsigned long long>(s.contacts));
    else if (c == kThermoTimeColumn) std::snprintf(buf, sizeof buf, "%s", formatTime(s.time, m_dt).c_str());
    else std::snprintf(buf, sizeof buf, "%.10g", row[c]);
    if (c > 0) line += ',';
    line += buf;
  }
  line += '\n';
  if (m_torn) throw Error("cannot write " + m_out->writingTo() + ": an earlier row could not be cut off");
  // A row that cannot be written whole (a full disk) is cut off again: the file keeps its whole
  // rows, and close() still puts it in place.
  int error = 0;
  if (const Appended a = appendWhole(*m_out, line.data(), line.size(), m_complete, error); a != Appended::Whole) {
    m_torn = a == Appended::Torn;
    throw Error("cannot write " + (m_torn ? m_out->writingTo() : m_path) + ": " + std::strerror(error) +
                (m_torn ? "" : "; it keeps the " + std::to_string(m_rows) + " whole rows written before"));
  }
  ++m_rows;
}

void ThermoWriter::abandon() noexcept {
  if (m_out) std::exchange(m_out, nullptr)->abandon();
}

void ThermoWriter::close() {
  if (!m_out) return;
  std::unique_ptr<OutputFile> out = std::move(m_out);
  if (m_torn) {  // a torn row is left where the error said, never renamed into place
    out->keep();
    return;
  }
  out->commit();
}

}  // namespace tumble
