#include "ptvDisplay.h"

#include "vtkOpenGLError.h" // GL enums (glew in VTK <= 9.3, glad later)
#include "vtkOpenGLFramebufferObject.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkRenderer.h"
#include "vtkShaderProgram.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace ptv
{
struct Display::Internals
{
  vtkSmartPointer<vtkTextureObject> Color;
  vtkSmartPointer<vtkTextureObject> Alpha;
  vtkSmartPointer<vtkTextureObject> Depth;
  std::vector<float> CoveredDepth; ///< the window depth of the covered rectangle
  std::unique_ptr<vtkOpenGLQuadHelper> Quad;
  /// Single-sample copy of a multisampled window's depth (ReadDepth), made for each read.
  vtkSmartPointer<vtkOpenGLFramebufferObject> Resolve;
};

namespace
{
const char* kDecl = "uniform sampler2D ptvColor;\n"
                    "uniform sampler2D ptvAlpha;\n"
                    "uniform sampler2D ptvDepth;\n"
                    "uniform float ptvLeast;\n"
                    "uniform vec2 ptvImage;\n"   // the image's size in pixels
                    "uniform vec2 ptvOrigin;\n"  // the covered rectangle's first pixel
                    "uniform vec2 ptvCovered;\n"; // its size: the textures'
const char* kImpl =
  "  vec2 t = (texCoord * ptvImage - ptvOrigin) / ptvCovered;\n"
  "  vec4 c = vec4(texture(ptvColor, t).rgb, texture(ptvAlpha, t).r);\n"
  "  float z = texture(ptvDepth, t).r;\n"
  "  if (c.a <= ptvLeast) { discard; }\n"
  "  gl_FragDepth = z;\n"
  "  gl_FragData[0] = c;\n";

/// Opacity a pixel needs for its depth to be written: later geometry, picking and other volumes
/// (whose rays stop at the depth buffer) see the volume only where it mostly hides what is
/// behind; a translucent volume drawn first would otherwise cut the rays of one behind it.
constexpr float kDepthOpacity = 0.5f;

void Allocate(vtkSmartPointer<vtkTextureObject>& tex, vtkOpenGLRenderWindow* win, int w, int h,
  int comps)
{
  if (!tex)
  {
    tex = vtkSmartPointer<vtkTextureObject>::New();
  }
  tex->SetContext(win);
  tex->SetMinificationFilter(vtkTextureObject::Nearest);
  tex->SetMagnificationFilter(vtkTextureObject::Nearest);
  tex->SetWrapS(vtkTextureObject::ClampToEdge);
  tex->SetWrapT(vtkTextureObject::ClampToEdge);
  tex->Allocate2D(static_cast<unsigned int>(w), static_cast<unsigned int>(h), comps, VTK_FLOAT);
}

/// The texture's width of @a rows rows of @a data (@a stride pixels a row).
void Upload(vtkTextureObject* tex, int rows, int stride, int comps, const float* data)
{
  tex->Bind();
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, stride);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, static_cast<GLsizei>(tex->GetWidth()), rows,
    comps == 3 ? GL_RGB : GL_RED, GL_FLOAT, data);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
}
}

//------------------------------------------------------------------------------
Display::Display()
  : Impl(new Internals)
{
}

//------------------------------------------------------------------------------
Display::~Display() = default;

