// PNG I/O, text strips, paper-style panels (vtkImageAppend) and baseline comparison
// (vtkImageDifference).
#include "image_tools.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <vtkImageAppend.h>
#include <vtkImageData.h>
#include <vtkImageDifference.h>
#include <vtkImageExtractComponents.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include "error.hpp"
#include "offscreen_window.hpp"

namespace brittle::render {

namespace fs = std::filesystem;

void write_png(vtkImageData& image, const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty()) fs::create_directories(parent);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(&image);
  writer->SetFileName(path.c_str());
  writer->Write();
  BRITTLE_CHECK(writer->GetErrorCode() == 0 && fs::is_regular_file(path), "render: cannot write '",
                path, "'");
}

vtkSmartPointer<vtkImageData> read_png(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  BRITTLE_CHECK(fs::is_regular_file(path) && reader->CanReadFile(path.c_str()), "render: '", path,
                "' is not a readable PNG file");
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* read = reader->GetOutput();
  auto image = vtkSmartPointer<vtkImageData>::New();
  if (read->GetNumberOfScalarComponents() == 3) {
    image->DeepCopy(read);
  } else {
    BRITTLE_CHECK(read->GetNumberOfScalarComponents() == 4, "render: '", path,
                  "' is neither RGB nor RGBA");
    vtkNew<vtkImageExtractComponents> rgb;
    rgb->SetInputData(read);
    rgb->SetComponents(0, 1, 2);
    rgb->Update();
    image->DeepCopy(rgb->GetOutput());
  }
  return image;
}

vtkSmartPointer<vtkImageData> snapshot(OffscreenWindow& window) {
  window.window()->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window.window());
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(grab->GetOutput());
  return image;
}

vtkSmartPointer<vtkImageData> text_image(const std::string& text, int width, int height,
                                         int font_size, bool bold) {
  OffscreenWindow window(width, height);
  window.window()->SetMultiSamples(0);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  window.window()->AddRenderer(renderer);
  vtkNew<vtkTextActor> actor;
  actor->SetInput(text.c_str());
  actor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  actor->GetPositionCoordinate()->SetValue(0.5, 0.5);
  vtkTextProperty* p = actor->GetTextProperty();
  p->SetColor(0, 0, 0);
  p->SetFontFamilyToArial();
  p->SetFontSize(font_size);
  p->SetBold(bold);
  p->ShadowOff();
  p->SetJustificationToCentered();
  p->SetVerticalJustificationToCentered();
  renderer->AddViewProp(actor);
  return snapshot(window);
}

namespace {

/// Images side by side (axis 0, left to right) or stacked (axis 1, given top to bottom).
vtkSmartPointer<vtkImageData> append(const std::vector<vtkImageData*>& images, int axis) {
  vtkNew<vtkImageAppend> append;
  append->SetAppendAxis(axis);
  append->PreserveExtentsOff();
  // VTK's y axis points up: the last input ends up at the top.
  if (axis == 1)
    for (auto it = images.rbegin(); it != images.rend(); ++it) append->AddInputData(*it);
  else
    for (vtkImageData* image : images) append->AddInputData(image);
  append->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->DeepCopy(append->GetOutput());
  return out;
}

}  // namespace

