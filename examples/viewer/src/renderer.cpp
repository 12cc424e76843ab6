// SPDX-License-Identifier: MIT
// OpenGL 3.3 core renderer. Spheres are one icosphere mesh (two subdivisions: 162 vertices,
// 320 triangles, smooth normals; one subdivision, 80 triangles, when they are drawn small)
// drawn once per particle with glDrawElementsInstanced; the per-instance attributes are
// centre + radius and colour. The ground is one large quad whose
// fragment shader draws a faint grid and fades into the sky with distance, so the horizon has
// no hard edge. Under each sphere a soft blob shadow on the ground (one instanced quad per
// sphere, its darkness fading and its size growing with the height above the ground) shows
// what rests on the ground and what is in the air. Everything is lit by one directional light
// plus a hemisphere ambient term.
//
// Walls are drawn after the opaque spheres and the ground, blended, depth-tested but not
// written to the depth buffer, so that a sphere in front of a wall hides it and a wall in front
// of a sphere only tints it. What makes a container readable from outside is the triangles'
// winding (wall_geometry.hpp): they are counter-clockwise seen from the side the bodies are on.
// Where the camera sees that inner side (a box's far faces, the inside of a drum's far half) the
// wall is fairly opaque: it is behind the bodies. Where it sees the outer side (the near faces,
// which would hide the bodies) the wall is faint, with a little more at grazing angles so its
// shape still reads. Whole walls are sorted back to front by the distance of their box's centre,
// and each is drawn inner side first, then outer side, then its outline (where the surface ends
// or folds), so the blending order is right for convex walls and near enough for the rest. A
// wall that turns (WallMotion) is posed by a rotation and a translation in the vertex shader and
// carries a few dark stripes about its spin axis, fixed to it, so the turning can be seen.
#include "tumble/output_file.hpp"
#include "tumble/viewer/renderer.hpp"

#include <epoxy/gl.h>
#include <png.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include "tumble/error.hpp"

namespace tumble::viewer {
namespace {

const char* kSphereVs = R"(#version 330 core
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec4 iSphere;
layout(location = 2) in vec3 iColor;
uniform mat4 uViewProj;
out vec3 vNormal;
out vec3 vColor;
out vec3 vWorld;
void main() {
  vec3 w = iSphere.xyz + iSphere.w * aPos;
  vNormal = aPos;
  vColor = iColor;
  vWorld = w;
  gl_Position = uViewProj * vec4(w, 1.0);
}
)";

// The lighting of spheres and walls: one directional light (diffuse k.z, specular k.w with
// `shininess`), an ambient term k.x and a hemisphere term k.y (more light from above). Prepended
// to the fragment shaders that use it (withShade()).
const char* kShadeGlsl = R"(#version 330 core
vec3 shade(vec3 base, vec3 n, vec3 v, vec3 light, vec4 k, float shininess) {
  float diff = max(dot(n, light), 0.0);
  float hemi = 0.5 + 0.5 * n.z;
  float spec = pow(max(dot(n, normalize(light + v)), 0.0), shininess);
  return base * (k.x + k.y * hemi + k.z * diff) + vec3(k.w * spec);
}
)";

const char* kSphereFs = R"(
in vec3 vNormal;
in vec3 vColor;
in vec3 vWorld;
uniform vec3 uEye;
uniform vec3 uLight;
out vec4 oColor;
void main() {
  vec3 n = normalize(vNormal);
  vec3 v = normalize(uEye - vWorld);
  vec3 c = shade(vColor, n, v, uLight, vec4(0.22, 0.18, 0.68, 0.25), 40.0);
  oColor = vec4(min(c, vec3(1.0)), 1.0);
}
)";

const char* kGroundVs = R"(#version 330 core
layout(location = 0) in vec2 aPos;
uniform mat4 uViewProj;
uniform vec3 uCenter;
uniform float uHalf;
uniform float uHeight;
out vec3 vWorld;
void main() {
  vec3 w = vec3(uCenter.xy + uHalf * aPos, uHeight);
  vWorld = w;
  gl_Position = uViewProj * vec4(w, 1.0);
}
)";

