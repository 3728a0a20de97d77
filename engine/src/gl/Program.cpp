#include "gl/Program.h"

#include <cctype>
#include <set>
#include <sstream>
#include <vector>

#include "core/Embedded.h"

namespace tandem::gl {

namespace {

struct Expander {
  std::vector<std::string>& files;
  std::set<std::string> included;
  std::string out;

  Result<void> expand(const std::string& path, std::string_view defines, bool top) {
    auto text = findEmbedded(path);
    if (!text) return Error{"shader file '" + path + "' is not embedded (is it under shaders/?)"};
    int fileIndex = static_cast<int>(files.size());
    files.push_back(path);
    included.insert(path);
    std::istringstream in{std::string(*text)};
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
      ++lineNo;
      std::string_view trimmed = line;
      while (!trimmed.empty() && std::isspace(static_cast<unsigned char>(trimmed.front()))) trimmed.remove_prefix(1);
      if (top && trimmed.rfind("#version", 0) == 0) {
        out += line + "\n";
        out += std::string(defines);
        out += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(fileIndex) + "\n";
        continue;
      }
      if (trimmed.rfind("#include", 0) == 0) {
        auto open = trimmed.find('"');
        auto close = trimmed.rfind('"');
        if (open == std::string_view::npos || close <= open)
          return Error{path + ":" + std::to_string(lineNo) + ": malformed #include"};
        std::string name = "shaders/" + std::string(trimmed.substr(open + 1, close - open - 1));
        if (!included.count(name)) {
          out += "#line 1 " + std::to_string(files.size()) + "\n";
          auto ok = expand(name, {}, false);
          if (!ok) return Error{path + ":" + std::to_string(lineNo) + ": " + ok.error().message};
        }
        out += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(fileIndex) + "\n";
        continue;
      }
      out += line + "\n";
    }
    return {};
  }
};

// Mesa and most drivers start each message with "<source string>:<line>"; the source-string number is
// our file index.
std::string nameFiles(const std::string& log, const std::vector<std::string>& files) {
  std::istringstream in(log);
  std::string line, out;
  while (std::getline(in, line)) {
    std::size_t i = 0;
    while (i < line.size() && std::isdigit(static_cast<unsigned char>(line[i]))) ++i;
    if (i > 0 && i < line.size() && line[i] == ':') {
      std::size_t index = std::stoul(line.substr(0, i));
      if (index < files.size()) line = files[index] + line.substr(i);
    }
    out += "  " + line + "\n";
  }
  return out;
}

}  // namespace

Result<std::string> expandShaderSource(std::string_view path, std::string_view defines,
                                       std::vector<std::string>& fileNames) {
  Expander e{fileNames, {}, {}};
  auto ok = e.expand(std::string(path), defines, true);
  if (!ok) return ok.error();
  return std::move(e.out);
}

namespace {
const char* stageName(GLenum stage) {
  switch (stage) {
    case GL_VERTEX_SHADER: return "vertex stage";
    case GL_FRAGMENT_SHADER: return "fragment stage";
    case GL_GEOMETRY_SHADER: return "geometry stage";
    case GL_COMPUTE_SHADER: return "compute stage";
    default: return "another stage";
  }
}

// A compile that fails without a log is not the source's fault: say what the GL itself says (no context bound
// to this thread's GL, the shader object never made, an error pending).
std::string whyNoLog(GLuint shader) {
  std::string why;
  const GLubyte* version = glGetString(GL_VERSION);
  if (version == nullptr) why += "the thread's GL answers no GL_VERSION (is a context current on this thread?); ";
  else why += std::string("GL ") + reinterpret_cast<const char*>(version) + "; ";
  if (shader == 0) why += "glCreateShader returned 0; ";
  else if (glIsShader(shader) != GL_TRUE) why += "shader " + std::to_string(shader) + " is not a shader object; ";
  why += "glGetError: " + glErrorName(glGetError());
  return why;
}

// Per thread: GL work happens on the thread whose context is current, so a Renderer counts its own.
thread_local std::uint64_t tProgramsBuilt = 0;
}  // namespace

std::uint64_t programsBuilt() { return tProgramsBuilt; }

Result<Program> buildProgram(std::string_view label, std::initializer_list<ShaderSource> sources,
                             std::string_view defines) {
  ++tProgramsBuilt;
  Program program = createProgram(label);
  std::vector<Shader> shaders;
  for (const ShaderSource& s : sources) {
    std::vector<std::string> files;
    auto text = expandShaderSource(s.path, defines, files);
    if (!text) return Error{"program '" + std::string(label) + "': " + text.error().message};
    Shader shader = createShader(s.path, s.stage);
    const char* src = text->c_str();
    glShaderSource(shader.id(), 1, &src, nullptr);
    glCompileShader(shader.id());
    GLint ok = 0;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
      GLint length = 0;
      glGetShaderiv(shader.id(), GL_INFO_LOG_LENGTH, &length);
      std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
      glGetShaderInfoLog(shader.id(), length, nullptr, log.data());
      if (log.c_str()[0] == '\0')
        return Error{"program '" + std::string(label) + "': compiling " + std::string(s.path) + " (" +
                     stageName(s.stage) + ") failed with no info log: " + whyNoLog(shader.id())};
      return Error{"program '" + std::string(label) + "': compiling " + std::string(s.path) + " failed:\n" +
                   nameFiles(log.c_str(), files)};
    }
    glAttachShader(program.id(), shader.id());
    shaders.push_back(std::move(shader));
  }
  glLinkProgram(program.id());
  GLint ok = 0;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  for (const Shader& s : shaders) glDetachShader(program.id(), s.id());
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program.id(), length, nullptr, log.data());
    return Error{"program '" + std::string(label) + "': linking failed:\n" + std::string(log.c_str())};
  }
  return program;
}

}  // namespace tandem::gl
