#include "gl/FeedbackLoop.h"

#include <algorithm>
#include <cassert>
#include <utility>

#include "gl/Gl.h"
#include "gl/GlObjects.h"
#include "tandem/Log.h"

namespace tandem::gl {

namespace {

#ifdef NDEBUG
bool gChecks = false;
#else
bool gChecks = true;  // a loop is a bug: builds with assertions always look for one
#endif
FeedbackLoopReport gReport;

// The binding a sampler type reads, or 0 for samplers whose textures cannot be attached (buffers).
GLenum bindingOf(GLenum samplerType) {
  switch (samplerType) {
    case GL_SAMPLER_1D: case GL_SAMPLER_1D_SHADOW: case GL_INT_SAMPLER_1D: case GL_UNSIGNED_INT_SAMPLER_1D:
      return GL_TEXTURE_BINDING_1D;
    case GL_SAMPLER_2D: case GL_SAMPLER_2D_SHADOW: case GL_INT_SAMPLER_2D: case GL_UNSIGNED_INT_SAMPLER_2D:
      return GL_TEXTURE_BINDING_2D;
    case GL_SAMPLER_3D: case GL_INT_SAMPLER_3D: case GL_UNSIGNED_INT_SAMPLER_3D:
      return GL_TEXTURE_BINDING_3D;
    case GL_SAMPLER_CUBE: case GL_SAMPLER_CUBE_SHADOW: case GL_INT_SAMPLER_CUBE: case GL_UNSIGNED_INT_SAMPLER_CUBE:
      return GL_TEXTURE_BINDING_CUBE_MAP;
    case GL_SAMPLER_1D_ARRAY: case GL_SAMPLER_1D_ARRAY_SHADOW: case GL_INT_SAMPLER_1D_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_1D_ARRAY:
      return GL_TEXTURE_BINDING_1D_ARRAY;
    case GL_SAMPLER_2D_ARRAY: case GL_SAMPLER_2D_ARRAY_SHADOW: case GL_INT_SAMPLER_2D_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_2D_ARRAY:
      return GL_TEXTURE_BINDING_2D_ARRAY;
    case GL_SAMPLER_CUBE_MAP_ARRAY: case GL_SAMPLER_CUBE_MAP_ARRAY_SHADOW: case GL_INT_SAMPLER_CUBE_MAP_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_CUBE_MAP_ARRAY:
      return GL_TEXTURE_BINDING_CUBE_MAP_ARRAY;
    case GL_SAMPLER_2D_RECT: case GL_SAMPLER_2D_RECT_SHADOW: case GL_INT_SAMPLER_2D_RECT:
    case GL_UNSIGNED_INT_SAMPLER_2D_RECT:
      return GL_TEXTURE_BINDING_RECTANGLE;
    case GL_SAMPLER_2D_MULTISAMPLE: case GL_INT_SAMPLER_2D_MULTISAMPLE: case GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE:
      return GL_TEXTURE_BINDING_2D_MULTISAMPLE;
    case GL_SAMPLER_2D_MULTISAMPLE_ARRAY: case GL_INT_SAMPLER_2D_MULTISAMPLE_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE_ARRAY:
      return GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY;
    default: return 0;  // not a sampler, or a buffer texture
  }
}

std::string describeObject(GLenum kind, GLuint id) {
  std::string label = objectLabel(kind, id);
  return std::to_string(id) + (label.empty() ? "" : " '" + label + "'");
}

struct Attachment {
  GLenum point;
  GLuint texture;
  GLint level;
};

std::string attachmentName(GLenum point) {
  if (point == GL_DEPTH_ATTACHMENT) return "GL_DEPTH_ATTACHMENT";
  if (point == GL_STENCIL_ATTACHMENT) return "GL_STENCIL_ATTACHMENT";
  return "GL_COLOR_ATTACHMENT" + std::to_string(point - GL_COLOR_ATTACHMENT0);
}

// The mip levels a draw may read from `texture` on `unit`: the base level alone unless the minification
// filter (the sampler object's on the active unit, else the texture's) takes mipmaps.
void sampledLevels(GLuint texture, GLint& lo, GLint& hi) {
  GLint sampler = 0, minFilter = 0, base = 0, maxLevel = 0, immutable = 0, levels = 0;
  glGetIntegerv(GL_SAMPLER_BINDING, &sampler);
  if (sampler != 0) glGetSamplerParameteriv(static_cast<GLuint>(sampler), GL_TEXTURE_MIN_FILTER, &minFilter);
  else glGetTextureParameteriv(texture, GL_TEXTURE_MIN_FILTER, &minFilter);
  glGetTextureParameteriv(texture, GL_TEXTURE_BASE_LEVEL, &base);
  glGetTextureParameteriv(texture, GL_TEXTURE_MAX_LEVEL, &maxLevel);
  glGetTextureParameteriv(texture, GL_TEXTURE_IMMUTABLE_FORMAT, &immutable);
  if (immutable) glGetTextureParameteriv(texture, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
  lo = hi = base;
  if (minFilter != GL_NEAREST && minFilter != GL_LINEAR) hi = immutable ? std::min(maxLevel, levels - 1) : maxLevel;
}

bool isShadowSampler(GLenum type) {
  switch (type) {
    case GL_SAMPLER_1D_SHADOW: case GL_SAMPLER_2D_SHADOW: case GL_SAMPLER_CUBE_SHADOW: case GL_SAMPLER_1D_ARRAY_SHADOW:
    case GL_SAMPLER_2D_ARRAY_SHADOW: case GL_SAMPLER_CUBE_MAP_ARRAY_SHADOW: case GL_SAMPLER_2D_RECT_SHADOW:
      return true;
    default: return false;
  }
}

// 'i' signed integer, 'u' unsigned integer, 'f' anything else a float sampler reads.
char samplerKind(GLenum type) {
  switch (type) {
    case GL_INT_SAMPLER_1D: case GL_INT_SAMPLER_2D: case GL_INT_SAMPLER_3D: case GL_INT_SAMPLER_CUBE:
    case GL_INT_SAMPLER_1D_ARRAY: case GL_INT_SAMPLER_2D_ARRAY: case GL_INT_SAMPLER_CUBE_MAP_ARRAY:
    case GL_INT_SAMPLER_2D_RECT: case GL_INT_SAMPLER_2D_MULTISAMPLE: case GL_INT_SAMPLER_2D_MULTISAMPLE_ARRAY:
    case GL_INT_SAMPLER_BUFFER:
      return 'i';
    case GL_UNSIGNED_INT_SAMPLER_1D: case GL_UNSIGNED_INT_SAMPLER_2D: case GL_UNSIGNED_INT_SAMPLER_3D:
    case GL_UNSIGNED_INT_SAMPLER_CUBE: case GL_UNSIGNED_INT_SAMPLER_1D_ARRAY: case GL_UNSIGNED_INT_SAMPLER_2D_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_CUBE_MAP_ARRAY: case GL_UNSIGNED_INT_SAMPLER_2D_RECT:
    case GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE: case GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_BUFFER:
      return 'u';
    default: return 'f';
  }
}

bool isBufferSampler(GLenum type) {
  return type == GL_SAMPLER_BUFFER || type == GL_INT_SAMPLER_BUFFER || type == GL_UNSIGNED_INT_SAMPLER_BUFFER;
}

// What kind of values an internal format holds: 'd' depth (or depth-stencil), 'i' signed integer,
// 'u' unsigned integer, 'f' float or normalized.
char formatKind(GLint format) {
  switch (format) {
    case GL_DEPTH_COMPONENT: case GL_DEPTH_COMPONENT16: case GL_DEPTH_COMPONENT24: case GL_DEPTH_COMPONENT32:
    case GL_DEPTH_COMPONENT32F: case GL_DEPTH_STENCIL: case GL_DEPTH24_STENCIL8: case GL_DEPTH32F_STENCIL8:
      return 'd';
    case GL_R8I: case GL_R16I: case GL_R32I: case GL_RG8I: case GL_RG16I: case GL_RG32I: case GL_RGB8I: case GL_RGB16I:
    case GL_RGB32I: case GL_RGBA8I: case GL_RGBA16I: case GL_RGBA32I:
      return 'i';
    case GL_R8UI: case GL_R16UI: case GL_R32UI: case GL_RG8UI: case GL_RG16UI: case GL_RG32UI: case GL_RGB8UI:
    case GL_RGB16UI: case GL_RGB32UI: case GL_RGBA8UI: case GL_RGBA16UI: case GL_RGBA32UI: case GL_RGB10_A2UI:
      return 'u';
    default: return 'f';
  }
}

// The current program's sampler uniforms, each element with its unit.
struct SamplerSlot {
  std::string name;
  GLenum type;
  GLint unit;
};
std::vector<SamplerSlot> samplerSlots(GLuint prog) {
  std::vector<SamplerSlot> slots;
  GLint uniforms = 0, maxName = 0;
  glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &uniforms);
  glGetProgramiv(prog, GL_ACTIVE_UNIFORM_MAX_LENGTH, &maxName);
  std::vector<char> nameBuf(static_cast<std::size_t>(std::max(maxName, 1)));
  for (GLint u = 0; u < uniforms; ++u) {
    GLint size = 0;
    GLenum type = 0;
    GLsizei length = 0;
    glGetActiveUniform(prog, static_cast<GLuint>(u), static_cast<GLsizei>(nameBuf.size()), &length, &size, &type,
                       nameBuf.data());
    if (bindingOf(type) == 0 && !isBufferSampler(type)) continue;
    std::string name(nameBuf.data(), static_cast<std::size_t>(length));
    // An array of samplers reports "name[0]": each element has a location (and a unit) of its own.
    std::string base = name.size() > 3 && name.ends_with("[0]") ? name.substr(0, name.size() - 3) : name;
    for (GLint e = 0; e < size; ++e) {
      std::string element = size > 1 ? base + "[" + std::to_string(e) + "]" : name;
      GLint location = glGetUniformLocation(prog, element.c_str());
      if (location < 0) continue;
      GLint unit = 0;
      glGetUniformiv(prog, location, &unit);
      slots.push_back({element, type, unit});
    }
  }
  return slots;
}

}  // namespace

std::vector<std::string> findSamplerProblems() {
  std::vector<std::string> problems;
  GLint program = 0, activeTexture = GL_TEXTURE0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &program);
  if (program == 0) return problems;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &activeTexture);
  for (const SamplerSlot& s : samplerSlots(static_cast<GLuint>(program))) {
    const std::string who = "sampler '" + s.name + "' (unit " + std::to_string(s.unit) + ")";
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(s.unit));
    GLint texture = 0, sampler = 0;
    glGetIntegerv(isBufferSampler(s.type) ? GL_TEXTURE_BINDING_BUFFER : bindingOf(s.type), &texture);
    glGetIntegerv(GL_SAMPLER_BINDING, &sampler);
    if (texture == 0) {
      problems.push_back(who + " has no texture of its type bound: what it reads is undefined on some drivers");
      continue;
    }
    const auto tex = static_cast<GLuint>(texture);
    if (isBufferSampler(s.type)) {
      GLint store = 0;
      glGetTextureLevelParameteriv(tex, 0, GL_TEXTURE_BUFFER_DATA_STORE_BINDING, &store);
      if (store == 0) problems.push_back(who + " reads buffer texture " + describeObject(GL_TEXTURE, tex) + ", which has no buffer");
    }
    GLint format = 0;
    glGetTextureLevelParameteriv(tex, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
    const char kind = formatKind(format), wants = samplerKind(s.type);
    auto parameter = [&](GLenum name) {
      GLint v = 0;
      if (sampler != 0) glGetSamplerParameteriv(static_cast<GLuint>(sampler), name, &v);
      else glGetTextureParameteriv(tex, name, &v);
      return v;
    };
    const std::string what = "texture " + describeObject(GL_TEXTURE, tex);
    if (isShadowSampler(s.type)) {
      if (kind != 'd') problems.push_back(who + " is a shadow sampler, but " + what + " has no depth format");
      else if (parameter(GL_TEXTURE_COMPARE_MODE) != GL_COMPARE_REF_TO_TEXTURE)
        problems.push_back(who + " is a shadow sampler, but " + what + " compares no depths");
      continue;
    }
    if (kind == 'd') {
      if (wants != 'f') problems.push_back(who + " is an integer sampler reading depth " + what);
      else if (parameter(GL_TEXTURE_COMPARE_MODE) != GL_NONE)
        problems.push_back(who + " reads depth " + what + " with depth comparison on, which only a shadow sampler may");
      continue;
    }
    if ((wants == 'f') != (kind == 'f') || (wants != 'f' && wants != kind))
      problems.push_back(who + " (" + (wants == 'f' ? "float" : wants == 'i' ? "signed integer" : "unsigned integer") +
                         ") reads " + what + " of another kind of format");
    // An integer texture filtered linearly is incomplete: it reads zeros.
    if (kind != 'f' && !isBufferSampler(s.type) &&
        (parameter(GL_TEXTURE_MAG_FILTER) != GL_NEAREST ||
         (parameter(GL_TEXTURE_MIN_FILTER) != GL_NEAREST && parameter(GL_TEXTURE_MIN_FILTER) != GL_NEAREST_MIPMAP_NEAREST)))
      problems.push_back(who + " reads integer " + what + " with linear filtering: incomplete, it reads zeros");
  }
  glActiveTexture(static_cast<GLenum>(activeTexture));
  return problems;
}