const char* kGroundFs = R"(#version 330 core
in vec3 vWorld;
uniform vec3 uColor;
uniform vec3 uSky;
uniform vec3 uCenter;
uniform float uFade;
uniform float uGrid;
uniform vec3 uLight;
out vec4 oColor;
void main() {
  vec2 g = abs(fract(vWorld.xy / uGrid + 0.5) - 0.5) / fwidth(vWorld.xy / uGrid);
  float line = 1.0 - min(min(g.x, g.y), 1.0);
  vec3 c = uColor * (0.55 + 0.45 * max(uLight.z, 0.0)) * (1.0 - 0.12 * line);
  float d = length(vWorld.xy - uCenter.xy);
  oColor = vec4(mix(c, uSky, smoothstep(0.6 * uFade, uFade, d)), 1.0);
}
)";

const char* kShadowVs = R"(#version 330 core
layout(location = 0) in vec2 aPos;
layout(location = 1) in vec4 iSphere;
uniform mat4 uViewProj;
uniform float uHeight;
out vec2 vLocal;
out float vStrength;
void main() {
  float r = iSphere.w;
  float h = max(iSphere.z - r - uHeight, 0.0) / r;  // gap to the ground, in radii
  float size = r * (1.0 + 0.5 * min(h, 4.0));
  vStrength = iSphere.z < uHeight ? 0.0 : 0.6 / ((1.0 + 0.25 * h) * (1.0 + 0.25 * h));
  vLocal = aPos;
  gl_Position = uViewProj * vec4(iSphere.xy + size * aPos, uHeight, 1.0);
}
)";

const char* kShadowFs = R"(#version 330 core
in vec2 vLocal;
in float vStrength;
out vec4 oColor;
void main() {
  float a = vStrength * (1.0 - smoothstep(0.35, 1.0, length(vLocal)));
  oColor = vec4(0.0, 0.0, 0.0, a);  // blended as dst * (1 - a)
}
)";

const char* kWallVs = R"(#version 330 core
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
uniform mat4 uViewProj;
uniform mat3 uRot;
uniform vec3 uPivot;
uniform vec3 uShift;
out vec3 vWorld;
out vec3 vNormal;
out vec3 vLocal;
void main() {
  vec3 w = uRot * (aPos - uPivot) + uPivot + uShift;
  vLocal = aPos;
  vWorld = w;
  vNormal = uRot * aNormal;
  gl_Position = uViewProj * vec4(w, 1.0);
}
)";

const char* kWallFs = R"(
in vec3 vWorld;
in vec3 vNormal;
in vec3 vLocal;
uniform vec3 uColor;
uniform vec3 uEye;
uniform vec3 uLight;
uniform float uAlphaInner;
uniform float uAlphaOuter;
uniform int uSpin;
uniform vec3 uSpinPivot;
uniform vec3 uSpinE1;
uniform vec3 uSpinE2;
out vec4 oColor;
const float kTwoPi = 6.28318531;
const float kStripes = 8.0;
void main() {
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;  // lit on the side seen
  vec3 v = normalize(uEye - vWorld);
  vec3 c = shade(uColor, n, v, uLight, vec4(0.30, 0.20, 0.50, 0.15), 30.0);
  float a = gl_FrontFacing ? uAlphaInner : uAlphaOuter;
  a += (0.6 - a) * pow(1.0 - abs(dot(n, v)), 4.0);  // grazing: a little more
  if (uSpin != 0) {
    // Stripes at kStripes angles about the spin axis, in the wall's own frame. The angle's
    // derivative is taken from two atan branches, so the wrap at +-pi leaves no seam.
    vec3 r = vLocal - uSpinPivot;
    float x = dot(r, uSpinE1), y = dot(r, uSpinE2);
    float f = atan(y, x) * kStripes / kTwoPi;
    float g = atan(-y, -x) * kStripes / kTwoPi;
    float w = min(fwidth(f), fwidth(g));
    float d = abs(f - floor(f + 0.5));
    float stripe = 1.0 - smoothstep(0.05 - w, 0.05 + w, d);
    stripe *= 1.0 - smoothstep(0.1, 0.3, w);  // none where they crowd (near the axis)
    c *= 1.0 - 0.55 * stripe;
    a = min(a + 0.3 * stripe, 1.0);
  }
  oColor = vec4(min(c, vec3(1.0)), a);
}
)";

