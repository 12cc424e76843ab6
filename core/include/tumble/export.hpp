// SPDX-License-Identifier: MIT
/// @file export.hpp
/// A recording as files other tools read (docs/export.md): one VTK XML PolyData file (.vtp) per
/// frame plus a ParaView collection (.pvd), with the ground and the walls as parts of their own,
/// or one CSV per frame plus an index (particles only); and optionally the contacts with their
/// forces, a file per frame of their own.
#pragma once
#include <cstddef>
#include <functional>
#include <string>

#include "tumble/recording.hpp"

namespace tumble {

enum class ExportFormat { Vtk, Csv };

struct ExportOptions {
  ExportFormat format = ExportFormat::Vtk;
  /// Every k-th frame from the first (frames 0, k, 2k, …), k ≥ 1.
  std::size_t every = 1;
  /// File names start with this (default "frame"; `tumble export` passes the recording's name
  /// without its extension).
  std::string name;
  /// Also the contacts with their forces (a recording with contact forces): NAME_contacts_K.vtp
  /// (a line per contact between the two particles' centres, its forces as cell data) or
  /// NAME_contacts_K.csv per frame.
  bool contacts = false;
  /// Called after each frame file with (frames written, frames to write).
  std::function<void(std::size_t, std::size_t)> progress;
  /// Polled before each frame; true stops the export (the files written so far stay, the
  /// collection or index is written for them).
  std::function<bool()> stop;
};

/// What exportRecording wrote.
struct ExportResult {
  std::size_t frames = 0;   ///< frame files
  std::string index;        ///< the .pvd collection or the CSV index
  bool stopped = false;     ///< options.stop asked to stop
};

/// The longest name prefix: NAME_0000000.vtp and its temporary (.part-XXXXXX) fit in 255 bytes
/// with room for a billion frames.
inline constexpr std::size_t kMaxExportName = 200;

/// Why `name` cannot be a file name prefix ('/', a control character, not UTF-8, empty, longer
/// than kMaxExportName), or "" when it can.
std::string exportNameProblem(const std::string& name);

/// The name exportRecording gives frame k's file when there are `numFrames` frames to write:
/// NAME_k with k zero-padded to at least 6 digits, then ".vtp" or ".csv".
std::string exportFrameName(const std::string& name, std::size_t k, std::size_t numFrames, ExportFormat format);

/// Writes the selected frames of `reader` into the folder `dir` (created when missing, with its
/// parents). VTK: the recording's walls (version 2) as triangles, NAME_walls.vtp for all frames
/// when none moves, else NAME_walls_K.vtp per frame, posed at its time (wallPose). Particle positions are x = X + R(Q) u, the expression every pipeline uses
/// (kernels/integrate.hpp particlePosition), so they are the simulation's own bits. Each file is
/// written atomically (output_file.hpp); files of the same names are replaced, others are left
/// alone. An index of the same name from an earlier export is removed first; it is written for
/// this export's frames at the end, and also when a frame fails (for the frames written before),
/// so it never lists another recording's frames. Throws tumble::Error (a frame the reader rejects:
/// tumble::InputError; options.contacts for a recording without contact forces, before any file
/// is written).
ExportResult exportRecording(RecordingReader& reader, const std::string& dir, const ExportOptions& options);

}  // namespace tumble
