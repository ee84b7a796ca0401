// floorcast_gl.so: the OpenGL back-end (OSMesa, llvmpipe; no display needed), loaded with dlopen
// by sim/src/gl_renderer.cpp on first use. Draws a labelled triangle soup from OpenCV pinhole
// cameras into three images at once: colour (lit, procedurally textured surfaces; glass tinted
// and blended over what lies behind it), z-depth and the label of the first surface. Sampling is
// at pixel centres, like the Embree ray caster, so depths agree away from silhouette edges.
//
// Passes per view: (1) opaque surfaces, depth test and write; (2) glass colour blended over the
// opaque image, depth test without write; (3) glass depth and label, depth test and write with
// the colour target masked, so depth and label report the nearest surface, glass included.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "../src/gl_backend_api.hpp"

namespace {

using namespace floorcast::gl_api;

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position_world;
layout(location = 1) in vec3 normal_world;
layout(location = 2) in vec2 face_uv;
layout(location = 3) in vec4 face_box;
layout(location = 4) in vec3 ids;  // material, label, instance
uniform mat4 clip_from_world;
uniform mat4 camera_from_world;
out vec3 p_world;
out vec3 n_world;
out vec2 uv;
flat out vec4 box;
flat out vec3 id;
out float depth_z;
void main() {
  p_world = position_world;
  n_world = normal_world;
  uv = face_uv;
  box = face_box;
  id = ids;
  depth_z = (camera_from_world * vec4(position_world, 1.0)).z;
  gl_Position = clip_from_world * vec4(position_world, 1.0);
}
)";

// Procedural materials: value noise and fractal noise on world or face coordinates; every
// constant is a plain colour in linear-ish sRGB. Lighting: ambient, a fixed sky direction, a
// head-light term and a mild fall-off with distance, darker corners near the floor.
const char* kFragmentShader = R"(#version 330 core
in vec3 p_world;
in vec3 n_world;
in vec2 uv;
flat in vec4 box;
flat in vec3 id;
in float depth_z;
uniform vec3 camera_world;
uniform int glass_pass;
layout(location = 0) out vec4 out_colour;
layout(location = 1) out float out_depth;
layout(location = 2) out float out_label;

float hash12(vec2 p) {
  vec3 p3 = fract(vec3(p.xyx) * 0.1031);
  p3 += dot(p3, p3.yzx + 33.33);
  return fract((p3.x + p3.y) * p3.z);
}
float noise2(vec2 p) {
  vec2 i = floor(p), f = fract(p);
  vec2 u = f * f * (3.0 - 2.0 * f);
  return mix(mix(hash12(i), hash12(i + vec2(1.0, 0.0)), u.x),
             mix(hash12(i + vec2(0.0, 1.0)), hash12(i + vec2(1.0, 1.0)), u.x), u.y);
}
float fbm(vec2 p) {
  float a = 0.5, s = 0.0;
  for (int i = 0; i < 4; ++i) { s += a * noise2(p); p = p * 2.03 + vec2(17.1, 5.7); a *= 0.5; }
  return s;
}