const char* kWallLineFs = R"(#version 330 core
uniform vec3 uColor;
uniform float uAlpha;
out vec4 oColor;
void main() { oColor = vec4(uColor, uAlpha); }
)";

const char* kLineVs = R"(#version 330 core
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aColor;
uniform mat4 uViewProj;
out vec3 vColor;
void main() {
  vColor = aColor;
  gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";

const char* kLineFs = R"(#version 330 core
in vec3 vColor;
out vec4 oColor;
void main() { oColor = vec4(vColor, 1.0); }
)";

GLuint compile(GLenum type, const char* src, const char* name) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw Error(std::string("viewer: shader ") + name + " does not compile: " + log);
  }
  return s;
}

GLuint program(const char* vs, const char* fs, const char* name) {
  const GLuint v = compile(GL_VERTEX_SHADER, vs, name), f = compile(GL_FRAGMENT_SHADER, fs, name);
  const GLuint p = glCreateProgram();
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw Error(std::string("viewer: shader program ") + name + " does not link: " + log);
  }
  return p;
}

// A fragment shader's source after the shared lighting (kShadeGlsl, which holds the #version).
std::string withShade(const char* body) { return std::string(kShadeGlsl) + body; }

// Icosphere: the icosahedron subdivided `levels` times, vertices pushed onto the unit sphere.
void icosphere(int levels, std::vector<float>& outPos, std::vector<std::uint32_t>& outIdx) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<Vec3f> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::uint32_t> f = {0, 11, 5, 0, 5,  1,  0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                  4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                                  6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (Vec3f& p : v) p = (1.0f / norm(p)) * p;
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      if (const auto it = mid.find(key); it != mid.end()) return it->second;
      Vec3f p = 0.5f * (v[a] + v[b]);
      v.push_back((1.0f / norm(p)) * p);
      const auto i = static_cast<std::uint32_t>(v.size() - 1);
      mid.emplace(key, i);
      return i;
    };
    std::vector<std::uint32_t> g;
    for (std::size_t i = 0; i < f.size(); i += 3) {
      const std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(g);
  }
  outPos.clear();
  for (const Vec3f& p : v) outPos.insert(outPos.end(), {p.x, p.y, p.z});
  outIdx = std::move(f);
}

// One sphere mesh with the instance attributes bound to the shared instance buffers.
struct SphereMesh {
  GLuint vao = 0, vbo = 0, ibo = 0;
  GLsizei numIndices = 0;
  void create(int levels, GLuint instSphereVbo, GLuint instColorVbo) {
    std::vector<float> pos;
    std::vector<std::uint32_t> idx;
    icosphere(levels, pos, idx);
    numIndices = static_cast<GLsizei>(idx.size());
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(pos.size() * sizeof(float)), pos.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glGenBuffers(1, &ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(idx.size() * sizeof(std::uint32_t)), idx.data(),
                 GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, instSphereVbo);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
    glVertexAttribDivisor(1, 1);
    glBindBuffer(GL_ARRAY_BUFFER, instColorVbo);
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glVertexAttribDivisor(2, 1);
  }
  void destroy() {
    glDeleteBuffers(1, &vbo);
    glDeleteBuffers(1, &ibo);
    glDeleteVertexArrays(1, &vao);
  }
};

