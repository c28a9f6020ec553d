// The OpenGL functions reel uses, loaded at run time through the current context's
// getProcAddress (OSMesa exports its own GL, EGL goes through GLVND): no link to libGL, so the
// binary starts on machines without one. Every GL call in reel goes through GlApi.
#pragma once

#define GL_GLEXT_PROTOTYPES 0
#include <GL/glcorearb.h>

#include <string>

#include "core/error.h"

namespace reel::gl {

// X-macro: (name without the gl prefix, its PFNGL...PROC type).
#define REEL_GL_FUNCTIONS(X)                                              \
  X(GetError, PFNGLGETERRORPROC)                                          \
  X(GetString, PFNGLGETSTRINGPROC)                                        \
  X(GetIntegerv, PFNGLGETINTEGERVPROC)                                    \
  X(Enable, PFNGLENABLEPROC)                                              \
  X(Disable, PFNGLDISABLEPROC)                                            \
  X(Viewport, PFNGLVIEWPORTPROC)                                          \
  X(ClearColor, PFNGLCLEARCOLORPROC)                                      \
  X(ClearDepth, PFNGLCLEARDEPTHPROC)                                      \
  X(Clear, PFNGLCLEARPROC)                                                \
  X(DepthFunc, PFNGLDEPTHFUNCPROC)                                        \
  X(DepthMask, PFNGLDEPTHMASKPROC)                                        \
  X(ColorMask, PFNGLCOLORMASKPROC)                                        \
  X(CullFace, PFNGLCULLFACEPROC)                                          \
  X(BlendFunc, PFNGLBLENDFUNCPROC)                                        \
  X(PolygonOffset, PFNGLPOLYGONOFFSETPROC)                                \
  X(PixelStorei, PFNGLPIXELSTOREIPROC)                                    \
  X(ReadPixels, PFNGLREADPIXELSPROC)                                      \
  X(Finish, PFNGLFINISHPROC)                                              \
  X(GenFramebuffers, PFNGLGENFRAMEBUFFERSPROC)                            \
  X(DeleteFramebuffers, PFNGLDELETEFRAMEBUFFERSPROC)                      \
  X(BindFramebuffer, PFNGLBINDFRAMEBUFFERPROC)                            \
  X(FramebufferRenderbuffer, PFNGLFRAMEBUFFERRENDERBUFFERPROC)            \
  X(FramebufferTexture2D, PFNGLFRAMEBUFFERTEXTURE2DPROC)                  \
  X(CheckFramebufferStatus, PFNGLCHECKFRAMEBUFFERSTATUSPROC)              \
  X(BlitFramebuffer, PFNGLBLITFRAMEBUFFERPROC)                            \
  X(DrawBuffer, PFNGLDRAWBUFFERPROC)                                      \
  X(ReadBuffer, PFNGLREADBUFFERPROC)                                      \
  X(GenRenderbuffers, PFNGLGENRENDERBUFFERSPROC)                          \
  X(DeleteRenderbuffers, PFNGLDELETERENDERBUFFERSPROC)                    \
  X(BindRenderbuffer, PFNGLBINDRENDERBUFFERPROC)                          \
  X(RenderbufferStorageMultisample, PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC) \
  X(GenTextures, PFNGLGENTEXTURESPROC)                                    \
  X(DeleteTextures, PFNGLDELETETEXTURESPROC)                              \
  X(BindTexture, PFNGLBINDTEXTUREPROC)                                    \
  X(ActiveTexture, PFNGLACTIVETEXTUREPROC)                                \
  X(TexImage2D, PFNGLTEXIMAGE2DPROC)                                      \
  X(TexParameteri, PFNGLTEXPARAMETERIPROC)                                \
  X(GenSamplers, PFNGLGENSAMPLERSPROC)                                    \
  X(DeleteSamplers, PFNGLDELETESAMPLERSPROC)                              \
  X(BindSampler, PFNGLBINDSAMPLERPROC)                                    \
  X(SamplerParameteri, PFNGLSAMPLERPARAMETERIPROC)                        \
  X(TexParameterfv, PFNGLTEXPARAMETERFVPROC)                              \
  X(GenerateMipmap, PFNGLGENERATEMIPMAPPROC)                              \
  X(GenBuffers, PFNGLGENBUFFERSPROC)                                      \
  X(DeleteBuffers, PFNGLDELETEBUFFERSPROC)                                \
  X(BindBuffer, PFNGLBINDBUFFERPROC)                                      \
  X(BufferData, PFNGLBUFFERDATAPROC)                                      \
  X(BufferSubData, PFNGLBUFFERSUBDATAPROC)                                \
  X(GenVertexArrays, PFNGLGENVERTEXARRAYSPROC)                            \
  X(DeleteVertexArrays, PFNGLDELETEVERTEXARRAYSPROC)                      \
  X(BindVertexArray, PFNGLBINDVERTEXARRAYPROC)                            \
  X(EnableVertexAttribArray, PFNGLENABLEVERTEXATTRIBARRAYPROC)            \
  X(DisableVertexAttribArray, PFNGLDISABLEVERTEXATTRIBARRAYPROC)          \
  X(VertexAttribPointer, PFNGLVERTEXATTRIBPOINTERPROC)                    \
  X(VertexAttribDivisor, PFNGLVERTEXATTRIBDIVISORPROC)                    \
  X(VertexAttrib3f, PFNGLVERTEXATTRIB3FPROC)                              \
  X(VertexAttrib1f, PFNGLVERTEXATTRIB1FPROC)                              \
  X(VertexAttrib2f, PFNGLVERTEXATTRIB2FPROC)                              \
  X(DrawArrays, PFNGLDRAWARRAYSPROC)                                      \
  X(DrawElements, PFNGLDRAWELEMENTSPROC)                                  \
  X(DrawElementsInstanced, PFNGLDRAWELEMENTSINSTANCEDPROC)                \
  X(CreateShader, PFNGLCREATESHADERPROC)                                  \
  X(DeleteShader, PFNGLDELETESHADERPROC)                                  \
  X(ShaderSource, PFNGLSHADERSOURCEPROC)                                  \
  X(CompileShader, PFNGLCOMPILESHADERPROC)                                \
  X(GetShaderiv, PFNGLGETSHADERIVPROC)                                    \
  X(GetShaderInfoLog, PFNGLGETSHADERINFOLOGPROC)                          \
  X(CreateProgram, PFNGLCREATEPROGRAMPROC)                                \
  X(DeleteProgram, PFNGLDELETEPROGRAMPROC)                                \
  X(AttachShader, PFNGLATTACHSHADERPROC)                                  \
  X(LinkProgram, PFNGLLINKPROGRAMPROC)                                    \
  X(GetProgramiv, PFNGLGETPROGRAMIVPROC)                                  \
  X(GetProgramInfoLog, PFNGLGETPROGRAMINFOLOGPROC)                        \
  X(UseProgram, PFNGLUSEPROGRAMPROC)                                      \
  X(GetUniformLocation, PFNGLGETUNIFORMLOCATIONPROC)                      \
  X(Uniform1i, PFNGLUNIFORM1IPROC)                                        \
  X(Uniform1f, PFNGLUNIFORM1FPROC)                                        \
  X(Uniform3f, PFNGLUNIFORM3FPROC)                                        \
  X(Uniform4f, PFNGLUNIFORM4FPROC)                                        \
  X(Uniform2f, PFNGLUNIFORM2FPROC)                                        \
  X(Uniform4fv, PFNGLUNIFORM4FVPROC)                                      \
  X(Uniform1fv, PFNGLUNIFORM1FVPROC)                                      \
  X(Uniform3fv, PFNGLUNIFORM3FVPROC)                                      \
  X(Uniform1iv, PFNGLUNIFORM1IVPROC)                                      \
  X(UniformMatrix4fv, PFNGLUNIFORMMATRIX4FVPROC)

struct GlApi {
#define REEL_GL_MEMBER(name, type) type name = nullptr;
  REEL_GL_FUNCTIONS(REEL_GL_MEMBER)
#undef REEL_GL_MEMBER
};

using ProcLoader = void* (*)(const char* name);

// Fills every entry through `load`; fails naming the first missing function.
Status loadGlApi(ProcLoader load, GlApi& api);

}  // namespace reel::gl
