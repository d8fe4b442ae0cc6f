#include "render/shader_program.h"

#include <stdexcept>
#include <vector>

#include "common/check.h"
#include "render/gl.h"

namespace viscera::render {
namespace {

GLuint Compile(GLenum kind, const std::string& source) {
  const GLuint shader = glCreateShader(kind);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<size_t>(length) + 1, '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    throw std::runtime_error(Cat(kind == GL_VERTEX_SHADER ? "vertex" : "fragment",
                                 " shader failed to compile: ", log.data()));
  }
  return shader;
}

}  // namespace

ShaderProgram::ShaderProgram(const std::string& vertex_source, const std::string& fragment_source) {
  const GLuint vertex = Compile(GL_VERTEX_SHADER, vertex_source);
  GLuint fragment = 0;
  try {
    fragment = Compile(GL_FRAGMENT_SHADER, fragment_source);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  program_ = glCreateProgram();
  glAttachShader(program_, vertex);
  glAttachShader(program_, fragment);
  glLinkProgram(program_);
  // The program keeps what it needs; the shader objects can go now.
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint length = 0;
    glGetProgramiv(program_, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<size_t>(length) + 1, '\0');
    glGetProgramInfoLog(program_, length, nullptr, log.data());
    glDeleteProgram(program_);
    throw std::runtime_error(Cat("shader program failed to link: ", log.data()));
  }
}

ShaderProgram::~ShaderProgram() {
  if (program_ != 0) glDeleteProgram(program_);
}

void ShaderProgram::Use() const { glUseProgram(program_); }

int ShaderProgram::Uniform(const char* name) const {
  const GLint location = glGetUniformLocation(program_, name);
  if (location < 0) throw std::runtime_error(Cat("shader program has no uniform '", name, "'"));
  return location;
}

}  // namespace viscera::render