// A vertex array over a new static buffer of `data`: per vertex `attributes` interleaved vec3
// (location 0 the position, 1 the normal).
void staticVertices(const std::vector<float>& data, int attributes, GLuint& outVao, GLuint& outVbo) {
  glGenVertexArrays(1, &outVao);
  glBindVertexArray(outVao);
  glGenBuffers(1, &outVbo);
  glBindBuffer(GL_ARRAY_BUFFER, outVbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
  const auto stride = static_cast<GLsizei>(3 * attributes * sizeof(float));
  for (int a = 0; a < attributes; ++a) {
    glEnableVertexAttribArray(static_cast<GLuint>(a));
    glVertexAttribPointer(static_cast<GLuint>(a), 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<void*>(static_cast<std::uintptr_t>(3 * a) * sizeof(float)));
  }
}

// One wall on the GPU: its triangles (position, normal) and its outline, with what poses it.
struct WallBuffers {
  GLuint vao = 0, vbo = 0, lineVao = 0, lineVbo = 0;
  GLsizei numVertices = 0, numLineVertices = 0;
  Rgb color{0.6f, 0.7f, 0.8f};
  WallMotion motion;
  Vec3f centre{0, 0, 0};                   // of its box, at rest
  Vec3f spinE1{1, 0, 0}, spinE2{0, 1, 0};  // perpendicular to ω, for the stripes
  bool spins = false;
  void destroy() {
    glDeleteBuffers(1, &vbo);
    glDeleteBuffers(1, &lineVbo);
    glDeleteVertexArrays(1, &vao);
    glDeleteVertexArrays(1, &lineVao);
  }
};

// How see-through a wall is: seen from the bodies' side (behind them) and from outside.
constexpr float kWallAlphaInner = 0.55f;
constexpr float kWallAlphaOuter = 0.10f;
constexpr float kWallOutlineAlpha = 0.45f;

}  // namespace

struct Renderer::Impl {
  GLuint sphereProg = 0, groundProg = 0, lineProg = 0, shadowProg = 0, wallProg = 0, wallLineProg = 0;
  std::vector<WallBuffers> walls;
  GLuint shadowVao = 0;
  SphereMesh fine, coarse;  // 320 and 80 triangles
  GLuint instSphereVbo = 0, instColorVbo = 0;
  GLuint groundVao = 0, groundVbo = 0;
  GLuint lineVao = 0, lineVbo = 0;
};