std::vector<std::string> findFeedbackLoops() {
  std::vector<std::string> loops;
  GLint framebuffer = 0, program = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  glGetIntegerv(GL_CURRENT_PROGRAM, &program);
  if (framebuffer == 0 || program == 0) return loops;  // the default framebuffer holds no textures
  const auto fbo = static_cast<GLuint>(framebuffer);
  const auto prog = static_cast<GLuint>(program);

  std::vector<Attachment> attachments;
  GLint colors = 0;
  glGetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &colors);
  std::vector<GLenum> points = {GL_DEPTH_ATTACHMENT, GL_STENCIL_ATTACHMENT};
  for (GLint i = 0; i < colors; ++i) points.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  for (GLenum point : points) {
    GLint type = GL_NONE, name = 0, level = 0;
    glGetNamedFramebufferAttachmentParameteriv(fbo, point, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_TEXTURE) continue;
    glGetNamedFramebufferAttachmentParameteriv(fbo, point, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
    glGetNamedFramebufferAttachmentParameteriv(fbo, point, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL, &level);
    attachments.push_back({point, static_cast<GLuint>(name), level});
  }
  if (attachments.empty()) return loops;

  GLint activeTexture = GL_TEXTURE0, uniforms = 0, maxName = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &activeTexture);
  glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &uniforms);
  glGetProgramiv(prog, GL_ACTIVE_UNIFORM_MAX_LENGTH, &maxName);
  std::vector<char> nameBuf(static_cast<std::size_t>(std::max(maxName, 1)));
  for (GLint u = 0; u < uniforms; ++u) {
    GLint size = 0;
    GLenum type = 0;
    GLsizei length = 0;
    glGetActiveUniform(prog, static_cast<GLuint>(u), static_cast<GLsizei>(nameBuf.size()), &length, &size, &type,
                       nameBuf.data());
    GLenum binding = bindingOf(type);
    if (binding == 0) continue;
    std::string name(nameBuf.data(), static_cast<std::size_t>(length));
    // An array of samplers reports "name[0]": each element has a location (and a unit) of its own.
    std::string base = name.size() > 3 && name.ends_with("[0]") ? name.substr(0, name.size() - 3) : name;
    for (GLint e = 0; e < size; ++e) {
      std::string element = size > 1 ? base + "[" + std::to_string(e) + "]" : name;
      GLint location = glGetUniformLocation(prog, element.c_str());
      if (location < 0) continue;
      GLint unit = 0, texture = 0;
      glGetUniformiv(prog, location, &unit);
      glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
      glGetIntegerv(binding, &texture);
      if (texture == 0) continue;
      GLint lo = 0, hi = 0;
      sampledLevels(static_cast<GLuint>(texture), lo, hi);
      for (const Attachment& a : attachments) {
        if (a.texture != static_cast<GLuint>(texture) || a.level < lo || a.level > hi) continue;
        loops.push_back("sampler '" + element + "' (unit " + std::to_string(unit) + ") reads texture " +
                        describeObject(GL_TEXTURE, a.texture) + " level " + std::to_string(a.level) +
                        ", attached to framebuffer " + describeObject(GL_FRAMEBUFFER, fbo) + " as " +
                        attachmentName(a.point));
      }
    }
  }
  glActiveTexture(static_cast<GLenum>(activeTexture));
  return loops;
}

