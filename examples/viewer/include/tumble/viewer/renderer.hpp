// SPDX-License-Identifier: MIT
/// @file renderer.hpp
/// OpenGL 3.3 core renderer: instanced lit spheres, the ground plane coloured by the pulls,
/// the walls (shaded, see-through where they would hide the bodies) and force lines. Needs a
/// current OpenGL context (a GLFW window or an OffscreenContext); every call must come from the
/// thread that owns it.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tumble/viewer/camera.hpp"
#include "tumble/viewer/draw_data.hpp"

namespace tumble::viewer {

class Renderer {
 public:
  /// Compiles the shaders and creates the buffers; throws tumble::Error with the compiler log
  /// when a shader does not compile.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// The walls to draw from now on (wallMeshes(); none at first): uploaded once, posed at each
  /// draw's DrawData::time and drawn when DrawData::wallsShown. Replaces the previous ones.
  void setWalls(const std::vector<WallMesh>& walls);

  /// Draws `d` into the currently bound framebuffer of size w × h (clears it first).
  void draw(const DrawData& d, const Camera& camera, int w, int h);

  /// The OpenGL renderer string (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
  static std::string glRenderer();

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

/// An RGB image, 8 bits per channel, top row first.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  const std::uint8_t* at(int x, int y) const {
    return &rgb[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x))];
  }
};

/// The name of an OpenGL error code (GLenum), e.g. "GL_OUT_OF_MEMORY".
std::string glErrorName(unsigned error);

/// Reads the currently bound read framebuffer (w × h) into an image, flipping it so that the
/// top row comes first.
Image readPixels(int w, int h);

/// The image formats writeImage writes.
enum class ImageFormat { Png, Ppm };
/// The format writeImage writes to `path`: PNG for a name ending in .png, binary PPM for one
/// ending in .ppm (either case), PPM for a device or a FIFO (/dev/stdout, whatever its name);
/// none for any other name (x.jpg: no JPEG writer is linked).
std::optional<ImageFormat> imageFormatOf(const std::string& path);
/// Throws tumble::Error when writeImage would refuse `path`, naming `option` (e.g. "-o"), the
/// path and the formats it writes; called before any work, so a bad name costs nothing.
void checkImageName(const std::string& path, const std::string& option);

/// Writes an image as PNG or binary PPM (imageFormatOf; any other name is refused), through a
/// temporary renamed into place (tumble/output_file.hpp), so no half-written file is left.
/// Throws tumble::Error.
void writeImage(const std::string& path, const Image& img);
/// Reads a binary PPM (P6, maxval 255) as written by writeImage; throws tumble::Error.
Image readPpm(const std::string& path);

}  // namespace tumble::viewer