Renderer::Renderer() : m(std::make_unique<Impl>()) {
  m->sphereProg = program(kSphereVs, withShade(kSphereFs).c_str(), "sphere");
  m->groundProg = program(kGroundVs, kGroundFs, "ground");
  m->lineProg = program(kLineVs, kLineFs, "lines");
  m->shadowProg = program(kShadowVs, kShadowFs, "shadow");
  m->wallProg = program(kWallVs, withShade(kWallFs).c_str(), "wall");
  m->wallLineProg = program(kWallVs, kWallLineFs, "wall outline");

  glGenBuffers(1, &m->instSphereVbo);
  glGenBuffers(1, &m->instColorVbo);
  m->fine.create(2, m->instSphereVbo, m->instColorVbo);
  m->coarse.create(1, m->instSphereVbo, m->instColorVbo);

  const float quad[] = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  glGenVertexArrays(1, &m->groundVao);
  glBindVertexArray(m->groundVao);
  glGenBuffers(1, &m->groundVbo);
  glBindBuffer(GL_ARRAY_BUFFER, m->groundVbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);

  // The shadows: the ground's quad per vertex, the spheres' centre and radius per instance.
  glGenVertexArrays(1, &m->shadowVao);
  glBindVertexArray(m->shadowVao);
  glBindBuffer(GL_ARRAY_BUFFER, m->groundVbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);
  glBindBuffer(GL_ARRAY_BUFFER, m->instSphereVbo);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  glVertexAttribDivisor(1, 1);

  glGenVertexArrays(1, &m->lineVao);
  glBindVertexArray(m->lineVao);
  glGenBuffers(1, &m->lineVbo);
  glBindBuffer(GL_ARRAY_BUFFER, m->lineVbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  glBindVertexArray(0);
}

Renderer::~Renderer() {
  for (WallBuffers& w : m->walls) w.destroy();
  glDeleteProgram(m->wallProg);
  glDeleteProgram(m->wallLineProg);
  m->fine.destroy();
  m->coarse.destroy();
  glDeleteBuffers(1, &m->instSphereVbo);
  glDeleteBuffers(1, &m->instColorVbo);
  glDeleteBuffers(1, &m->groundVbo);
  glDeleteBuffers(1, &m->lineVbo);
  glDeleteVertexArrays(1, &m->groundVao);
  glDeleteVertexArrays(1, &m->lineVao);
  glDeleteVertexArrays(1, &m->shadowVao);
  glDeleteProgram(m->shadowProg);
  glDeleteProgram(m->sphereProg);
  glDeleteProgram(m->groundProg);
  glDeleteProgram(m->lineProg);
}

void Renderer::setWalls(const std::vector<WallMesh>& walls) {
  for (WallBuffers& w : m->walls) w.destroy();
  m->walls.clear();
  for (const WallMesh& mesh : walls) {
    WallBuffers w;
    w.color = mesh.color;
    w.motion = mesh.motion;
    w.centre = mesh.bounds.empty ? Vec3f{0, 0, 0} : 0.5f * (mesh.bounds.lo + mesh.bounds.hi);
    const Vec3f& om = mesh.motion.angularVelocity;
    if (norm(om) > 0.0f) {
      // A frame about the spin axis (any one: the stripes turn with the wall).
      const Vec3f a = (1.0f / norm(om)) * om;
      const Vec3f e = std::abs(a.x) < 0.6f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
      w.spinE1 = cross(a, e);
      w.spinE1 = (1.0f / norm(w.spinE1)) * w.spinE1;
      w.spinE2 = cross(a, w.spinE1);
      w.spins = true;
    }
    w.numVertices = static_cast<GLsizei>(mesh.numVertices());
    staticVertices(mesh.vertices, 2, w.vao, w.vbo);
    w.numLineVertices = static_cast<GLsizei>(mesh.outline.size() / 3);
    staticVertices(mesh.outline, 1, w.lineVao, w.lineVbo);
    m->walls.push_back(w);
  }
  glBindVertexArray(0);
}

std::string Renderer::glRenderer() {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "unknown";
}

void Renderer::draw(const DrawData& d, const Camera& camera, int w, int h) {
  glViewport(0, 0, w, h);
  glClearColor(d.background.r, d.background.g, d.background.b, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glDisable(GL_BLEND);

  const Mat4 vp = camera.viewProjection(float(w) / float(std::max(h, 1)));
  const Vec3f eye = camera.eye();
  // Light from above (the camera's up), over the camera's left shoulder.
  Vec3f light = std::cos(camera.yaw + 0.6f) * camera.ex + std::sin(camera.yaw + 0.6f) * camera.ey + 1.6f * camera.up;
  light = (1.0f / norm(light)) * light;

  if (d.groundEnabled) {
    // Half-size and fade radius grow with the camera distance and the scene, so the ground
    // always reaches the horizon smoothly.
    const Bounds b = sphereBounds(d.spheres);
    const float sceneR = b.empty ? 1.0f : 0.5f * norm(b.hi - b.lo);
    const float fade = std::max(3.0f * camera.distance, 4.0f * sceneR);
    const float grid = std::pow(10.0f, std::floor(std::log10(std::max(fade / 8.0f, 1e-3f))));
    const Rgb gc = d.groundColor ? *d.groundColor : groundColor(d.pulls);
    glDisable(GL_CULL_FACE);
    glUseProgram(m->groundProg);
    glUniformMatrix4fv(glGetUniformLocation(m->groundProg, "uViewProj"), 1, GL_FALSE, vp.m.data());
    glUniform3f(glGetUniformLocation(m->groundProg, "uCenter"), camera.target.x, camera.target.y, 0.0f);
    glUniform1f(glGetUniformLocation(m->groundProg, "uHalf"), fade);
    glUniform1f(glGetUniformLocation(m->groundProg, "uHeight"), d.groundHeight);
    glUniform3f(glGetUniformLocation(m->groundProg, "uColor"), gc.r, gc.g, gc.b);
    glUniform3f(glGetUniformLocation(m->groundProg, "uSky"), d.background.r, d.background.g, d.background.b);
    glUniform1f(glGetUniformLocation(m->groundProg, "uFade"), fade);
    glUniform1f(glGetUniformLocation(m->groundProg, "uGrid"), grid);
    glUniform3f(glGetUniformLocation(m->groundProg, "uLight"), light.x, light.y, light.z);
    glBindVertexArray(m->groundVao);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glEnable(GL_CULL_FACE);
  }

  const std::size_t n = d.numSpheres();
  if (n > 0) {
    glBindBuffer(GL_ARRAY_BUFFER, m->instSphereVbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(4 * n * sizeof(float)), d.spheres.data(), GL_STREAM_DRAW);
  }
  if (d.groundEnabled && n > 0) {
    // On the ground, under the spheres: no depth test or write (the spheres, drawn next, cover
    // them where they are in front), darkening what is there.
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ZERO, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(m->shadowProg);
    glUniformMatrix4fv(glGetUniformLocation(m->shadowProg, "uViewProj"), 1, GL_FALSE, vp.m.data());
    glUniform1f(glGetUniformLocation(m->shadowProg, "uHeight"), d.groundHeight);
    glBindVertexArray(m->shadowVao);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, static_cast<GLsizei>(n));
    glDisable(GL_BLEND);
    glEnable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
  }
  if (n > 0 && d.colors.size() >= 3 * n) {
    glUseProgram(m->sphereProg);
    glUniformMatrix4fv(glGetUniformLocation(m->sphereProg, "uViewProj"), 1, GL_FALSE, vp.m.data());
    glUniform3f(glGetUniformLocation(m->sphereProg, "uEye"), eye.x, eye.y, eye.z);
    glUniform3f(glGetUniformLocation(m->sphereProg, "uLight"), light.x, light.y, light.z);
    // Level of detail: spheres drawn smaller than about 8 pixels in radius look the same with
    // 80 triangles as with 320, and llvmpipe draws them four times faster.
    float maxR = 0.0f;
    for (std::size_t i = 0; i < n; ++i) maxR = std::max(maxR, d.spheres[4 * i + 3]);
    const float pixelsPerUnit = float(h) / (2.0f * std::tan(camera.fovY / 2.0f) * camera.distance);
    const SphereMesh& mesh = maxR * pixelsPerUnit < 8.0f ? m->coarse : m->fine;
    glBindVertexArray(mesh.vao);
    glBindBuffer(GL_ARRAY_BUFFER, m->instColorVbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(3 * n * sizeof(float)), d.colors.data(), GL_STREAM_DRAW);
    glDrawElementsInstanced(GL_TRIANGLES, mesh.numIndices, GL_UNSIGNED_INT, nullptr, static_cast<GLsizei>(n));
  }

  if (d.wallsShown && !m->walls.empty()) {
    // Back to front by the posed centre of each wall's box (see the design note at the top).
    struct Posed {
      const WallBuffers* w;
      WallPose pose;
      float distance;
    };
    std::vector<Posed> order;
    for (const WallBuffers& w : m->walls) {
      const WallPose pose = wallPose(w.motion, d.time);
      order.push_back({&w, pose, norm(pose.apply(w.centre) - eye)});
    }
    std::stable_sort(order.begin(), order.end(), [](const Posed& a, const Posed& b) { return a.distance > b.distance; });
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-1.0f, -2.0f);  // a wall on the ground (a box's floor) is drawn over it
    glEnable(GL_CULL_FACE);
    const auto poseUniforms = [&](GLuint prog, const WallPose& pose) {
      const Mat3f r = rotationMatrix(pose.rotation);
      glUniformMatrix4fv(glGetUniformLocation(prog, "uViewProj"), 1, GL_FALSE, vp.m.data());
      glUniformMatrix3fv(glGetUniformLocation(prog, "uRot"), 1, GL_TRUE, &r.xx);
      glUniform3f(glGetUniformLocation(prog, "uPivot"), pose.pivot.x, pose.pivot.y, pose.pivot.z);
      glUniform3f(glGetUniformLocation(prog, "uShift"), pose.translation.x, pose.translation.y, pose.translation.z);
    };
    for (const Posed& p : order) {
      const WallBuffers& w = *p.w;
      glUseProgram(m->wallProg);
      poseUniforms(m->wallProg, p.pose);
      glUniform3f(glGetUniformLocation(m->wallProg, "uColor"), w.color.r, w.color.g, w.color.b);
      glUniform3f(glGetUniformLocation(m->wallProg, "uEye"), eye.x, eye.y, eye.z);
      glUniform3f(glGetUniformLocation(m->wallProg, "uLight"), light.x, light.y, light.z);
      glUniform1f(glGetUniformLocation(m->wallProg, "uAlphaInner"), kWallAlphaInner);
      glUniform1f(glGetUniformLocation(m->wallProg, "uAlphaOuter"), kWallAlphaOuter);
      glUniform1i(glGetUniformLocation(m->wallProg, "uSpin"), w.spins ? 1 : 0);
      glUniform3f(glGetUniformLocation(m->wallProg, "uSpinPivot"), w.motion.pivot.x, w.motion.pivot.y, w.motion.pivot.z);
      glUniform3f(glGetUniformLocation(m->wallProg, "uSpinE1"), w.spinE1.x, w.spinE1.y, w.spinE1.z);
      glUniform3f(glGetUniformLocation(m->wallProg, "uSpinE2"), w.spinE2.x, w.spinE2.y, w.spinE2.z);
      glBindVertexArray(w.vao);
      glCullFace(GL_BACK);  // the inner side: facing the camera where the camera is on the bodies' side
      glDrawArrays(GL_TRIANGLES, 0, w.numVertices);
      glCullFace(GL_FRONT);  // then the outer side, in front of it
      glDrawArrays(GL_TRIANGLES, 0, w.numVertices);
      if (w.numLineVertices > 0) {
        const Rgb c{0.55f * w.color.r, 0.55f * w.color.g, 0.55f * w.color.b};
        glUseProgram(m->wallLineProg);
        poseUniforms(m->wallLineProg, p.pose);
        glUniform3f(glGetUniformLocation(m->wallLineProg, "uColor"), c.r, c.g, c.b);
        glUniform1f(glGetUniformLocation(m->wallLineProg, "uAlpha"), kWallOutlineAlpha);
        glBindVertexArray(w.lineVao);
        glDrawArrays(GL_LINES, 0, w.numLineVertices);
      }
    }
    glCullFace(GL_BACK);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }

  if (!d.lines.empty()) {
    glUseProgram(m->lineProg);
    glUniformMatrix4fv(glGetUniformLocation(m->lineProg, "uViewProj"), 1, GL_FALSE, vp.m.data());
    glBindVertexArray(m->lineVao);
    glBindBuffer(GL_ARRAY_BUFFER, m->lineVbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(d.lines.size() * sizeof(float)), d.lines.data(),
                 GL_STREAM_DRAW);
    // Force lines are a debugging aid: drawn over everything, since most of them start inside a
    // pile and point into a neighbour.
    glDisable(GL_DEPTH_TEST);
    glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(d.lines.size() / 6));
    glEnable(GL_DEPTH_TEST);
  }
  glBindVertexArray(0);
  glUseProgram(0);
}

