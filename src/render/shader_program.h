#pragma once
/// ShaderProgram: compiles and links a GLSL vertex + fragment shader pair.
#include <string>

namespace viscera::render {

class ShaderProgram {
 public:
  /// @pre a GL context (OffscreenContext) is current on this thread.
  /// @throws std::runtime_error with the driver's log when compiling or linking fails
  ///         (the sources are ours, so a failure is a bug or a missing GL feature).
  ShaderProgram(const std::string& vertex_source, const std::string& fragment_source);
  ~ShaderProgram();
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  /// Makes this program current.
  void Use() const;
  /// Location of a uniform. @throws std::runtime_error when the program has none so named.
  int Uniform(const char* name) const;
  unsigned id() const { return program_; }

 private:
  unsigned program_ = 0;
};

}  // namespace viscera::render
