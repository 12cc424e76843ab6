// SPDX-License-Identifier: MIT
/// @file camera_path.hpp
/// Cameras that change over a video (`tumble render --camera follow`, `--camera-path FILE`):
/// a camera that follows the bulk of the bodies, smoothed over the video's frames, and key
/// frames read from a file, interpolated over the simulated time. Plain C++ (no OpenGL).
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "tumble/viewer/camera.hpp"

namespace tumble::viewer {

/// One camera per video frame that follows the bulk of the bodies: frame k is framed as
/// Camera::framing(boxes[k]) would frame it, with its target and distance averaged over the
/// neighbouring frames by a Gaussian of `sigmaFrames` frames (cut at 3 σ; at the ends the part of
/// the window that exists is used; 0 = no smoothing). An empty box takes the previous frame's
/// framing (the default camera when there is none). Yaw and pitch are the defaults.
std::vector<Camera> followCameras(const std::vector<Bounds>& boxes, double sigmaFrames);

/// A key frame of a camera path. Each value is either given or NaN ("automatic": from the
/// fixed or following framing and the command's options).
struct CameraKey {
  static constexpr float kAuto = std::numeric_limits<float>::quiet_NaN();
  double time = 0.0;  ///< simulated time, s
  float x = kAuto, y = kAuto, z = kAuto;  ///< the point looked at, m
  float yawDeg = kAuto, pitchDeg = kAuto;  ///< direction of the eye from that point, degrees
  float distance = kAuto;                  ///< from the eye to that point, m
};

/// Parses a camera path: one key per line, `time, x, y, z, yaw, pitch, distance` separated by
/// commas (time in simulated seconds, strictly increasing; an empty or missing field is
/// automatic), `#` starts a comment, blank lines are skipped and a first line that does not
/// start with a number is a header. Throws InputError naming `origin` and the line.
std::vector<CameraKey> parseCameraPath(const std::string& text, const std::string& origin);
/// parseCameraPath of a file (InputError when it cannot be read).
std::vector<CameraKey> readCameraPath(const std::string& path);

/// The camera at simulated time t: each value the path gives is interpolated linearly between
/// the nearest keys before and after t that give it (held before the first and after the last
/// such key; yaw is not wrapped, so 0 to 360 is a full turn); the others come from `automatic`.
Camera cameraOnPath(const std::vector<CameraKey>& keys, double t, const Camera& automatic);

}  // namespace tumble::viewer
