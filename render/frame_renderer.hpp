// PNG frames of the plate: the (deformed) grid face-on, coloured by sigma1/sigma_c or Omega with
// a fixed colour range (over-range colours marked), a colour bar, a mm scale bar, a time/load
// label and the scene's name (SPEC 9, paper Figs. 7-10; docs/rendering.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "scene.hpp"

class vtkImageData;
class vtkUnstructuredGrid;

namespace brittle::render {

/// Field data the simulation stores on the live grid for the labels: the load sigma/sigma_c.
inline constexpr const char* load_array = "sigma_over_sigmac";

/// What a frame shows: sigma1/sigma_c or Omega as cell colours, or the crack itself (cracked
/// faces as dark lines on a grey plate, crack tips as red dots; docs/rendering.md).
enum class Field { sigma1, damage, crack };

/// "sigma1", "damage" or "crack" (the words of render.fields and --field, any case); throws
/// brittle::Error otherwise.
Field parse_field(const std::string& word);
/// The word for file names and options: "sigma1", "damage", "crack".
const char* field_word(Field f);

/// A single PNG frame has its own colour bar and names the scene; a panel cell has neither (the
/// panel has one shared colour bar, FrameRenderer::colour_bar, and a title). Both have the time
/// label and the mm scale bar.
enum class Layout { single, cell };

/// Colours of values outside the colour range (both colormaps; docs/rendering.md): above the
/// top magenta, which neither jet nor viridis contains; below the bottom mid grey.
inline constexpr double kAboveRangeColour[3] = {1.0, 0.0, 1.0};
inline constexpr double kBelowRangeColour[3] = {0.5, 0.5, 0.5};

/// The mm scale bar of a frame: its length and how many pixels it spans.
struct ScaleBar {
  double length = 0;  ///< [m], 1, 2 or 5 times a power of ten: at most 1/5 of the plate's width
  int pixels = 0;     ///< length / (metres per pixel of the camera), rounded
};

/// The scale bar's length for a plate `width` wide [m]: the largest 1, 2 or 5 x 10^k m that is
/// at most width / 5.
double scale_bar_length(double width);

/// Renders frames of grids (live or read from VTU) with the style of the scene's [render] keys.
/// Keeps one off-screen window for all frames; not thread-safe.
class FrameRenderer {
 public:
  /// `scene_name` is shown in single frames (bottom right); empty = none.
  explicit FrameRenderer(const RenderParams& params, std::string scene_name = "");
  ~FrameRenderer();

  /// The frame as an RGB image of render.width x render.height. The camera is set from the
  /// reference positions' bounds, the label from the grid's field data (TimeValue, and
  /// sigma_over_sigmac when present), so a live grid and its VTU copy give the same picture.
  vtkSmartPointer<vtkImageData> render(vtkUnstructuredGrid& grid, Field field,
                                       Layout layout = Layout::single);

  /// The colour bar of a sigma1 or Omega frame alone, vertical, `width` x `height` px, with the
  /// field's name and the over-range swatches: the one shared bar of a panel.
  vtkSmartPointer<vtkImageData> colour_bar(Field field, int width, int height) const;

  /// The width of colour_bar images that suits frames of this renderer's height [px].
  int colour_bar_width() const;

  /// The scale bar of the last frame rendered.
  const ScaleBar& scale_bar() const { return scale_bar_; }

  const RenderParams& params() const { return params_; }

  struct Pipeline;  ///< the VTK objects, kept between frames (frame_renderer.cpp)

 private:
  RenderParams params_;
  std::string scene_name_;
  std::unique_ptr<Pipeline> pipeline_;
  ScaleBar scale_bar_;
};

/// The PNG file name of a frame: "<field>_<time in us, 3 decimals>us.png", e.g.
/// "sigma1_015.000us.png", so that a directory listing sorts by field, then time.
std::string frame_file_name(Field field, double time);

}  // namespace brittle::render