std::string glErrorName(unsigned e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "OpenGL error " + std::to_string(e);
  }
}

Image readPixels(int w, int h) {
  Image img;
  img.width = w;
  img.height = h;
  const std::size_t row = 3 * static_cast<std::size_t>(w);
  std::vector<std::uint8_t> raw(row * static_cast<std::size_t>(h));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, raw.data());
  // A draw or read-back that failed (GL_OUT_OF_MEMORY at a large size, say) leaves an error
  // flag and an undefined (typically black) image: report it instead of returning that image.
  // OpenGL keeps one flag per kind of error; collect them all, which also clears them.
  std::string errors;
  for (int i = 0; i < 8; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    errors += (errors.empty() ? "" : ", ") + glErrorName(e);
  }
  if (!errors.empty())
    throw Error("OpenGL failed to draw or read back a " + std::to_string(w) + "x" + std::to_string(h) + " image (" +
                errors + ")" + (errors.find("GL_OUT_OF_MEMORY") != std::string::npos ? "; try a smaller --size" : ""));
  img.rgb.resize(raw.size());
  // OpenGL's first row is the bottom one.
  for (int y = 0; y < h; ++y)
    std::memcpy(&img.rgb[static_cast<std::size_t>(y) * row], &raw[static_cast<std::size_t>(h - 1 - y) * row], row);
  return img;
}

