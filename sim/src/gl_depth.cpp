#include "floorcast/sim/gl_depth.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <string>
#include <vector>

#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position_world;
uniform mat4 clip_from_world;
uniform mat4 camera_from_world;  // OpenCV camera frame
out float depth_z;
void main() {
  depth_z = (camera_from_world * vec4(position_world, 1.0)).z;
  gl_Position = clip_from_world * vec4(position_world, 1.0);
}
)";

const char* kFragmentShader = R"(#version 330 core
in float depth_z;
layout(location = 0) out float out_depth;
void main() { out_depth = depth_z; }
)";

GLuint compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof(log), nullptr, log);
    glDeleteShader(s);
    throw InputError(std::string("OpenGL depth renderer: shader compilation failed: ") + log);
  }
  return s;
}

}  // namespace

struct GlDepthRenderer::Impl {
  OSMesaContext ctx = nullptr;
  std::vector<unsigned char> osmesa_buffer;  // the context's default framebuffer (unused)
  int width = 0, height = 0;
  GLuint program = 0, vao = 0, vbo = 0, fbo = 0, color_tex = 0, depth_rb = 0;
  GLint loc_clip = -1, loc_camera = -1;
  GLsizei vertex_count = 0;

  void make_current() {
    if (!OSMesaMakeCurrent(ctx, osmesa_buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
      throw InputError("OpenGL depth renderer: OSMesaMakeCurrent failed");
    }
  }

  ~Impl() {
    if (!ctx) return;
    if (OSMesaMakeCurrent(ctx, osmesa_buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
      if (fbo) glDeleteFramebuffers(1, &fbo);
      if (color_tex) glDeleteTextures(1, &color_tex);
      if (depth_rb) glDeleteRenderbuffers(1, &depth_rb);
      if (vbo) glDeleteBuffers(1, &vbo);
      if (vao) glDeleteVertexArrays(1, &vao);
      if (program) glDeleteProgram(program);
    }
    OSMesaDestroyContext(ctx);
  }
};

GlDepthRenderer::GlDepthRenderer(const Mesh& mesh, int width_px, int height_px) : impl_(std::make_unique<Impl>()) {
  if (width_px < 1 || height_px < 1 || width_px > 8192 || height_px > 8192) {
    throw InputError("OpenGL depth renderer: image size must be in [1, 8192]");
  }
  Impl& g = *impl_;
  g.width = width_px;
  g.height = height_px;
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         3,
                         0};
  g.ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!g.ctx) throw InputError("OpenGL depth renderer: OSMesa could not create a GL 3.3 core context");
  g.osmesa_buffer.resize(static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px) * 4);
  g.make_current();

  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  g.program = glCreateProgram();
  glAttachShader(g.program, vs);
  glAttachShader(g.program, fs);
  glLinkProgram(g.program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint linked = 0;
  glGetProgramiv(g.program, GL_LINK_STATUS, &linked);
  if (!linked) throw InputError("OpenGL depth renderer: shader link failed");
  g.loc_clip = glGetUniformLocation(g.program, "clip_from_world");
  g.loc_camera = glGetUniformLocation(g.program, "camera_from_world");

  // Unindexed triangle soup: three vertices per triangle.
  std::vector<float> xyz;
  xyz.reserve(mesh.triangles.size() * 9);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f& v = mesh.vertices_m[static_cast<std::size_t>(t[k])];
      xyz.insert(xyz.end(), {v.x(), v.y(), v.z()});
    }
  }
  g.vertex_count = static_cast<GLsizei>(xyz.size() / 3);
  glGenVertexArrays(1, &g.vao);
  glBindVertexArray(g.vao);
  glGenBuffers(1, &g.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(xyz.size() * sizeof(float)), xyz.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);

  // Offscreen target: a float colour texture (the z-depth) and a 32-bit float depth buffer.
  glGenTextures(1, &g.color_tex);
  glBindTexture(GL_TEXTURE_2D, g.color_tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, width_px, height_px, 0, GL_RED, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glGenRenderbuffers(1, &g.depth_rb);
  glBindRenderbuffer(GL_RENDERBUFFER, g.depth_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width_px, height_px);
  glGenFramebuffers(1, &g.fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, g.fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g.color_tex, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g.depth_rb);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw InputError("OpenGL depth renderer: offscreen framebuffer incomplete");
  }
  if (glGetError() != GL_NO_ERROR) throw InputError("OpenGL depth renderer: GL error during setup");
}

GlDepthRenderer::~GlDepthRenderer() = default;

std::string GlDepthRenderer::renderer_name() const {
  impl_->make_current();
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "";
}

cv::Mat GlDepthRenderer::render_depth(const Eigen::Isometry3d& T_world_camera, const CameraIntrinsics& K,
                                      double near_m, double far_m) {
  Impl& g = *impl_;
  if (K.width_px != g.width || K.height_px != g.height) {
    throw InputError("OpenGL depth renderer: intrinsics size differs from the renderer's");
  }
  if (!(near_m > 0.0) || !(far_m > near_m)) throw InputError("OpenGL depth renderer: need 0 < near < far");
  g.make_current();

  // OpenCV pinhole -> OpenGL clip space. GL eye = OpenCV camera with y and z flipped; window x
  // of pixel u is u + 0.5, window y (from the bottom) of row v is H - v - 0.5.
  const double W = g.width, H = g.height, n = near_m, f = far_m;
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = 2.0 * K.fx_px / W;
  P(0, 2) = 1.0 - (2.0 * K.cx_px + 1.0) / W;
  P(1, 1) = 2.0 * K.fy_px / H;
  P(1, 2) = (2.0 * K.cy_px + 1.0) / H - 1.0;
  P(2, 2) = -(f + n) / (f - n);
  P(2, 3) = -2.0 * f * n / (f - n);
  P(3, 2) = -1.0;
  const Eigen::Matrix4d camera_from_world = T_world_camera.inverse().matrix();
  const Eigen::Matrix4d gl_from_cv = Eigen::Vector4d(1.0, -1.0, -1.0, 1.0).asDiagonal();
  const Eigen::Matrix4f clip = (P * gl_from_cv * camera_from_world).cast<float>();
  const Eigen::Matrix4f cam = camera_from_world.cast<float>();

  glBindFramebuffer(GL_FRAMEBUFFER, g.fbo);
  glViewport(0, 0, g.width, g.height);
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearBufferfv(GL_COLOR, 0, zero);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  glUseProgram(g.program);
  glUniformMatrix4fv(g.loc_clip, 1, GL_FALSE, clip.data());  // Eigen is column-major like GL
  glUniformMatrix4fv(g.loc_camera, 1, GL_FALSE, cam.data());
  glBindVertexArray(g.vao);
  glDrawArrays(GL_TRIANGLES, 0, g.vertex_count);

  cv::Mat bottom_up(g.height, g.width, CV_32F);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, g.width, g.height, GL_RED, GL_FLOAT, bottom_up.data);
  if (glGetError() != GL_NO_ERROR) throw InputError("OpenGL depth renderer: GL error while rendering");
  cv::Mat depth;
  cv::flip(bottom_up, depth, 0);
  return depth;
}

}  // namespace floorcast
