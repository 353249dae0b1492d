// Images around the frames: PNG in and out, text strips, panels laid out as the paper's figures,
// and the regression comparison of a frame with its baseline.
#pragma once

#include <string>
#include <vector>

#include <vtkSmartPointer.h>

class vtkImageData;

namespace brittle::render {

/// Writes an RGB(A) image as PNG (parent directories are created); throws brittle::Error.
void write_png(vtkImageData& image, const std::string& path);

class OffscreenWindow;
/// Renders the window and returns its RGB pixels (a copy the window no longer touches).
vtkSmartPointer<vtkImageData> snapshot(OffscreenWindow& window);
/// Reads a PNG as RGB; throws brittle::Error naming the file when it cannot be read.
vtkSmartPointer<vtkImageData> read_png(const std::string& path);

/// A width x height white strip with `text` (UTF-8) centred in black.
vtkSmartPointer<vtkImageData> text_image(const std::string& text, int width, int height,
                                         int font_size, bool bold = false);

/// A colour bar shared by `rows` consecutive rows of a panel, right of them: `image` is as high as
/// those rows together (FrameRenderer::colour_bar).
struct PanelBar {
  vtkImageData* image = nullptr;
  int rows = 1;
};

/// The paper's panel: cells[row][column] (all of one size), column titles above, row titles to
/// the left, a title across the top, and the shared colour bars (if any) in a column on the
/// right, top to bottom, covering every row once. Composed with vtkImageAppend.
vtkSmartPointer<vtkImageData> panel(const std::vector<std::vector<vtkImageData*>>& cells,
                                    const std::vector<std::string>& row_titles,
                                    const std::vector<std::string>& column_titles,
                                    const std::string& title,
                                    const std::vector<PanelBar>& bars = {});

/// The result of comparing an image with its baseline through vtkImageDifference.
struct Comparison {
  bool same_size = false;
  /// Mean over pixels of the per-pixel error above vtkImageDifference's threshold, in [0, 1]:
  /// 0 = every pixel within the threshold of the baseline (after the filter's 1-pixel shift and
  /// 3x3 averaging); 1 = every pixel off by full scale in every channel.
  double error = 1;
  vtkSmartPointer<vtkImageData> difference;  ///< the filter's thresholded difference image
};

/// Per-pixel colour threshold (0-255 per channel) given to vtkImageDifference: absorbs
/// anti-aliasing and font hinting noise, not a changed colour range or camera.
inline constexpr int kPixelThreshold = 16;

Comparison compare_images(vtkImageData& image, vtkImageData& baseline);

}  // namespace brittle::render
