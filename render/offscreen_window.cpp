// Off-screen OpenGL for VTK without any display, and the GLEW/GLX shim it needs on Debian's VTK.
//
// Debian 12's VTK 9.1 is built for X11 only (VTK_OPENGL_HAS_OSMESA undefined), so there is no
// vtkOSOpenGLRenderWindow and it loads GL entry points through the system GLEW, a GLX build.
// We therefore (1) create an OSMesa context ourselves and hand it to a
// vtkGenericOpenGLRenderWindow, (2) make GLEW resolve GL functions from OSMesa by defining
// glXGetProcAddress[ARB] in the program (exported with --export-dynamic-symbol, see
// render/CMakeLists.txt; libOSMesa is linked ahead of VTK so direct GL 1.x calls bind to it too),
// and (3) interpose glewInit, whose GLX half fails without a display although the GL half, all
// that an OSMesa context needs, succeeded. Where VTK itself was built with OSMesa, none of this is
// compiled and VTK's own off-screen window is used.
// Background: docs/rendering.md.
#include "offscreen_window.hpp"

#include <vtkRenderingOpenGLConfigure.h>  // VTK_OPENGL_HAS_OSMESA
#include <vtkRenderWindow.h>
#include <vtkSmartPointer.h>

#include "error.hpp"

#ifdef VTK_OPENGL_HAS_OSMESA

namespace brittle::render {

struct OffscreenWindow::Context {
  vtkSmartPointer<vtkRenderWindow> window;
};

OffscreenWindow::OffscreenWindow(int width, int height)
    : width_(width), height_(height), context_(std::make_unique<Context>()) {
  BRITTLE_CHECK(width > 0 && height > 0, "render: window size ", width, " x ", height,
                " (expected positive)");
  context_->window = vtkSmartPointer<vtkRenderWindow>::New();  // vtkOSOpenGLRenderWindow
  context_->window->SetOffScreenRendering(true);
  context_->window->SetSize(width, height);
}

OffscreenWindow::~OffscreenWindow() = default;

vtkRenderWindow* OffscreenWindow::window() const { return context_->window; }

}  // namespace brittle::render

#else  // VTK built for X11: our own OSMesa context + the shim below

#include <dlfcn.h>

#include <cstring>
#include <vector>

#include <GL/osmesa.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkGenericOpenGLRenderWindow.h>

// ---- The shim: symbols that libGLEW and VTK resolve to the program's definitions. ----------
extern "C" {

using GlProc = void (*)();

/// GLEW asks GLX for every GL entry point; answer gl* names from OSMesa (the context we use),
/// and pass genuine glX* names on to the real libGLX.
static GlProc brittle_get_proc(const unsigned char* name, const char* glx_symbol) {
  const char* n = reinterpret_cast<const char*>(name);
  if (n && std::strncmp(n, "gl", 2) == 0 && std::strncmp(n, "glX", 3) != 0)
    return reinterpret_cast<GlProc>(OSMesaGetProcAddress(n));
  using Real = GlProc (*)(const unsigned char*);
  auto real = reinterpret_cast<Real>(dlsym(RTLD_NEXT, glx_symbol));
  return real ? real(name) : nullptr;
}

__attribute__((visibility("default"))) GlProc glXGetProcAddressARB(const unsigned char* name) {
  return brittle_get_proc(name, "glXGetProcAddressARB");
}

__attribute__((visibility("default"))) GlProc glXGetProcAddress(const unsigned char* name) {
  return brittle_get_proc(name, "glXGetProcAddress");
}

/// glewInit = GL part (succeeds through the functions above) + GLX part, which fails with
/// GLEW_ERROR_NO_GLX_DISPLAY (4) without a display; VTK would then log "GLEW could not be
/// initialized" and skip part of its context set-up on every frame. Report that case as
/// GLEW_OK (0).
__attribute__((visibility("default"))) unsigned int glewInit() {
  constexpr unsigned int glew_ok = 0, glew_error_no_glx_display = 4;
  using Real = unsigned int (*)();
  static const auto real = reinterpret_cast<Real>(dlsym(RTLD_NEXT, "glewInit"));
  if (!real) return 1;  // GLEW_ERROR_NO_GL_VERSION: no GLEW at all
  const unsigned int status = real();
  return status == glew_error_no_glx_display ? glew_ok : status;
}

}  // extern "C"

namespace brittle::render {

struct OffscreenWindow::Context {
  OSMesaContext gl = nullptr;
  std::vector<unsigned char> pixels;  ///< OSMesa's colour buffer, width * height RGBA
  int width = 0, height = 0;
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> window;
  vtkSmartPointer<vtkCallbackCommand> make_current, is_current;

  bool current() const { return OSMesaGetCurrentContext() == gl; }
  void make() {
    if (!current()) OSMesaMakeCurrent(gl, pixels.data(), GL_UNSIGNED_BYTE, width, height);
  }
};

OffscreenWindow::OffscreenWindow(int width, int height)
    : width_(width), height_(height), context_(std::make_unique<Context>()) {
  BRITTLE_CHECK(width > 0 && height > 0, "render: window size ", width, " x ", height,
                " (expected positive)");
  Context& c = *context_;
  const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA,
                            OSMESA_DEPTH_BITS, 24,
                            OSMESA_STENCIL_BITS, 0,
                            OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, 3,
                            OSMESA_CONTEXT_MINOR_VERSION, 2,
                            0};
  c.gl = OSMesaCreateContextAttribs(attributes, nullptr);
  BRITTLE_CHECK(c.gl, "render: OSMesa could not create a GL 3.2 core context (is libosmesa6 "
                "installed?)");
  c.width = width;
  c.height = height;
  c.pixels.assign(static_cast<std::size_t>(width) * height * 4, 0);
  BRITTLE_CHECK(OSMesaMakeCurrent(c.gl, c.pixels.data(), GL_UNSIGNED_BYTE, width, height),
                "render: OSMesa could not make its context current (", width, " x ", height, ")");

  // VTK asks the generic window to make its context current / whether it is; we answer for
  // OSMesa, so that several windows can take turns.
  c.make_current = vtkSmartPointer<vtkCallbackCommand>::New();
  c.make_current->SetClientData(&c);
  c.make_current->SetCallback([](vtkObject*, unsigned long, void* self, void*) {
    static_cast<Context*>(self)->make();
  });
  c.is_current = vtkSmartPointer<vtkCallbackCommand>::New();
  c.is_current->SetClientData(&c);
  c.is_current->SetCallback([](vtkObject*, unsigned long, void* self, void* answer) {
    *static_cast<bool*>(answer) = static_cast<Context*>(self)->current();
  });

  c.window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  c.window->AddObserver(vtkCommand::WindowMakeCurrentEvent, c.make_current);
  c.window->AddObserver(vtkCommand::WindowIsCurrentEvent, c.is_current);
  c.window->SetSize(width, height);
  c.window->SetReadyForRendering(true);
  c.window->SetIsCurrent(true);
  c.window->SetOffScreenRendering(true);
  BRITTLE_CHECK(c.window->InitializeFromCurrentContext(),
                "render: VTK could not initialise OpenGL on the OSMesa context");
}

OffscreenWindow::~OffscreenWindow() {
  Context& c = *context_;
  c.make();
  c.window->Finalize();  // frees VTK's GL resources while its context is still alive
  c.window->RemoveAllObservers();
  c.window = nullptr;
  OSMesaDestroyContext(c.gl);
}

vtkRenderWindow* OffscreenWindow::window() const { return context_->window; }

}  // namespace brittle::render

#endif  // VTK_OPENGL_HAS_OSMESA
