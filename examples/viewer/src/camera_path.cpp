// SPDX-License-Identifier: MIT
#include "tumble/viewer/camera_path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "text.hpp"
#include "tumble/error.hpp"

namespace tumble::viewer {

std::vector<Camera> followCameras(const std::vector<Bounds>& boxes, double sigmaFrames) {
  const std::size_t n = boxes.size();
  std::vector<Camera> framed(n);
  Camera previous;
  for (std::size_t k = 0; k < n; ++k) {
    if (!boxes[k].empty) previous = Camera::framing(boxes[k]);
    framed[k] = previous;
  }
  if (!(sigmaFrames > 0.0)) return framed;
  const auto reach = static_cast<std::ptrdiff_t>(std::ceil(3.0 * sigmaFrames));
  std::vector<double> weight(static_cast<std::size_t>(reach) + 1);
  for (std::ptrdiff_t j = 0; j <= reach; ++j)
    weight[static_cast<std::size_t>(j)] = std::exp(-0.5 * double(j * j) / (sigmaFrames * sigmaFrames));
  std::vector<Camera> out = framed;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(n); ++k) {
    double sum = 0.0, x = 0.0, y = 0.0, z = 0.0, d = 0.0;
    for (std::ptrdiff_t j = std::max<std::ptrdiff_t>(0, k - reach);
         j <= std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(n) - 1, k + reach); ++j) {
      const double w = weight[static_cast<std::size_t>(std::abs(j - k))];
      const Camera& c = framed[static_cast<std::size_t>(j)];
      sum += w;
      x += w * c.target.x;
      y += w * c.target.y;
      z += w * c.target.z;
      d += w * c.distance;
    }
    Camera& c = out[static_cast<std::size_t>(k)];
    c.target = {static_cast<float>(x / sum), static_cast<float>(y / sum), static_cast<float>(z / sum)};
    c.distance = static_cast<float>(d / sum);
  }
  return out;
}

namespace {

using detail::trim;

bool parseNumber(const std::string& s, double& out) {
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == '\0' && std::isfinite(out);
}

// Appended, not chained: GCC 12 at -O3 warns, wrongly, about chains of temporaries (-Wrestrict).
[[noreturn]] void pathError(const std::string& origin, long line, const std::string& field, const std::string& what) {
  std::string m = field;
  m += ": ";
  m += what;
  throw InputError(origin, line, m);
}

}  // namespace

std::vector<CameraKey> parseCameraPath(const std::string& text, const std::string& origin) {
  static const char* const kNames[] = {"time", "x", "y", "z", "yaw", "pitch", "distance"};
  std::vector<CameraKey> keys;
  std::istringstream in(text);
  std::string line;
  long lineNo = 0;
  bool sawLine = false;
  while (std::getline(in, line)) {
    ++lineNo;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    if (trim(line).empty()) continue;
    std::vector<std::string> fields;
    std::istringstream ls(line);
    for (std::string f; std::getline(ls, f, ',');) fields.push_back(trim(f));
    if (trim(line).back() == ',') fields.emplace_back();
    double v = 0.0;
    if (!sawLine && !parseNumber(fields[0], v)) {  // a header
      sawLine = true;
      continue;
    }
    sawLine = true;
    if (fields.size() > 7)
      throw InputError(origin, lineNo, "expected at most 7 fields (time, x, y, z, yaw, pitch, distance), got " +
                                           std::to_string(fields.size()));
    CameraKey k;
    float* const slots[] = {nullptr, &k.x, &k.y, &k.z, &k.yawDeg, &k.pitchDeg, &k.distance};
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (fields[i].empty()) {
        if (i == 0) pathError(origin, lineNo, kNames[0], "every key needs a time (simulated seconds)");
        continue;
      }
      if (!parseNumber(fields[i], v)) pathError(origin, lineNo, kNames[i], "expected a number, got '" + fields[i] + "'");
      if (i == 0) k.time = v;
      else if (std::abs(v) > 1e30) pathError(origin, lineNo, kNames[i], "out of range");
      else *slots[i] = static_cast<float>(v);
    }
    if (!keys.empty() && !(k.time > keys.back().time))
      pathError(origin, lineNo, kNames[0], "key times must increase (the key before is at " +
                                               std::to_string(keys.back().time) + " s)");
    if (!std::isnan(k.pitchDeg) && std::abs(k.pitchDeg) > 85.0f)
      pathError(origin, lineNo, kNames[5], "must be within -85 to 85 degrees");
    if (!std::isnan(k.distance) && !(k.distance > 0.0f)) pathError(origin, lineNo, kNames[6], "must be positive");
    keys.push_back(k);
  }
  if (keys.empty()) throw InputError(origin, 0, "the camera path holds no keys (lines of time, x, y, z, yaw, pitch, distance)");
  return keys;
}

std::vector<CameraKey> readCameraPath(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path, 0, "cannot open the camera path");
  std::ostringstream s;
  s << f.rdbuf();
  if (f.bad()) throw InputError(path, 0, "cannot read the camera path");
  return parseCameraPath(s.str(), path);
}

Camera cameraOnPath(const std::vector<CameraKey>& keys, double t, const Camera& automatic) {
  // NaN when no key gives the value.
  const auto value = [&](float CameraKey::*field) {
    const CameraKey* before = nullptr;
    const CameraKey* after = nullptr;
    for (const CameraKey& k : keys) {
      if (std::isnan(k.*field)) continue;
      if (k.time <= t) before = &k;
      if (k.time >= t && !after) after = &k;
    }
    if (!before && !after) return CameraKey::kAuto;
    if (!before) return after->*field;
    if (!after || after == before) return before->*field;
    const double s = (t - before->time) / (after->time - before->time);
    return static_cast<float>((1.0 - s) * double(before->*field) + s * double(after->*field));
  };
  // Degrees to radians in double, as the command's --yaw and --pitch are.
  constexpr double kDeg = 3.14159265358979 / 180.0;
  const auto set = [](float& out, float v, double scale) {
    if (!std::isnan(v)) out = static_cast<float>(double(v) * scale);
  };
  Camera c = automatic;
  set(c.target.x, value(&CameraKey::x), 1.0);
  set(c.target.y, value(&CameraKey::y), 1.0);
  set(c.target.z, value(&CameraKey::z), 1.0);
  set(c.yaw, value(&CameraKey::yawDeg), kDeg);
  set(c.pitch, value(&CameraKey::pitchDeg), kDeg);
  set(c.distance, value(&CameraKey::distance), 1.0);
  return c;
}

}  // namespace tumble::viewer
