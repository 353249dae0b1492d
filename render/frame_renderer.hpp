// PNG frames of the plate: the (deformed) grid face-on, coloured by sigma1/sigma_c or Omega with
// a fixed colour range, a colour bar and a time/load label (SPEC 9, paper Figs. 7-10).
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

/// Renders frames of grids (live or read from VTU) with the style of the scene's [render] keys.
/// Keeps one off-screen window for all frames; not thread-safe.
class FrameRenderer {
 public:
  explicit FrameRenderer(const RenderParams& params);
  ~FrameRenderer();

  /// The frame as an RGB image of render.width x render.height. The camera is set from the
  /// reference positions' bounds, the label from the grid's field data (TimeValue, and
  /// sigma_over_sigmac when present), so a live grid and its VTU copy give the same picture.
  vtkSmartPointer<vtkImageData> render(vtkUnstructuredGrid& grid, Field field);

  const RenderParams& params() const { return params_; }

  struct Pipeline;  ///< the VTK objects, kept between frames (frame_renderer.cpp)

 private:
  RenderParams params_;
  std::unique_ptr<Pipeline> pipeline_;
};

/// The PNG file name of a frame: "<field>_<time in us, 3 decimals>us.png", e.g.
/// "sigma1_015.000us.png", so that a directory listing sorts by field, then time.
std::string frame_file_name(Field field, double time);

}  // namespace brittle::render