//------------------------------------------------------------------------------
void Display::Draw(vtkRenderer* ren, int width, int height, const float* rgb, const float* alpha,
  const DepthRows& depth, const int covered[4])
{
  auto* win = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!win || width <= 0 || height <= 0 || covered[2] <= covered[0] || covered[3] <= covered[1])
  {
    return; // every fragment would be discarded
  }
  if (!this->Impl->Quad)
  {
    std::string fs = vtkOpenGLRenderUtilities::GetFullScreenQuadFragmentShaderTemplate();
    vtkShaderProgram::Substitute(fs, "//VTK::FSQ::Decl", kDecl);
    vtkShaderProgram::Substitute(fs, "//VTK::FSQ::Impl", kImpl);
    this->Impl->Quad.reset(new vtkOpenGLQuadHelper(win, nullptr, fs.c_str(), ""));
  }
  else
  {
    win->GetShaderCache()->ReadyShaderProgram(this->Impl->Quad->Program);
  }
  vtkShaderProgram* program = this->Impl->Quad->Program;
  if (!program || !program->GetCompiled())
  {
    return; // the shader cache already reported the compile error
  }

  vtkOpenGLState* state = win->GetState();
  vtkOpenGLState::ScopedglEnableDisable blendSaver(state, GL_BLEND);
  vtkOpenGLState::ScopedglEnableDisable depthSaver(state, GL_DEPTH_TEST);
  vtkOpenGLState::ScopedglBlendFuncSeparate blendFuncSaver(state);
  vtkOpenGLState::ScopedglDepthMask depthMaskSaver(state);
  vtkOpenGLState::ScopedglDepthFunc depthFuncSaver(state);
  vtkOpenGLState::ScopedglColorMask colorMaskSaver(state);
  state->vtkglEnable(GL_BLEND);
  state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  state->vtkglEnable(GL_DEPTH_TEST);
  state->vtkglDepthFunc(GL_ALWAYS); // rays already stop at opaque geometry

  // Only the rectangle the drawn pixels cover (the quad spans the viewport, one texel per
  // pixel): the fragments outside it would all be discarded, and a software rasteriser pays
  // for each of them. Within an enclosing scissor box, if one is set.
  int viewport[4];
  state->vtkglGetIntegerv(GL_VIEWPORT, viewport);
  const double sx = static_cast<double>(viewport[2]) / width;
  const double sy = static_cast<double>(viewport[3]) / height;
  int box[4] = { viewport[0] + static_cast<int>(std::floor(covered[0] * sx)),
    viewport[1] + static_cast<int>(std::floor(covered[1] * sy)),
    viewport[0] + static_cast<int>(std::ceil(covered[2] * sx)),
    viewport[1] + static_cast<int>(std::ceil(covered[3] * sy)) };
  vtkOpenGLState::ScopedglEnableDisable scissorTestSaver(state, GL_SCISSOR_TEST);
  vtkOpenGLState::ScopedglScissor scissorSaver(state);
  if (state->GetEnumState(GL_SCISSOR_TEST))
  {
    int outer[4];
    state->vtkglGetIntegerv(GL_SCISSOR_BOX, outer);
    box[0] = std::max(box[0], outer[0]);
    box[1] = std::max(box[1], outer[1]);
    box[2] = std::min(box[2], outer[0] + outer[2]);
    box[3] = std::min(box[3], outer[1] + outer[3]);
  }
  if (box[2] <= box[0] || box[3] <= box[1])
  {
    return;
  }
  state->vtkglEnable(GL_SCISSOR_TEST);

  // Textures of the covered rectangle alone, made for this image and released after it (the
  // window's memory is not held between frames).
  const int x0 = covered[0];
  const int y0 = covered[1];
  const int columns = covered[2] - covered[0];
  const int rows = covered[3] - covered[1];
  Internals& in = *this->Impl;
  Allocate(in.Color, win, columns, rows, 3);
  Allocate(in.Alpha, win, columns, rows, 1);
  Allocate(in.Depth, win, columns, rows, 1);
  in.CoveredDepth.resize(static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows));
  depth(x0, y0, covered[2], covered[3], in.CoveredDepth.data());
  const std::size_t first = static_cast<std::size_t>(y0) * width + x0;
  Upload(in.Color, rows, width, 3, rgb + 3 * first);
  Upload(in.Alpha, rows, width, 1, alpha + first);
  Upload(in.Depth, rows, columns, 1, in.CoveredDepth.data());
  in.Color->Activate();
  in.Alpha->Activate();
  in.Depth->Activate();
  program->SetUniformi("ptvColor", in.Color->GetTextureUnit());
  program->SetUniformi("ptvAlpha", in.Alpha->GetTextureUnit());
  program->SetUniformi("ptvDepth", in.Depth->GetTextureUnit());
  const float image[2] = { static_cast<float>(width), static_cast<float>(height) };
  const float origin[2] = { static_cast<float>(x0), static_cast<float>(y0) };
  const float size[2] = { static_cast<float>(columns), static_cast<float>(rows) };
  program->SetUniform2f("ptvImage", image);
  program->SetUniform2f("ptvOrigin", origin);
  program->SetUniform2f("ptvCovered", size);
  state->vtkglScissor(box[0], box[1], box[2] - box[0], box[3] - box[1]);
  // Colour: every drawn pixel, no depth; then depth alone where the volume is mostly opaque.
  state->vtkglDepthMask(GL_FALSE);
  program->SetUniformf("ptvLeast", 0.0f);
  this->Impl->Quad->Render();
  state->vtkglColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  state->vtkglDepthMask(GL_TRUE);
  program->SetUniformf("ptvLeast", kDepthOpacity);
  this->Impl->Quad->Render();
  in.Depth->Deactivate();
  in.Alpha->Deactivate();
  in.Color->Deactivate();
  for (vtkTextureObject* tex : { in.Color.Get(), in.Alpha.Get(), in.Depth.Get() })
  {
    tex->ReleaseGraphicsResources(win);
  }
  std::vector<float>().swap(in.CoveredDepth);
}