std::optional<ImageFormat> imageFormatOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png") return ImageFormat::Png;
  if (ext == ".ppm") return ImageFormat::Ppm;
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (!ec && (std::filesystem::is_character_file(st) || std::filesystem::is_fifo(st))) return ImageFormat::Ppm;
  return std::nullopt;
}

void checkImageName(const std::string& path, const std::string& option) {
  if (!imageFormatOf(path))
    throw Error(option + " " + path + ": an image is written as PNG (a name ending in .png) or binary PPM (.ppm); "
                "this name asks for another format (convert afterwards, e.g. ffmpeg -i x.png x.jpg)");
}

void writeImage(const std::string& path, const Image& img) {
  checkImageName(path, "image");
  const bool png = imageFormatOf(path) == ImageFormat::Png;
  OutputFile out(path);  // a temporary renamed into place; abandoned if this throws
  if (png) {
    png_image pi;
    std::memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    pi.width = static_cast<png_uint_32>(img.width);
    pi.height = static_cast<png_uint_32>(img.height);
    pi.format = PNG_FORMAT_RGB;
    if (png_image_write_to_stdio(&pi, out.file(), 0, img.rgb.data(), 0, nullptr) == 0)
      throw Error("cannot write " + path + ": " + pi.message);
  } else {
    std::fprintf(out.file(), "P6\n%d %d\n255\n", img.width, img.height);
    if (std::fwrite(img.rgb.data(), 1, img.rgb.size(), out.file()) != img.rgb.size())
      throw Error("cannot write " + path + ": " + std::strerror(errno));
  }
  out.commit();
}

Image readPpm(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error(path + ": cannot open image: " + std::strerror(errno));
  Image img;
  int maxval = 0;
  const int got = std::fscanf(f, "P6 %d %d %d", &img.width, &img.height, &maxval);
  if (got != 3 || maxval != 255 || img.width <= 0 || img.height <= 0 || img.width > 16384 || img.height > 16384 ||
      std::fgetc(f) == EOF) {
    std::fclose(f);
    throw Error(path + ": not a binary PPM (P6, maxval 255)");
  }
  img.rgb.resize(3 * static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height));
  const bool full = std::fread(img.rgb.data(), 1, img.rgb.size(), f) == img.rgb.size();
  std::fclose(f);
  if (!full) throw Error(path + ": PPM pixel data truncated");
  return img;
}

}  // namespace tumble::viewer
