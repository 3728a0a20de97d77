#pragma once
// Shader programs built from the embedded shaders/ files. `#include "x.glsl"` lines are expanded from
// shaders/x.glsl (once per program) with #line markers, and compile errors name the file and line.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "gl/GlObjects.h"
#include "tandem/Result.h"

namespace tandem::gl {

struct ShaderSource {
  GLenum stage;          // GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER
  std::string_view path;  // relative to the repository root, e.g. "shaders/shade.frag"
};

/// Compiles and links; `defines` is inserted after #version (e.g. "#define TD_OUTLINES 1\n").
Result<Program> buildProgram(std::string_view label, std::initializer_list<ShaderSource> sources,
                             std::string_view defines = {});
/// Programs buildProgram has compiled on the calling thread so far (FrameStats::shaderCompiles).
std::uint64_t programsBuilt();

/// Expanded source text of one shader with its includes (for tests and error messages).
Result<std::string> expandShaderSource(std::string_view path, std::string_view defines,
                                       std::vector<std::string>& fileNames);

}  // namespace tandem::gl