//------------------------------------------------------------------------------
bool Display::ReadDepth(vtkRenderer* ren, int x0, int y0, int width, int height, float* depth)
{
  auto* win = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!win || width <= 0 || height <= 0)
  {
    return false;
  }
  vtkOpenGLState* state = win->GetState();
  unsigned int drawBinding = 0, drawBuffer = 0;
  state->GetCurrentDrawFramebufferState(drawBinding, drawBuffer);
  state->PushFramebufferBindings();
  state->vtkglBindFramebuffer(GL_READ_FRAMEBUFFER, drawBinding);
  while (glGetError() != GL_NO_ERROR)
  {
  }
  GLint samples = 0;
  glGetIntegerv(GL_SAMPLES, &samples);
  vtkOpenGLFramebufferObject* source = win->GetRenderFramebuffer();
  bool resolved = false;
  if (samples > 0 && source && source->GetFBOIndex() == drawBinding)
  {
    // A multisampled framebuffer (a default vtkRenderWindow asks for 8 samples) cannot be read:
    // resolve its depth into a single-sample framebuffer of the same size and format first.
    // Depth alone (no colour attachment where the driver allows), made for this read and
    // released after it: the window's memory is not held between frames.
    const int* size = source->GetLastSize();
    if (!this->Impl->Resolve)
    {
      this->Impl->Resolve = vtkSmartPointer<vtkOpenGLFramebufferObject>::New();
    }
    vtkOpenGLFramebufferObject* resolve = this->Impl->Resolve;
    resolve->SetContext(win);
    for (const int colors : { 0, 1 })
    {
      resolve->PopulateFramebuffer(size[0], size[1], true, colors, VTK_UNSIGNED_CHAR, true, 32, 0,
        win->GetStencilCapable() != 0);
      if (colors == 0)
      {
        state->vtkglDrawBuffer(GL_NONE);
        state->vtkglReadBuffer(GL_NONE);
      }
      if (glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE)
      {
        break;
      }
    }
    state->vtkglBindFramebuffer(GL_READ_FRAMEBUFFER, drawBinding);
    state->vtkglBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve->GetFBOIndex());
    glBlitFramebuffer(x0, y0, x0 + width, y0 + height, x0, y0, x0 + width, y0 + height,
      GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    state->vtkglBindFramebuffer(GL_READ_FRAMEBUFFER, resolve->GetFBOIndex());
    resolved = true;
  }
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(x0, y0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
  const bool ok = glGetError() == GL_NO_ERROR;
  state->PopFramebufferBindings();
  if (resolved)
  {
    this->Impl->Resolve->ReleaseGraphicsResources(win);
  }
  return ok;
}

//------------------------------------------------------------------------------
void Display::ReleaseGraphicsResources(vtkWindow* window)
{
  if (this->Impl->Quad)
  {
    this->Impl->Quad->ReleaseGraphicsResources(window);
    this->Impl->Quad.reset();
  }
  for (vtkTextureObject* tex : { this->Impl->Color.Get(), this->Impl->Alpha.Get(),
         this->Impl->Depth.Get() })
  {
    if (tex)
    {
      tex->ReleaseGraphicsResources(window);
    }
  }
  if (this->Impl->Resolve)
  {
    this->Impl->Resolve->ReleaseGraphicsResources(window);
    this->Impl->Resolve = nullptr;
  }
}
}