void assertNoFeedbackLoop(std::string_view pass) {
  if (!gChecks) return;
  std::vector<std::string> loops = findFeedbackLoops();
  std::vector<std::string> samplers = findSamplerProblems();
  ++gReport.draws;
  const bool debugOutput = glIsEnabled(GL_DEBUG_OUTPUT) == GL_TRUE;
  auto report = [&](const std::string& message) {
    logError(message);
    // Where the context has debug output, as a message of its own: what a stricter driver would say.
    if (debugOutput)
      glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR, 1, GL_DEBUG_SEVERITY_HIGH,
                           static_cast<GLsizei>(message.size()), message.c_str());
  };
  for (const std::string& loop : loops) {
    std::string message = std::string(pass) + ": feedback loop: " + loop;
    report(message);
    gReport.loops.push_back(std::move(message));
  }
  for (const std::string& problem : samplers) {
    std::string message = std::string(pass) + ": " + problem;
    report(message);
    gReport.samplers.push_back(std::move(message));
  }
  assert(loops.empty() && "a pass samples a texture attached to its own framebuffer (see the log)");
  assert(samplers.empty() && "a pass samples a unit without what its sampler declares (see the log)");
}

void setFeedbackLoopChecks(bool on) {
#ifdef NDEBUG
  gChecks = on;
#else
  (void)on;  // always on where assertions are
#endif
}

FeedbackLoopReport takeFeedbackLoopReport() { return std::exchange(gReport, {}); }

}  // namespace tandem::gl
