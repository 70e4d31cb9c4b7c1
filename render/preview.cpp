// Sphere impostors with OpenGL 4.5 core through OSMesa; see preview.h.
//
// Every GL entry point is looked up with OSMesaGetProcAddress into a table of our own rather
// than called through the gl* symbols: if libGL were ever linked into the same binary, those
// symbols could resolve to it, and every call would go to a library with no current context
// (silently empty images). OSMesa's framebuffer rows are bottom-up; they are flipped here.
#include "render/preview.h"

#include <GL/osmesa.h>
#include <GL/glcorearb.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace kurage::render {

namespace {

// The GL functions used here: name, type.
#define KURAGE_GL_FUNCTIONS(X)                                    \
  X(glGetString, PFNGLGETSTRINGPROC)                              \
  X(glGetError, PFNGLGETERRORPROC)                                \
  X(glViewport, PFNGLVIEWPORTPROC)                                \
  X(glClearColor, PFNGLCLEARCOLORPROC)                            \
  X(glClearDepth, PFNGLCLEARDEPTHPROC)                            \
  X(glClear, PFNGLCLEARPROC)                                      \
  X(glEnable, PFNGLENABLEPROC)                                    \
  X(glDepthFunc, PFNGLDEPTHFUNCPROC)                              \
  X(glFinish, PFNGLFINISHPROC)                                    \
  X(glReadPixels, PFNGLREADPIXELSPROC)                            \
  X(glPixelStorei, PFNGLPIXELSTOREIPROC)                          \
  X(glCreateShader, PFNGLCREATESHADERPROC)                        \
  X(glShaderSource, PFNGLSHADERSOURCEPROC)                        \
  X(glCompileShader, PFNGLCOMPILESHADERPROC)                      \
  X(glGetShaderiv, PFNGLGETSHADERIVPROC)                          \
  X(glGetShaderInfoLog, PFNGLGETSHADERINFOLOGPROC)                \
  X(glDeleteShader, PFNGLDELETESHADERPROC)                        \
  X(glCreateProgram, PFNGLCREATEPROGRAMPROC)                      \
  X(glAttachShader, PFNGLATTACHSHADERPROC)                        \
  X(glLinkProgram, PFNGLLINKPROGRAMPROC)                          \
  X(glGetProgramiv, PFNGLGETPROGRAMIVPROC)                        \
  X(glGetProgramInfoLog, PFNGLGETPROGRAMINFOLOGPROC)              \
  X(glDeleteProgram, PFNGLDELETEPROGRAMPROC)                      \
  X(glUseProgram, PFNGLUSEPROGRAMPROC)                            \
  X(glGetUniformLocation, PFNGLGETUNIFORMLOCATIONPROC)            \
  X(glUniformMatrix4fv, PFNGLUNIFORMMATRIX4FVPROC)                \
  X(glUniform3f, PFNGLUNIFORM3FPROC)                              \
  X(glUniform1f, PFNGLUNIFORM1FPROC)                              \
  X(glGenVertexArrays, PFNGLGENVERTEXARRAYSPROC)                  \
  X(glBindVertexArray, PFNGLBINDVERTEXARRAYPROC)                  \
  X(glDeleteVertexArrays, PFNGLDELETEVERTEXARRAYSPROC)            \
  X(glGenBuffers, PFNGLGENBUFFERSPROC)                            \
  X(glBindBuffer, PFNGLBINDBUFFERPROC)                            \
  X(glBufferData, PFNGLBUFFERDATAPROC)                            \
  X(glDeleteBuffers, PFNGLDELETEBUFFERSPROC)                      \
  X(glEnableVertexAttribArray, PFNGLENABLEVERTEXATTRIBARRAYPROC)  \
  X(glVertexAttribPointer, PFNGLVERTEXATTRIBPOINTERPROC)          \
  X(glVertexAttribDivisor, PFNGLVERTEXATTRIBDIVISORPROC)          \
  X(glDrawArraysInstanced, PFNGLDRAWARRAYSINSTANCEDPROC)

struct Gl {
#define KURAGE_GL_MEMBER(name, type) type name = nullptr;
  KURAGE_GL_FUNCTIONS(KURAGE_GL_MEMBER)
#undef KURAGE_GL_MEMBER
};

// One instance per sphere: centre (3), radius (1), albedo (3).
constexpr int kFloatsPerSphere = 7;

const char* const kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 centre;
layout(location = 1) in float radius;
layout(location = 2) in vec3 albedo;
uniform mat4 view;
uniform mat4 projection;
out vec3 quadPoint;           // view space
flat out vec3 sphereCentre;   // view space
flat out float sphereRadius;
flat out vec3 sphereAlbedo;
void main() {
  vec3 c = (view * vec4(centre, 1.0)).xyz;
  float d = length(c);
  sphereCentre = c;
  sphereRadius = radius;
  sphereAlbedo = albedo;
  if (d <= radius * 1.0001) {  // the camera is inside the sphere: draw nothing
    quadPoint = c;
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  // A quad through the centre, perpendicular to the line of sight, that holds the silhouette:
  // the tangent cone meets that plane in a circle of radius r d / sqrt(d^2 - r^2).
  vec3 dir = c / d;
  vec3 u = normalize(cross(dir, abs(dir.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
  vec3 v = cross(u, dir);
  float s = radius * d / sqrt(d * d - radius * radius);
  vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
  quadPoint = c + s * (corner.x * u + corner.y * v);
  gl_Position = projection * vec4(quadPoint, 1.0);
}
)";

const char* const kFragmentShader = R"(#version 450 core
in vec3 quadPoint;
flat in vec3 sphereCentre;
flat in float sphereRadius;
flat in vec3 sphereAlbedo;
uniform mat4 projection;
uniform vec3 lightDirection;  // view space, unit, towards the light
uniform vec3 lightRadiance;
uniform float ambient;
out vec4 colour;
float encode(float x) {  // IEC 61966-2-1 sRGB
  x = clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
  vec3 ray = normalize(quadPoint);
  float b = dot(ray, sphereCentre);
  float disc = b * b - (dot(sphereCentre, sphereCentre) - sphereRadius * sphereRadius);
  if (disc < 0.0) discard;
  vec3 hit = (b - sqrt(disc)) * ray;
  vec3 n = (hit - sphereCentre) / sphereRadius;
  vec4 clip = projection * vec4(hit, 1.0);
  gl_FragDepth = 0.5 * (clip.z / clip.w) + 0.5;
  vec3 lit = sphereAlbedo * (ambient + max(dot(n, lightDirection), 0.0) * lightRadiance);
  colour = vec4(encode(lit.r), encode(lit.g), encode(lit.b), 1.0);
}
)";

}  // namespace

struct PreviewRenderer::Impl {
  OSMesaContext context = nullptr;
  Gl gl;
  GLuint program = 0, vertexArray = 0, buffer = 0;
  std::vector<unsigned char> framebuffer;  // RGBA8, bottom-up
  int width = 0, height = 0;

  void check(const char* what) const {
    const GLenum error = gl.glGetError();
    if (error != GL_NO_ERROR)
      throw std::runtime_error(std::string("preview: OpenGL error ") + std::to_string(error) + " in " + what);
  }

  // (Re)binds the context to a framebuffer of the given size.
  void makeCurrent(int w, int h) {
    if (w == width && h == height && OSMesaGetCurrentContext() == context) return;
    framebuffer.assign(size_t(w) * size_t(h) * 4, 0);
    if (!OSMesaMakeCurrent(context, framebuffer.data(), GL_UNSIGNED_BYTE, w, h))
      throw std::runtime_error("preview: OSMesaMakeCurrent failed for " + std::to_string(w) + "x" + std::to_string(h));
    width = w;
    height = h;
  }

  GLuint compile(GLenum type, const char* source) const {
    const GLuint shader = gl.glCreateShader(type);
    gl.glShaderSource(shader, 1, &source, nullptr);
    gl.glCompileShader(shader);
    GLint ok = 0;
    gl.glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[2048] = {};
      gl.glGetShaderInfoLog(shader, sizeof log, nullptr, log);
      gl.glDeleteShader(shader);
      throw std::runtime_error(std::string("preview: shader compilation failed: ") + log);
    }
    return shader;
  }
};

PreviewRenderer::PreviewRenderer() : impl_(std::make_unique<Impl>()) {
  const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 0,
                            OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
  impl_->context = OSMesaCreateContextAttribs(attributes, nullptr);
  if (!impl_->context) throw std::runtime_error("preview: OSMesa could not create an OpenGL 4.5 core context");
  try {
    impl_->makeCurrent(16, 16);
    Gl& gl = impl_->gl;
#define KURAGE_GL_LOAD(name, type)                                                              \
  gl.name = reinterpret_cast<type>(OSMesaGetProcAddress(#name));                                \
  if (!gl.name) throw std::runtime_error("preview: OSMesa lacks the OpenGL function " #name);
    KURAGE_GL_FUNCTIONS(KURAGE_GL_LOAD)
#undef KURAGE_GL_LOAD
    const GLuint vs = impl_->compile(GL_VERTEX_SHADER, kVertexShader);
    const GLuint fs = impl_->compile(GL_FRAGMENT_SHADER, kFragmentShader);
    impl_->program = gl.glCreateProgram();
    gl.glAttachShader(impl_->program, vs);
    gl.glAttachShader(impl_->program, fs);
    gl.glLinkProgram(impl_->program);
    gl.glDeleteShader(vs);
    gl.glDeleteShader(fs);
    GLint ok = 0;
    gl.glGetProgramiv(impl_->program, GL_LINK_STATUS, &ok);
    if (!ok) {
      char log[2048] = {};
      gl.glGetProgramInfoLog(impl_->program, sizeof log, nullptr, log);
      throw std::runtime_error(std::string("preview: shader linking failed: ") + log);
    }
    gl.glGenVertexArrays(1, &impl_->vertexArray);
    gl.glBindVertexArray(impl_->vertexArray);
    gl.glGenBuffers(1, &impl_->buffer);
    gl.glBindBuffer(GL_ARRAY_BUFFER, impl_->buffer);
    const GLsizei stride = kFloatsPerSphere * sizeof(float);
    const int sizes[] = {3, 1, 3};
    size_t offset = 0;
    for (GLuint a = 0; a < 3; ++a) {
      gl.glEnableVertexAttribArray(a);
      gl.glVertexAttribPointer(a, sizes[a], GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offset));
      gl.glVertexAttribDivisor(a, 1);
      offset += sizes[a] * sizeof(float);
    }
    impl_->check("set-up");
  } catch (...) {
    OSMesaDestroyContext(impl_->context);
    throw;
  }
}

PreviewRenderer::~PreviewRenderer() {
  if (!impl_ || !impl_->context) return;
  if (OSMesaGetCurrentContext() == impl_->context) {
    impl_->gl.glDeleteBuffers(1, &impl_->buffer);
    impl_->gl.glDeleteVertexArrays(1, &impl_->vertexArray);
    impl_->gl.glDeleteProgram(impl_->program);
  }
  OSMesaDestroyContext(impl_->context);
}

std::string PreviewRenderer::glVersion() const {
  const Gl& gl = impl_->gl;
  const auto text = [&](GLenum name) {
    const GLubyte* s = gl.glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return text(GL_VERSION) + " (" + text(GL_RENDERER) + ")";
}

Image PreviewRenderer::render(const PreviewSpheres& spheres, const Camera& camera, const PreviewSettings& settings) {
  const size_t n = spheres.centres.size();
  if (spheres.radii.size() != n || spheres.colours.size() != n)
    throw std::invalid_argument("preview: centres, radii and colours differ in length");
  if (settings.width <= 0 || settings.height <= 0 || settings.width > 16384 || settings.height > 16384)
    throw std::invalid_argument("preview: image size out of range");
  const CameraRays f(camera, settings.width, settings.height);  // validates the camera
  impl_->makeCurrent(settings.width, settings.height);
  const Gl& gl = impl_->gl;

  // View: x right, y up, -z forward (OpenGL's convention).
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();
  view.block<1, 3>(0, 0) = f.right().transpose();
  view.block<1, 3>(1, 0) = f.up().transpose();
  view.block<1, 3>(2, 0) = -f.forward().transpose();
  view.block<3, 1>(0, 3) = -view.block<3, 3>(0, 0) * camera.position;

  // Near and far planes around the spheres in front of the camera.
  std::vector<float> instances(n * kFloatsPerSphere);
  float nearest = std::numeric_limits<float>::infinity(), farthest = 0.0f;
  for (size_t i = 0; i < n; ++i) {
    if (!(spheres.radii[i] > 0.0f)) throw std::invalid_argument("preview: sphere radius must be > 0");
    const Eigen::Vector3f& c = spheres.centres[i];
    const float depth = (c - camera.position).dot(f.forward());
    nearest = std::min(nearest, depth - spheres.radii[i]);
    farthest = std::max(farthest, depth + spheres.radii[i]);
    float* out = &instances[i * kFloatsPerSphere];
    out[0] = c.x(), out[1] = c.y(), out[2] = c.z(), out[3] = spheres.radii[i];
    for (int a = 0; a < 3; ++a) out[4 + a] = std::clamp(spheres.colours[i][a], 0.0f, 1.0f);
  }
  const float far = std::max(farthest * 1.01f, 1e-3f);
  const float near = std::clamp(nearest, far * 1e-5f, far * 0.5f);
  const float aspect = float(settings.width) / float(settings.height);
  Eigen::Matrix4f projection = Eigen::Matrix4f::Zero();
  projection(0, 0) = 1.0f / (aspect * f.tanHalfFov());
  projection(1, 1) = 1.0f / f.tanHalfFov();
  projection(2, 2) = -(far + near) / (far - near);
  projection(2, 3) = -2.0f * far * near / (far - near);
  projection(3, 2) = -1.0f;

  const Eigen::Vector3f toLight = (-view.block<3, 3>(0, 0) * settings.lightDirection).normalized();

  gl.glViewport(0, 0, settings.width, settings.height);
  const Eigen::Vector3f& bg = settings.background;
  gl.glClearColor(linearToSrgb(std::clamp(bg.x(), 0.0f, 1.0f)), linearToSrgb(std::clamp(bg.y(), 0.0f, 1.0f)),
                  linearToSrgb(std::clamp(bg.z(), 0.0f, 1.0f)), 1.0f);
  gl.glClearDepth(1.0);
  gl.glEnable(GL_DEPTH_TEST);
  gl.glDepthFunc(GL_LESS);
  gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (n > 0) {
    gl.glUseProgram(impl_->program);
    gl.glUniformMatrix4fv(gl.glGetUniformLocation(impl_->program, "view"), 1, GL_FALSE, view.data());
    gl.glUniformMatrix4fv(gl.glGetUniformLocation(impl_->program, "projection"), 1, GL_FALSE, projection.data());
    gl.glUniform3f(gl.glGetUniformLocation(impl_->program, "lightDirection"), toLight.x(), toLight.y(), toLight.z());
    const Eigen::Vector3f& radiance = settings.lightIrradiance;
    gl.glUniform3f(gl.glGetUniformLocation(impl_->program, "lightRadiance"), radiance.x(), radiance.y(), radiance.z());
    gl.glUniform1f(gl.glGetUniformLocation(impl_->program, "ambient"), settings.ambient);
    gl.glBindVertexArray(impl_->vertexArray);
    gl.glBindBuffer(GL_ARRAY_BUFFER, impl_->buffer);
    gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(instances.size() * sizeof(float)), instances.data(), GL_STREAM_DRAW);
    gl.glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(n));
  }
  gl.glFinish();
  impl_->check("render");

  // The framebuffer is the OSMesa buffer itself: rows bottom-up, sRGB-encoded bytes.
  Image image(settings.width, settings.height);
  float decode[256];
  for (int v = 0; v < 256; ++v) decode[v] = srgbToLinear(float(v) / 255.0f);
  for (int y = 0; y < settings.height; ++y) {
    const unsigned char* row = &impl_->framebuffer[size_t(settings.height - 1 - y) * size_t(settings.width) * 4];
    for (int x = 0; x < settings.width; ++x) {
      const unsigned char* p = row + size_t(x) * 4;
      image.at(x, y) = Eigen::Vector4f(decode[p[0]], decode[p[1]], decode[p[2]], 1.0f);
    }
  }
  return image;
}

}  // namespace kurage::render
