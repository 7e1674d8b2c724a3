#include "app/shader_program.hpp"

#include <glm/gtc/type_ptr.hpp>

#include "app/gl.hpp"

namespace cathbox::app {
namespace {

base::Result<GLuint> compile(GLenum kind, const char* src) {
  const GLuint s = glCreateShader(kind);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (ok == GL_FALSE) {
    char log[1024] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    return base::Error{std::string(kind == GL_VERTEX_SHADER ? "vertex" : "fragment") + " shader: " + log};
  }
  return s;
}

}  // namespace

ShaderProgram::~ShaderProgram() {
  if (id_ != 0) glDeleteProgram(id_);
}

base::Status<> ShaderProgram::build(const char* vertex_src, const char* fragment_src) {
  const base::Result<GLuint> vertex = compile(GL_VERTEX_SHADER, vertex_src);
  if (!vertex) return vertex.error();
  const base::Result<GLuint> fragment = compile(GL_FRAGMENT_SHADER, fragment_src);
  if (!fragment) {
    glDeleteShader(*vertex);
    return fragment.error();
  }
  const GLuint vs = *vertex;
  const GLuint fs = *fragment;
  id_ = glCreateProgram();
  glAttachShader(id_, vs);
  glAttachShader(id_, fs);
  glBindAttribLocation(id_, 0, "in_position");
  glBindAttribLocation(id_, 1, "in_normal");
  glLinkProgram(id_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (ok == GL_FALSE) {
    char log[1024] = {};
    glGetProgramInfoLog(id_, sizeof log, nullptr, log);
    return base::Error{std::string("shader link: ") + log};
  }
  return base::Ok{};
}

void ShaderProgram::use() const { glUseProgram(id_); }

void ShaderProgram::set(const char* name, const glm::mat4& m) const {
  glUniformMatrix4fv(glGetUniformLocation(id_, name), 1, GL_FALSE, glm::value_ptr(m));
}
void ShaderProgram::set(const char* name, const glm::vec4& v) const {
  glUniform4fv(glGetUniformLocation(id_, name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(const char* name, float v) const {
  glUniform1f(glGetUniformLocation(id_, name), v);
}
void ShaderProgram::set(const char* name, const glm::uvec4& v) const {
  glUniform4ui(glGetUniformLocation(id_, name), v.x, v.y, v.z, v.w);
}
void ShaderProgram::set_int(const char* name, int v) const { glUniform1i(glGetUniformLocation(id_, name), v); }

}  // namespace cathbox::app