vtkSmartPointer<vtkImageData> panel(const std::vector<std::vector<vtkImageData*>>& cells,
                                    const std::vector<std::string>& row_titles,
                                    const std::vector<std::string>& column_titles,
                                    const std::string& title,
                                    const std::vector<PanelBar>& bars) {
  BRITTLE_CHECK(!cells.empty() && !cells[0].empty() && cells.size() == row_titles.size() &&
                    cells[0].size() == column_titles.size(),
                "render: panel needs rows x columns images and a title for each row and column");
  int dims[3];
  cells[0][0]->GetDimensions(dims);
  const int w = dims[0], h = dims[1];
  for (const auto& row : cells) {
    BRITTLE_CHECK(row.size() == column_titles.size(), "render: panel rows of unequal length");
    for (vtkImageData* cell : row) {
      int d[3];
      cell->GetDimensions(d);
      BRITTLE_CHECK(d[0] == w && d[1] == h, "render: panel images of unequal size");
    }
  }
  const int font = std::max(12, h / 14);
  // Row titles as wide as the longest needs (about 0.62 em per character of the bold font).
  std::size_t longest = 0;
  for (const std::string& r : row_titles) longest = std::max(longest, r.size());
  const int label_w = std::max({60, w / 5, static_cast<int>(longest * font * 0.62) + font});
  const int header_h = font * 2, title_h = font * 5 / 2;

  std::vector<vtkSmartPointer<vtkImageData>> keep;  // owns the strips until appended
  keep.push_back(text_image(" ", label_w, header_h, font));
  std::vector<vtkImageData*> header = {keep.back()};
  for (const std::string& c : column_titles) {
    keep.push_back(text_image(c, w, header_h, font, true));
    header.push_back(keep.back());
  }
  int bar_w = 0, bar_rows = 0;
  for (const PanelBar& b : bars) {
    BRITTLE_CHECK(b.image, "render: panel colour bar without an image");
    int d[3];
    b.image->GetDimensions(d);
    BRITTLE_CHECK(b.rows > 0 && d[1] == b.rows * h && (bar_w == 0 || d[0] == bar_w),
                  "render: panel colour bars must be as high as their rows and of one width");
    bar_w = d[0];
    bar_rows += b.rows;
  }
  BRITTLE_CHECK(bars.empty() || bar_rows == static_cast<int>(cells.size()),
                "render: panel colour bars must cover every row once");
  std::vector<vtkSmartPointer<vtkImageData>> grid_rows;
  grid_rows.push_back(append(header, 0));
  for (std::size_t i = 0; i < cells.size(); ++i) {
    keep.push_back(text_image(row_titles[i], label_w, h, font, true));
    std::vector<vtkImageData*> row = {keep.back()};
    row.insert(row.end(), cells[i].begin(), cells[i].end());
    grid_rows.push_back(append(row, 0));
  }
  std::vector<vtkImageData*> stack;
  for (auto& r : grid_rows) stack.push_back(r);
  vtkSmartPointer<vtkImageData> body = append(stack, 1);
  if (!bars.empty()) {
    keep.push_back(text_image(" ", bar_w, header_h, font));
    std::vector<vtkImageData*> column = {keep.back()};
    for (const PanelBar& b : bars) column.push_back(b.image);
    keep.push_back(append(column, 1));
    body = append({body.Get(), keep.back().Get()}, 0);
  }
  const int total_w = label_w + w * static_cast<int>(column_titles.size()) + bar_w;
  keep.push_back(text_image(title, total_w, title_h, font * 6 / 5, true));
  return append({keep.back().Get(), body.Get()}, 1);
}

Comparison compare_images(vtkImageData& image, vtkImageData& baseline) {
  Comparison c;
  int a[3], b[3];
  image.GetDimensions(a);
  baseline.GetDimensions(b);
  c.same_size = a[0] == b[0] && a[1] == b[1] && a[2] == b[2] &&
                image.GetNumberOfScalarComponents() == baseline.GetNumberOfScalarComponents();
  if (!c.same_size) return c;
  vtkNew<vtkImageDifference> diff;
  diff->SetInputData(&image);
  diff->SetImageData(&baseline);
  diff->SetThreshold(kPixelThreshold);
  diff->Update();
  c.difference = vtkSmartPointer<vtkImageData>::New();
  c.difference->DeepCopy(diff->GetOutput());
  // Our own normalisation of the thresholded difference image (the filter's GetThresholdedError
  // is a sum whose scaling differs between VTK versions).
  const auto* px = static_cast<const unsigned char*>(c.difference->GetScalarPointer());
  const vtkIdType n = static_cast<vtkIdType>(a[0]) * a[1] * a[2] * 3;
  double sum = 0;
  for (vtkIdType i = 0; i < n; ++i) sum += px[i];
  c.error = n > 0 ? sum / (255.0 * n) : 0.0;
  return c;
}

}  // namespace brittle::render