vec3 wall_albedo() {
  // Plaster in a few soft tints that change slowly over the building, a darker skirting board.
  vec3 tint = mix(vec3(0.86, 0.84, 0.79), vec3(0.80, 0.84, 0.86), smoothstep(0.3, 0.7, noise2(p_world.xy * 0.12)));
  vec3 c = tint * (0.93 + 0.10 * fbm(uv * vec2(3.0, 3.0)));
  if (p_world.z < 0.09) c = vec3(0.42, 0.40, 0.37) * (0.95 + 0.1 * noise2(uv * 20.0));
  return c;
}
vec3 floor_albedo() {
  // Wooden planks 0.18 m wide along x, 1.5 m long with staggered joints, grain along the plank.
  float w = 0.18, len = 1.5;
  float plank = floor(p_world.y / w);
  float shift = hash12(vec2(plank, 3.7)) * len;
  float seg = floor((p_world.x + shift) / len);
  float tone = 0.75 + 0.30 * hash12(vec2(plank, seg));
  float grain = fbm(vec2(p_world.x * 6.0, p_world.y * 70.0));
  vec3 c = vec3(0.60, 0.43, 0.28) * tone * (0.85 + 0.25 * grain);
  float fy = fract(p_world.y / w), fx = fract((p_world.x + shift) / len);
  if (fy < 0.03 || fx < 0.004) c *= 0.55;
  return c;
}
vec3 ceiling_albedo() {
  // Suspended ceiling tiles (0.6 m) with grey grid lines.
  vec2 f = fract(p_world.xy / 0.6);
  vec3 c = vec3(0.93, 0.93, 0.91) * (0.96 + 0.06 * noise2(p_world.xy * 9.0));
  if (min(min(f.x, 1.0 - f.x), min(f.y, 1.0 - f.y)) < 0.02) c = vec3(0.70, 0.70, 0.70);
  return c;
}
vec3 door_albedo() {
  // Wood leaf with vertical grain, a dark frame along its outline and a metal handle.
  vec3 c = vec3(0.55, 0.34, 0.17) * (0.80 + 0.30 * fbm(vec2(uv.x * 30.0, uv.y * 1.5)));
  float d = min(min(uv.x - box.x, box.y - uv.x), min(uv.y - box.z, box.w - uv.y));
  if (d < 0.07) c = vec3(0.30, 0.19, 0.10);
  float width = box.y - box.x;
  if (width > 0.4) {
    vec2 handle = vec2(box.y - 0.12, box.z + 1.0);
    if (length((uv - handle) * vec2(1.0, 0.5)) < 0.035) c = vec3(0.78, 0.78, 0.80);
  }
  return c;
}
vec3 clutter_albedo() {
  float h = hash12(vec2(id.z * 1.618, 7.3));
  vec3 c;
  if (h < 0.2) c = vec3(0.62, 0.46, 0.30);        // wood
  else if (h < 0.4) c = vec3(0.55, 0.57, 0.60);   // grey metal
  else if (h < 0.55) c = vec3(0.24, 0.34, 0.58);  // blue
  else if (h < 0.7) c = vec3(0.30, 0.50, 0.34);   // green
  else if (h < 0.85) c = vec3(0.62, 0.28, 0.22);  // red
  else c = vec3(0.86, 0.86, 0.82);                // white
  return c * (0.88 + 0.2 * fbm(uv * 8.0));
}

void main() {
  int material = int(id.x + 0.5);
  vec3 n = normalize(n_world);
  vec3 to_camera = camera_world - p_world;
  float dist = length(to_camera);
  vec3 v = to_camera / max(dist, 1e-6);
  vec3 sky = normalize(vec3(0.35, 0.55, 0.76));
  float shade = 0.40 + 0.28 * max(dot(n, sky), 0.0) + 0.32 * abs(dot(n, v));
  shade *= mix(1.0, 0.72, clamp(dist / 15.0, 0.0, 1.0));
  if (abs(n.z) < 0.5) shade *= 1.0 - 0.22 * exp(-p_world.z / 0.25);  // corners near the floor
  out_depth = depth_z;
  out_label = (id.y + 1.0) / 255.0;
  if (material == 2) {
    float fresnel = pow(1.0 - abs(dot(n, v)), 3.0);
    vec3 tint = vec3(0.55, 0.76, 0.80) * (0.75 + 0.25 * shade) + vec3(0.35) * fresnel;
    out_colour = vec4(tint, 0.32 + 0.4 * fresnel);
    return;
  }
  vec3 albedo;
  if (material == 0) albedo = wall_albedo();
  else if (material == 1) albedo = door_albedo();
  else if (material == 3) albedo = clutter_albedo();
  else if (material == 4) albedo = floor_albedo();
  else if (material == 5) albedo = ceiling_albedo();
  else albedo = vec3(0.38, 0.35, 0.32) * (0.9 + 0.15 * noise2(uv * 15.0));  // frames
  out_colour = vec4(clamp(albedo * shade, 0.0, 1.0), 1.0);
}
)";

GLuint compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof(log), nullptr, log);
    glDeleteShader(s);
    throw std::runtime_error(std::string("OpenGL renderer: shader compilation failed: ") + log);
  }
  return s;
}

