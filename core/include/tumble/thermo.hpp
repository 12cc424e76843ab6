// SPDX-License-Identifier: MIT
/// @file thermo.hpp
/// Time series of a run (docs/thermo.md): energies, contacts, overlaps, speeds and momenta at
/// regular steps, as RunGuard measures them, written as CSV by `tumble run --thermo FILE`.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>

#include "tumble/kernels/energy.hpp"

namespace tumble {

class OutputFile;

/// The quantities of one measurement (RunGuard::sample()). Energies in J, in the conventions of
/// the guard's energy E (guard.hpp); positions in world coordinates.
struct ThermoSample {
  std::uint64_t step = 0;           ///< steps since the start of the run
  double time = 0.0;                ///< simulated time (s)
  double kineticTranslation = 0.0;  ///< Σ ½ M |V|²
  double kineticRotation = 0.0;     ///< Σ ½ ω·L over the bodies of more than one sphere
  double gravity = 0.0;             ///< −Σ M g·X (zero at the world origin)
  double pullPotential = 0.0;       ///< Σ ½ m κ x² (and y) of the x and y pulls that are on
  double springs = 0.0;             ///< Σ ½ k δ² over the particle contacts and the plane contacts (ground, walls)
  double pullWork = 0.0;            ///< work of the swirl pull on the bodies since the run started
  std::uint64_t contacts = 0;       ///< particle pairs in contact (those of the last step)
  double maxOverlap = 0.0;          ///< largest overlap δ / smaller radius (pairs, ground and walls)
  double maxSpeed = 0.0;            ///< largest centre-of-mass speed (m/s)
  double momentum[3] = {0, 0, 0};   ///< Σ M V (kg m/s)
  double angularMomentum[3] = {0, 0, 0};  ///< Σ (X × M V + L) about the world origin (kg m²/s)
  bool finite = true;               ///< false when the state is not finite (every value is then NaN in the file)
  /// The energy tally (Pipeline::setEnergyTally; docs/thermo.md#energy-balance) since the time
  /// series began: dissipated by the normal dashpots, by the tangential dashpots while contacts
  /// stick, by friction (slip, rolling resistance, and what the stick springs hold), by JKR's
  /// necks (cohesion hysteresis), and the work moving walls did. NaN where the run keeps no tally.
  double dissipatedNormal = std::numeric_limits<double>::quiet_NaN();
  double dissipatedTangential = std::numeric_limits<double>::quiet_NaN();
  double dissipatedFriction = std::numeric_limits<double>::quiet_NaN();
  double dissipatedCohesion = std::numeric_limits<double>::quiet_NaN();
  double wallWork = std::numeric_limits<double>::quiet_NaN();

  /// The mechanical energy E: kinetic + gravity + pull potential + springs.
  double energy() const { return kineticTranslation + kineticRotation + gravity + pullPotential + springs; }
  /// E + dissipated − the work put in (walls, the swirl pull): constant but for the
  /// integration's error where every term is counted (NaN without the tally).
  double balance() const {
    return energy() + ((dissipatedNormal + dissipatedTangential + dissipatedFriction) + dissipatedCohesion) -
           (wallWork + pullWork);
  }
};

/// The energy tally's columns of a run that keeps none.
inline constexpr EnergyTotals kNoEnergyTally{std::numeric_limits<double>::quiet_NaN(),
                                             std::numeric_limits<double>::quiet_NaN(),
                                             std::numeric_limits<double>::quiet_NaN(),
                                             std::numeric_limits<double>::quiet_NaN(),
                                             std::numeric_limits<double>::quiet_NaN()};

/// s with the energy tally's sums e (its five columns; StepStats::energy).
inline ThermoSample withEnergy(ThermoSample s, const EnergyTotals& e) {
  s.dissipatedNormal = e.normal;
  s.dissipatedTangential = e.tangential;
  s.dissipatedFriction = e.friction;
  s.dissipatedCohesion = e.cohesion;
  s.wallWork = e.wall;
  return s;
}

/// Writes samples as CSV (header thermoHeader()), one line per sample, flushed at once. Until
/// close() the rows go to the live name `FILE.part` (readable, as the finished file will be:
/// `tail -f FILE.part`, `tumble plot FILE`, which plots the live name while it is there);
/// close() renames it into place; the destructor does too, so an interrupted run keeps its rows.
/// A second run writing the same FILE is refused while the first's `FILE.part` is there.
/// Times are printed at the step's precision (formatTime). Thread safety: none.
class ThermoWriter {
 public:
  /// `dt`: the time step, whose decimals the times are printed with. Throws tumble::Error.
  ThermoWriter(const std::string& path, float dt);
  ~ThermoWriter();
  ThermoWriter(const ThermoWriter&) = delete;
  ThermoWriter& operator=(const ThermoWriter&) = delete;
  void write(const ThermoSample& s);  ///< throws tumble::Error (a full disk: with the reason)
  void close();                       ///< throws tumble::Error
  /// Removes the live file: FILE stays as it was (a run that could not start). Never throws.
  void abandon() noexcept;
  std::uint64_t rows() const { return m_rows; }
  const std::string& path() const { return m_path; }

 private:
  std::string m_path;
  std::unique_ptr<OutputFile> m_out;
  std::uint64_t m_rows = 0;
  std::uint64_t m_complete = 0;  ///< bytes of the header and the whole rows
  bool m_torn = false;           ///< a failed row could not be cut off again
  float m_dt;
};

/// A simulated time as text at the precision the step allows: with the decimals of the shortest
/// decimal that is `dt` in single precision (dt = 5e-05: 5 decimals, so 200 steps print 0.01,
/// not their sum in binary, 0.009999999747), trailing zeros dropped; %.10g where dt needs more
/// than 12 decimals.
std::string formatTime(double time, float dt);

/// The CSV header line, without the newline: kThermoColumns names.
const char* thermoHeader();

inline constexpr std::size_t kThermoColumns = 24;
inline constexpr std::size_t kThermoStepColumn = 0, kThermoContactsColumn = 9;  ///< the two counts
inline constexpr std::size_t kThermoTimeColumn = 1;

/// A row's values in thermoHeader()'s order; NaN, except for the step and the time, when the
/// state is not finite.
std::array<double, kThermoColumns> thermoRow(const ThermoSample& s);

}  // namespace tumble
