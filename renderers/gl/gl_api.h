#pragma once
// The OpenGL 4.5 core entry points the gl backend calls, as one table of function pointers
// loaded through the platform's GetProcAddress (OSMesa or EGL; gl_context.cpp). Nothing here
// links a GL symbol directly: libOSMesa does not export the DSA entry points, and linking libGL
// or libOpenGL beside it makes calls go silently nowhere (design.md §5). One table per context,
// no globals.

#include <GL/glcorearb.h>

namespace svr::gl {

// X(type, name): the function glName of type PFNGLNAMEPROC is loaded into GlApi::name.
#define SVR_GL_FUNCTIONS(X)                                              \
  X(PFNGLGETSTRINGPROC, GetString)                                       \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                   \
  X(PFNGLGETFLOATVPROC, GetFloatv)                                       \
  X(PFNGLGETINTEGER64VPROC, GetInteger64v)                               \
  X(PFNGLGETINTEGERI_VPROC, GetIntegeri_v)                               \
  X(PFNGLGETERRORPROC, GetError)                                         \
  X(PFNGLENABLEPROC, Enable)                                             \
  X(PFNGLDISABLEPROC, Disable)                                           \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                                       \
  X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)                       \
  X(PFNGLBLENDEQUATIONPROC, BlendEquation)                               \
  X(PFNGLVIEWPORTPROC, Viewport)                                         \
  X(PFNGLSCISSORPROC, Scissor)                                           \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                     \
  X(PFNGLDEBUGMESSAGECALLBACKPROC, DebugMessageCallback)                 \
  X(PFNGLCREATESHADERPROC, CreateShader)                                 \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                 \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                               \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                   \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                         \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                 \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                               \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                 \
  X(PFNGLDETACHSHADERPROC, DetachShader)                                 \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                   \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                 \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                       \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                               \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                     \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                     \
  X(PFNGLPROGRAMUNIFORM1IPROC, ProgramUniform1i)                         \
  X(PFNGLPROGRAMUNIFORM1FPROC, ProgramUniform1f)                         \
  X(PFNGLPROGRAMUNIFORM2FPROC, ProgramUniform2f)                         \
  X(PFNGLPROGRAMUNIFORM3FPROC, ProgramUniform3f)                         \
  X(PFNGLPROGRAMUNIFORM3IPROC, ProgramUniform3i)                         \
  X(PFNGLPROGRAMUNIFORM4FPROC, ProgramUniform4f)                         \
  X(PFNGLPROGRAMUNIFORM1FVPROC, ProgramUniform1fv)                       \
  X(PFNGLCREATEBUFFERSPROC, CreateBuffers)                               \
  X(PFNGLNAMEDBUFFERSTORAGEPROC, NamedBufferStorage)                     \
  X(PFNGLNAMEDBUFFERSUBDATAPROC, NamedBufferSubData)                     \
  X(PFNGLGETNAMEDBUFFERSUBDATAPROC, GetNamedBufferSubData)               \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                               \
  X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                             \
  X(PFNGLCREATETEXTURESPROC, CreateTextures)                             \
  X(PFNGLTEXTURESTORAGE2DPROC, TextureStorage2D)                         \
  X(PFNGLTEXTURESTORAGE3DPROC, TextureStorage3D)                         \
  X(PFNGLTEXTURESUBIMAGE3DPROC, TextureSubImage3D)                       \
  X(PFNGLTEXTURESUBIMAGE2DPROC, TextureSubImage2D)                       \
  X(PFNGLTEXTUREPARAMETERIPROC, TextureParameteri)                       \
  X(PFNGLGETTEXTURESUBIMAGEPROC, GetTextureSubImage)                     \
  X(PFNGLBINDTEXTUREUNITPROC, BindTextureUnit)                           \
  X(PFNGLTEXTUREBUFFERPROC, TextureBuffer)                               \
  X(PFNGLBINDIMAGETEXTUREPROC, BindImageTexture)                         \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                             \
  X(PFNGLCREATEFRAMEBUFFERSPROC, CreateFramebuffers)                     \
  X(PFNGLNAMEDFRAMEBUFFERTEXTUREPROC, NamedFramebufferTexture)           \
  X(PFNGLNAMEDFRAMEBUFFERTEXTURELAYERPROC, NamedFramebufferTextureLayer) \
  X(PFNGLNAMEDFRAMEBUFFERDRAWBUFFERSPROC, NamedFramebufferDrawBuffers)   \
  X(PFNGLCHECKNAMEDFRAMEBUFFERSTATUSPROC, CheckNamedFramebufferStatus)   \
  X(PFNGLCLEARNAMEDFRAMEBUFFERFVPROC, ClearNamedFramebufferfv)           \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                           \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                     \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                     \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                   \
  X(PFNGLCREATEVERTEXARRAYSPROC, CreateVertexArrays)                     \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                           \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                     \
  X(PFNGLDISPATCHCOMPUTEPROC, DispatchCompute)                           \
  X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)

struct GlApi {
#define SVR_GL_MEMBER(type, name) type name = nullptr;
  SVR_GL_FUNCTIONS(SVR_GL_MEMBER)
#undef SVR_GL_MEMBER
};

}  // namespace svr::gl