class OsmesaBackend final : public Backend {
 public:
  OsmesaBackend(const SceneData& scene, int width, int height) : width_(width), height_(height) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx_) throw std::runtime_error("OpenGL renderer: OSMesa could not create a GL 3.3 core context");
    default_buffer_.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
    make_current();

    const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
    program_ = glCreateProgram();
    glAttachShader(program_, vs);
    glAttachShader(program_, fs);
    glLinkProgram(program_);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint linked = 0;
    glGetProgramiv(program_, GL_LINK_STATUS, &linked);
    if (!linked) throw std::runtime_error("OpenGL renderer: shader link failed");
    loc_clip_ = glGetUniformLocation(program_, "clip_from_world");
    loc_camera_ = glGetUniformLocation(program_, "camera_from_world");
    loc_camera_world_ = glGetUniformLocation(program_, "camera_world");
    loc_glass_pass_ = glGetUniformLocation(program_, "glass_pass");

    vertex_count_ = static_cast<GLsizei>(scene.vertex_count);
    glass_first_ = static_cast<GLsizei>(scene.glass_first);
    glGenVertexArrays(1, &vao_);
    glBindVertexArray(vao_);
    glGenBuffers(1, &vbo_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(scene.vertex_count * sizeof(Vertex)), scene.vertices,
                 GL_STATIC_DRAW);
    const GLsizei stride = sizeof(Vertex);
    auto attrib = [stride](GLuint index, GLint size, std::size_t offset) {
      glEnableVertexAttribArray(index);
      glVertexAttribPointer(index, size, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offset));
    };
    attrib(0, 3, offsetof(Vertex, position_world_m));
    attrib(1, 3, offsetof(Vertex, normal_world));
    attrib(2, 2, offsetof(Vertex, face_uv_m));
    attrib(3, 4, offsetof(Vertex, face_box_m));
    attrib(4, 3, offsetof(Vertex, material));

    // Offscreen target: colour (RGBA8), z-depth (R32F), label (R8) and a 32-bit float depth buffer.
    colour_tex_ = texture(GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE);
    depth_tex_ = texture(GL_R32F, GL_RED, GL_FLOAT);
    label_tex_ = texture(GL_R8, GL_RED, GL_UNSIGNED_BYTE);
    glGenRenderbuffers(1, &depth_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour_tex_, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, depth_tex_, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT2, GL_TEXTURE_2D, label_tex_, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, buffers);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      throw std::runtime_error("OpenGL renderer: offscreen framebuffer incomplete");
    }
    if (glGetError() != GL_NO_ERROR) throw std::runtime_error("OpenGL renderer: GL error during setup");
  }

  ~OsmesaBackend() override {
    if (!ctx_) return;
    if (OSMesaMakeCurrent(ctx_, default_buffer_.data(), GL_UNSIGNED_BYTE, width_, height_)) {
      if (fbo_) glDeleteFramebuffers(1, &fbo_);
      for (GLuint t : {colour_tex_, depth_tex_, label_tex_})
        if (t) glDeleteTextures(1, &t);
      if (depth_rb_) glDeleteRenderbuffers(1, &depth_rb_);
      if (vbo_) glDeleteBuffers(1, &vbo_);
      if (vao_) glDeleteVertexArrays(1, &vao_);
      if (program_) glDeleteProgram(program_);
    }
    OSMesaDestroyContext(ctx_);
  }

  const char* renderer_name() override {
    make_current();
    const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    name_ = s ? s : "";
    return name_.c_str();
  }

  void render(const ViewRequest& view, const ViewOutput& out) override {
    make_current();
    // OpenCV pinhole -> OpenGL clip space. GL eye = OpenCV camera with y and z flipped; window x
    // of pixel u is u + 0.5, window y (from the bottom) of row v is H - v - 0.5.
    const double W = width_, H = height_, n = view.near_m, f = view.far_m;
    double P[16] = {0};  // column-major
    P[0 + 0 * 4] = 2.0 * view.fx_px / W;
    P[0 + 2 * 4] = 1.0 - (2.0 * view.cx_px + 1.0) / W;
    P[1 + 1 * 4] = 2.0 * view.fy_px / H;
    P[1 + 2 * 4] = (2.0 * view.cy_px + 1.0) / H - 1.0;
    P[2 + 2 * 4] = -(f + n) / (f - n);
    P[2 + 3 * 4] = -2.0 * f * n / (f - n);
    P[3 + 2 * 4] = -1.0;
    const double flip[4] = {1.0, -1.0, -1.0, 1.0};  // gl_from_cv (diagonal)
    float clip[16], cam[16];
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        double s = 0.0;
        for (int k = 0; k < 4; ++k) s += P[r + k * 4] * flip[k] * view.camera_from_world[k + c * 4];
        clip[r + c * 4] = static_cast<float>(s);
        cam[r + c * 4] = static_cast<float>(view.camera_from_world[r + c * 4]);
      }
    }

    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, width_, height_);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    const float background[4] = {0.08f, 0.08f, 0.10f, 1.0f};
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, background);
    glClearBufferfv(GL_COLOR, 1, zero);
    glClearBufferfv(GL_COLOR, 2, zero);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glUseProgram(program_);
    glUniformMatrix4fv(loc_clip_, 1, GL_FALSE, clip);
    glUniformMatrix4fv(loc_camera_, 1, GL_FALSE, cam);
    glUniform3f(loc_camera_world_, static_cast<float>(view.camera_position_world_m[0]),
                static_cast<float>(view.camera_position_world_m[1]), static_cast<float>(view.camera_position_world_m[2]));
    glBindVertexArray(vao_);
    // (1) opaque surfaces
    glUniform1i(loc_glass_pass_, 0);
    if (glass_first_ > 0) glDrawArrays(GL_TRIANGLES, 0, glass_first_);
    const GLsizei glass_count = vertex_count_ - glass_first_;
    if (glass_count > 0) {
      // (2) glass colour over the opaque image
      if (view.colour) {
        glColorMaski(1, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glColorMaski(2, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthMask(GL_FALSE);
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glUniform1i(loc_glass_pass_, 1);
        glDrawArrays(GL_TRIANGLES, glass_first_, glass_count);
        glDisable(GL_BLEND);
      }
      // (3) glass depth and label: the nearest surface, glass included
      glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glDepthMask(GL_TRUE);
      glUniform1i(loc_glass_pass_, 2);
      glDrawArrays(GL_TRIANGLES, glass_first_, glass_count);
      glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }

    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    const std::size_t pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
    if (out.depth_z_m) {
      scratch_f_.resize(pixels);
      glReadBuffer(GL_COLOR_ATTACHMENT1);
      glReadPixels(0, 0, width_, height_, GL_RED, GL_FLOAT, scratch_f_.data());
      flip_rows(reinterpret_cast<const unsigned char*>(scratch_f_.data()), reinterpret_cast<unsigned char*>(out.depth_z_m),
                sizeof(float));
    }
    if (out.label_plus_one) {
      scratch_b_.resize(pixels);
      glReadBuffer(GL_COLOR_ATTACHMENT2);
      glReadPixels(0, 0, width_, height_, GL_RED, GL_UNSIGNED_BYTE, scratch_b_.data());
      flip_rows(scratch_b_.data(), out.label_plus_one, 1);
    }
    if (out.bgr) {
      scratch_b_.resize(pixels * 3);
      glReadBuffer(GL_COLOR_ATTACHMENT0);
      glReadPixels(0, 0, width_, height_, GL_BGR, GL_UNSIGNED_BYTE, scratch_b_.data());
      flip_rows(scratch_b_.data(), out.bgr, 3);
    }
    if (glGetError() != GL_NO_ERROR) throw std::runtime_error("OpenGL renderer: GL error while rendering");
  }

 private:
  void make_current() {
    if (!OSMesaMakeCurrent(ctx_, default_buffer_.data(), GL_UNSIGNED_BYTE, width_, height_)) {
      throw std::runtime_error("OpenGL renderer: OSMesaMakeCurrent failed");
    }
  }

  GLuint texture(GLint internal, GLenum format, GLenum type) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, internal, width_, height_, 0, format, type, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
  }

  /// GL rows run bottom-up; images top-down.
  void flip_rows(const unsigned char* src, unsigned char* dst, std::size_t bytes_per_pixel) const {
    const std::size_t row = static_cast<std::size_t>(width_) * bytes_per_pixel;
    for (int r = 0; r < height_; ++r) {
      std::memcpy(dst + static_cast<std::size_t>(r) * row, src + static_cast<std::size_t>(height_ - 1 - r) * row, row);
    }
  }

  OSMesaContext ctx_ = nullptr;
  std::vector<unsigned char> default_buffer_;  // the context's default framebuffer (unused)
  int width_ = 0, height_ = 0;
  GLuint program_ = 0, vao_ = 0, vbo_ = 0, fbo_ = 0, colour_tex_ = 0, depth_tex_ = 0, label_tex_ = 0, depth_rb_ = 0;
  GLint loc_clip_ = -1, loc_camera_ = -1, loc_camera_world_ = -1, loc_glass_pass_ = -1;
  GLsizei vertex_count_ = 0, glass_first_ = 0;
  std::vector<float> scratch_f_;
  std::vector<unsigned char> scratch_b_;
  std::string name_;
};

}  // namespace

extern "C" __attribute__((visibility("default"))) Backend* floorcast_gl_create_backend(
    int api_version, const SceneData* scene, int width_px, int height_px, char* error, std::size_t error_size) {
  auto fail = [&](const std::string& message) -> Backend* {
    if (error && error_size > 0) std::snprintf(error, error_size, "%s", message.c_str());
    return nullptr;
  };
  if (api_version != kApiVersion) {
    return fail("floorcast_gl.so speaks API version " + std::to_string(kApiVersion) + ", the caller " +
                std::to_string(api_version) + " (a stale module: rebuild or reinstall floorcast)");
  }
  if (!scene) return fail("no scene");
  try {
    return new OsmesaBackend(*scene, width_px, height_px);
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
