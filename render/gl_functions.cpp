#include "render/gl_functions.h"

#include <string>

namespace corridorsim::render {

GlFunctions LoadGlFunctions(const GlContext& context) {
  GlFunctions gl;
  std::string missing;
#define CORRIDORSIM_GL_LOAD(upper, name)                                              \
  gl.name = reinterpret_cast<PFNGL##upper##PROC>(context.GetProcAddress("gl" #name)); \
  if (gl.name == nullptr) missing += " gl" #name;
  CORRIDORSIM_GL_FUNCTIONS(CORRIDORSIM_GL_LOAD)
#undef CORRIDORSIM_GL_LOAD
  if (!missing.empty()) {
    throw RenderError(BackendName(context.kind()) + ": GL entry points not found:" + missing);
  }
  return gl;
}

const char* GlErrorName(GLenum error) {
  switch (error) {
    case GL_NO_ERROR:
      return "GL_NO_ERROR";
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    default:
      return "unknown GL error";
  }
}

}  // namespace corridorsim::render
