// An off-screen VTK render window that needs no display (DISPLAY unset, no Xvfb): the one
// thing the rest of render/ knows about OpenGL. How it works: offscreen_window.cpp.
#pragma once

#include <memory>

class vtkRenderWindow;

namespace brittle::render {

/// A VTK render window of width x height pixels drawn by Mesa's software rasteriser (OSMesa).
/// Add renderers to window(), Render(), read the pixels back with vtkWindowToImageFilter
/// (ReadFrontBufferOff). The size is fixed for the window's lifetime; several windows may
/// coexist (each owns its context and is made current by VTK as needed).
class OffscreenWindow {
 public:
  OffscreenWindow(int width, int height);
  ~OffscreenWindow();
  OffscreenWindow(const OffscreenWindow&) = delete;
  OffscreenWindow& operator=(const OffscreenWindow&) = delete;

  vtkRenderWindow* window() const;
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  struct Context;
  int width_, height_;
  std::unique_ptr<Context> context_;
};

}  // namespace brittle::render
