#pragma once
// A linked GLSL program (vertex + fragment); attributes 0 = in_position, 1 = in_normal.
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "base/result.hpp"

namespace cathbox::app {

class ShaderProgram {
 public:
  ShaderProgram() = default;
  ~ShaderProgram();
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  // Compiles and links; or the driver's log as the error.
  [[nodiscard]] base::Status<> build(const char* vertex_src, const char* fragment_src);
  void use() const;
  void set(const char* name, const glm::mat4& m) const;
  void set(const char* name, const glm::vec4& v) const;
  void set(const char* name, float v) const;
  void set_int(const char* name, int v) const;  // e.g. a sampler's texture unit
  void set(const char* name, const glm::uvec4& v) const;

 private:
  unsigned id_ = 0;
};

}  // namespace cathbox::app
