#pragma once
// The GL 3.3 core entry points the renderer uses, loaded through a context's GetProcAddress
// (no libGL / libOpenGL link and no GLEW: GLEW does not initialise under OSMesa).

#include <GL/glcorearb.h>

#include "render/gl_context.h"

namespace corridorsim::render {

// X(UPPERCASE, CamelCase): member `CamelCase` of type PFNGL<UPPERCASE>PROC, loaded as
// "gl<CamelCase>".
#define CORRIDORSIM_GL_FUNCTIONS(X)                   \
  X(ACTIVETEXTURE, ActiveTexture)                     \
  X(ATTACHSHADER, AttachShader)                       \
  X(BINDBUFFER, BindBuffer)                           \
  X(BINDFRAMEBUFFER, BindFramebuffer)                 \
  X(BINDRENDERBUFFER, BindRenderbuffer)               \
  X(BINDTEXTURE, BindTexture)                         \
  X(BINDVERTEXARRAY, BindVertexArray)                 \
  X(BUFFERDATA, BufferData)                           \
  X(CHECKFRAMEBUFFERSTATUS, CheckFramebufferStatus)   \
  X(COLORMASK, ColorMask)                             \
  X(CLEARBUFFERFV, ClearBufferfv)                     \
  X(CLEARBUFFERUIV, ClearBufferuiv)                   \
  X(COMPILESHADER, CompileShader)                     \
  X(CREATEPROGRAM, CreateProgram)                     \
  X(CREATESHADER, CreateShader)                       \
  X(DELETEBUFFERS, DeleteBuffers)                     \
  X(DELETEFRAMEBUFFERS, DeleteFramebuffers)           \
  X(DELETEPROGRAM, DeleteProgram)                     \
  X(DELETERENDERBUFFERS, DeleteRenderbuffers)         \
  X(DELETESHADER, DeleteShader)                       \
  X(DELETETEXTURES, DeleteTextures)                   \
  X(DELETEVERTEXARRAYS, DeleteVertexArrays)           \
  X(DEPTHFUNC, DepthFunc)                             \
  X(FRONTFACE, FrontFace)                             \
  X(CULLFACE, CullFace)                               \
  X(DISABLE, Disable)                                 \
  X(DRAWARRAYS, DrawArrays)                           \
  X(DRAWBUFFERS, DrawBuffers)                         \
  X(DRAWELEMENTS, DrawElements)                       \
  X(ENABLE, Enable)                                   \
  X(ENABLEVERTEXATTRIBARRAY, EnableVertexAttribArray) \
  X(FINISH, Finish)                                   \
  X(FRAMEBUFFERRENDERBUFFER, FramebufferRenderbuffer) \
  X(GENBUFFERS, GenBuffers)                           \
  X(GENERATEMIPMAP, GenerateMipmap)                   \
  X(GENFRAMEBUFFERS, GenFramebuffers)                 \
  X(GENRENDERBUFFERS, GenRenderbuffers)               \
  X(GENTEXTURES, GenTextures)                         \
  X(GENVERTEXARRAYS, GenVertexArrays)                 \
  X(GETERROR, GetError)                               \
  X(GETINTEGERV, GetIntegerv)                         \
  X(GETPROGRAMINFOLOG, GetProgramInfoLog)             \
  X(GETPROGRAMIV, GetProgramiv)                       \
  X(GETSHADERINFOLOG, GetShaderInfoLog)               \
  X(GETSHADERIV, GetShaderiv)                         \
  X(GETSTRING, GetString)                             \
  X(GETUNIFORMLOCATION, GetUniformLocation)           \
  X(LINKPROGRAM, LinkProgram)                         \
  X(PIXELSTOREI, PixelStorei)                         \
  X(READBUFFER, ReadBuffer)                           \
  X(READPIXELS, ReadPixels)                           \
  X(RENDERBUFFERSTORAGE, RenderbufferStorage)         \
  X(SHADERSOURCE, ShaderSource)                       \
  X(TEXIMAGE2D, TexImage2D)                           \
  X(TEXPARAMETERI, TexParameteri)                     \
  X(UNIFORM1F, Uniform1f)                             \
  X(UNIFORM1I, Uniform1i)                             \
  X(UNIFORM1UI, Uniform1ui)                           \
  X(UNIFORM3F, Uniform3f)                             \
  X(UNIFORM3FV, Uniform3fv)                           \
  X(UNIFORMMATRIX4FV, UniformMatrix4fv)               \
  X(USEPROGRAM, UseProgram)                           \
  X(VERTEXATTRIBPOINTER, VertexAttribPointer)         \
  X(VIEWPORT, Viewport)

/// One context's GL function table. Entry points are per context: never share a table between
/// contexts of different backends.
struct GlFunctions {
#define CORRIDORSIM_GL_MEMBER(upper, name) PFNGL##upper##PROC name = nullptr;
  CORRIDORSIM_GL_FUNCTIONS(CORRIDORSIM_GL_MEMBER)
#undef CORRIDORSIM_GL_MEMBER
};

/// Loads every entry point of GlFunctions through `context` (which must be current). Throws
/// RenderError naming the backend and every missing function.
GlFunctions LoadGlFunctions(const GlContext& context);

/// "GL_INVALID_OPERATION" etc. for a glGetError code.
const char* GlErrorName(GLenum error);

}  // namespace corridorsim::render
