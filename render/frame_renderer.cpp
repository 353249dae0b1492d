// Frames of the plate (SPEC 9, Figs. 7-10): outer surface of the deformed tet grid seen face-on
// along -z, flat cell colours on a fixed range, colour bar, time/load label.
#include "frame_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnstructuredGrid.h>
#include <vtkWindowToImageFilter.h>

#include "crack_surface.hpp"
#include "error.hpp"
#include "grid.hpp"
#include "offscreen_window.hpp"

namespace brittle::render {

Field parse_field(const std::string& word) {
  std::string lower = word;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (Field f : {Field::sigma1, Field::damage, Field::crack})
    if (lower == field_word(f)) return f;
  throw Error(error_message("render: unknown field '", word,
                            "' (expected sigma1, damage or crack)"));
}

const char* field_word(Field f) {
  switch (f) {
    case Field::sigma1: return "sigma1";
    case Field::damage: return "damage";
    case Field::crack: return "crack";
  }
  return "?";
}

std::string frame_file_name(Field field, double time) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%07.3fus.png", field_word(field), time * 1e6);
  return buf;
}

namespace {

/// The cell array a colour frame shows (crack frames show none).
const char* array_name(Field f) {
  return f == Field::sigma1 ? field::sigma1_over_sigmac : field::damage;
}

/// Colour-bar titles. ASCII (and Latin-1 µ) only: VTK's embedded font has no Greek, and a
/// system font would make the pictures depend on what is installed.
const char* field_title(Field f) { return f == Field::sigma1 ? "sigma1 / sigma_c" : "Omega (damage)"; }

/// The first value of a one-tuple field-data array, or NaN.
double field_value(vtkUnstructuredGrid& grid, const char* name) {
  vtkDataArray* a = grid.GetFieldData()->GetArray(name);
  return a && a->GetNumberOfTuples() > 0 ? a->GetComponent(0, 0) : std::nan("");
}

/// Blue -> cyan -> green -> yellow -> red, the usual stress-plot ramp.
vtkSmartPointer<vtkLookupTable> make_lookup_table() {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(256);
  lut->SetHueRange(0.667, 0.0);
  lut->SetSaturationRange(1.0, 1.0);
  lut->SetValueRange(1.0, 1.0);
  lut->Build();
  return lut;
}

/// The most colour-bar labels (2 to 7) whose step is 1, 1.5, 2, 2.5 or 5 times a power of ten.
int nice_label_count(double range) {
  for (int n = 7; n > 2; --n) {
    const double step = range / (n - 1);
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step)));
    for (double nice : {1.0, 1.5, 2.0, 2.5, 5.0, 10.0})
      if (std::abs(mantissa - nice) < 1e-6 * nice) return n;
  }
  return 2;
}

}  // namespace

struct FrameRenderer::Pipeline {
  OffscreenWindow window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkUnstructuredGrid> shown;  ///< shallow copy of the input, points magnified
  vtkNew<vtkDataSetSurfaceFilter> surface;
  vtkNew<vtkPolyDataMapper> mapper;
  vtkNew<vtkActor> actor;
  vtkSmartPointer<vtkLookupTable> lut = make_lookup_table();
  vtkNew<vtkScalarBarActor> bar;
  vtkNew<vtkTextActor> label;
  vtkNew<vtkTextActor> name;  ///< the field's name, left of the colour bar
  vtkNew<vtkWindowToImageFilter> grab;
  // Crack frames: cracked faces and tips drawn in a second layer, over the plate's surface
  // (their edges on the faces z = 0, T coincide with it), with the same camera.
  vtkNew<vtkRenderer> overlay;
  vtkNew<vtkPolyData> crack_lines, crack_tips;
  vtkNew<vtkPolyDataMapper> lines_mapper, tips_mapper;
  vtkNew<vtkActor> lines_actor, tips_actor;
  vtkNew<vtkTextActor> legend;

  Pipeline(int width, int height) : window(width, height) {
    window.window()->SetMultiSamples(0);  // exact, reproducible pixels
    window.window()->SetNumberOfLayers(2);
    window.window()->AddRenderer(renderer);
    window.window()->AddRenderer(overlay);
    overlay->SetLayer(1);
    overlay->InteractiveOff();
    overlay->SetActiveCamera(renderer->GetActiveCamera());
    overlay->AddActor(lines_actor);
    overlay->AddActor(tips_actor);
    lines_mapper->SetInputData(crack_lines);
    tips_mapper->SetInputData(crack_tips);
    lines_mapper->ScalarVisibilityOff();
    tips_mapper->ScalarVisibilityOff();
    lines_actor->SetMapper(lines_mapper);
    tips_actor->SetMapper(tips_mapper);
    for (vtkActor* a : {lines_actor.Get(), tips_actor.Get()}) {
      a->GetProperty()->SetAmbient(1.0);
      a->GetProperty()->SetDiffuse(0.0);
      a->GetProperty()->SetSpecular(0.0);
      a->GetProperty()->LightingOff();
    }
    lines_actor->GetProperty()->SetColor(0.05, 0.05, 0.05);
    lines_actor->GetProperty()->SetLineWidth(std::max(2.0, std::round(height / 300.0)));
    tips_actor->GetProperty()->SetColor(0.85, 0.05, 0.05);
    tips_actor->GetProperty()->SetPointSize(std::max(7.0, std::round(height / 45.0)));
    tips_actor->GetProperty()->RenderPointsAsSpheresOn();
    renderer->AddViewProp(legend);
    renderer->SetBackground(1, 1, 1);
    renderer->AddActor(actor);
    renderer->AddViewProp(bar);
    renderer->AddViewProp(label);
    renderer->AddViewProp(name);

    surface->SetInputData(shown);
    mapper->SetInputConnection(surface->GetOutputPort());
    mapper->SetScalarModeToUseCellFieldData();
    mapper->SetLookupTable(lut);
    mapper->UseLookupTableScalarRangeOn();
    mapper->ScalarVisibilityOn();
    actor->SetMapper(mapper);
    // Flat colours: what is seen is the value on the colour bar, not a lighting effect.
    actor->GetProperty()->SetAmbient(1.0);
    actor->GetProperty()->SetDiffuse(0.0);
    actor->GetProperty()->SetSpecular(0.0);

    const double font = height;  // text scales with the frame
    bar->SetLookupTable(lut);
    bar->SetOrientationToHorizontal();
    bar->SetLabelFormat("%.3g");
    bar->UnconstrainedFontSizeOn();
    bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    bar->GetPositionCoordinate()->SetValue(0.12, 0.0);
    bar->SetWidth(0.76);
    bar->SetHeight(0.155);
    bar->SetBarRatio(0.3);
    bar->SetTextPositionToPrecedeScalarBar();  // labels below the bar
    for (vtkTextProperty* p : {bar->GetTitleTextProperty(), bar->GetLabelTextProperty()}) {
      p->SetColor(0, 0, 0);
      p->SetFontFamilyToArial();
      p->ShadowOff();
      p->ItalicOff();
    }
    bar->SetTitle(" ");  // the name is a text actor of its own: VTK would overlap the labels
    bar->GetLabelTextProperty()->SetFontSize(static_cast<int>(std::lround(font / 26)));
    bar->GetLabelTextProperty()->BoldOff();

    label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    label->GetPositionCoordinate()->SetValue(0.02, 0.975);
    vtkTextProperty* t = label->GetTextProperty();
    t->SetColor(0, 0, 0);
    t->SetFontFamilyToArial();
    t->SetFontSize(static_cast<int>(std::lround(font / 18)));
    t->SetVerticalJustificationToTop();
    t->SetJustificationToLeft();
    t->ShadowOff();

    name->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    name->GetPositionCoordinate()->SetValue(0.5, 0.175);
    vtkTextProperty* n = name->GetTextProperty();
    n->ShallowCopy(t);
    n->BoldOn();
    n->SetFontSize(static_cast<int>(std::lround(font / 22)));
    n->SetJustificationToCentered();
    n->SetVerticalJustificationToCentered();

    legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    legend->GetPositionCoordinate()->SetValue(0.5, 0.1);
    vtkTextProperty* g = legend->GetTextProperty();
    g->ShallowCopy(t);
    g->SetFontSize(static_cast<int>(std::lround(font / 22)));
    g->SetJustificationToCentered();
    g->SetVerticalJustificationToCentered();

    grab->SetInput(window.window());
    grab->ReadFrontBufferOff();
    grab->SetInputBufferTypeToRGB();
  }
};

/// Crack frames: every edge of both sides of every cracked face as a line, and a dot at each
/// crack tip of the solver's fronts, at the shown (magnified) positions; the legend counts
/// them (crack_surface.hpp).
static void draw_crack(FrameRenderer::Pipeline& p, vtkUnstructuredGrid& grid) {
  const CrackSurface crack = find_crack_surface(grid);
  vtkPoints* shown = p.shown->GetPoints();
  vtkNew<vtkCellArray> lines;
  for (const auto& face : crack.faces)
    for (int i = 0; i < 3; ++i) {
      const vtkIdType edge[2] = {face[i], face[(i + 1) % 3]};
      lines->InsertNextCell(2, edge);
    }
  p.crack_lines->SetPoints(shown);
  p.crack_lines->SetLines(lines);
  vtkNew<vtkPoints> tips;
  vtkNew<vtkCellArray> vertices;
  const auto tip_points = shown_tips(grid, *shown);
  for (const auto& t : tip_points) {
    const vtkIdType id = tips->InsertNextPoint(t.data());
    vertices->InsertNextCell(1, &id);
  }
  p.crack_tips->SetPoints(tips);
  p.crack_tips->SetVerts(vertices);
  p.crack_lines->Modified();
  p.crack_tips->Modified();
  char text[96];
  std::snprintf(text, sizeof text, "crack faces: %ld    tips: %zu", crack.face_count,
                tip_points.size());
  p.legend->SetInput(text);
}

FrameRenderer::FrameRenderer(const RenderParams& params)
    : params_(params), pipeline_(std::make_unique<Pipeline>(params.width, params.height)) {}

FrameRenderer::~FrameRenderer() = default;

vtkSmartPointer<vtkImageData> FrameRenderer::render(vtkUnstructuredGrid& grid, Field field) {
  Pipeline& p = *pipeline_;
  const RenderParams& r = params_;
  const bool crack_frame = field == Field::crack;
  const char* array = array_name(field);
  BRITTLE_CHECK(crack_frame || grid.GetCellData()->GetArray(array),
                "render: the grid has no cell data '", array, "'");

  // Magnified deformed configuration x_m = X + m (x - X); m = 1 shows the grid as it is.
  p.shown->ShallowCopy(&grid);
  vtkDataArray* X = grid.GetPointData()->GetArray(field::reference_position);
  if (r.magnification != 1.0) {
    BRITTLE_CHECK(X, "render: magnification needs the point data '", field::reference_position,
                  "'");
    auto points = vtkSmartPointer<vtkPoints>::New();
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(grid.GetNumberOfPoints());
    for (vtkIdType i = 0; i < grid.GetNumberOfPoints(); ++i) {
      double x[3], X0[3];
      grid.GetPoint(i, x);
      X->GetTuple(i, X0);
      for (int k = 0; k < 3; ++k) x[k] = X0[k] + r.magnification * (x[k] - X0[k]);
      points->SetPoint(i, x);
    }
    p.shown->SetPoints(points);
  }
  p.surface->Modified();

  const bool sigma1 = field == Field::sigma1;
  const double lo = sigma1 ? r.sigma1_min : r.damage_min, hi = sigma1 ? r.sigma1_max : r.damage_max;
  p.lut->SetTableRange(lo, hi);
  p.bar->SetNumberOfLabels(nice_label_count(hi - lo));
  p.mapper->SelectColorArray(array);
  p.name->SetInput(field_title(field));
  p.mapper->SetScalarVisibility(!crack_frame);
  p.bar->SetVisibility(!crack_frame);
  p.name->SetVisibility(!crack_frame);
  p.legend->SetVisibility(crack_frame);
  p.lines_actor->SetVisibility(crack_frame);
  p.tips_actor->SetVisibility(crack_frame);
  if (crack_frame) {
    p.actor->GetProperty()->SetColor(0.82, 0.82, 0.82);
    draw_crack(p, grid);
  }

  // Face-on along -z, fixed by the reference (undeformed) bounds, so every frame of a run and
  // its re-rendering share one camera. The plate fills 94 % of the width or the band between
  // the colour bar (bottom 25 %) and the label (top 12 %), whichever is tighter.
  double bounds[6];
  if (X) {
    for (int k = 0; k < 3; ++k) X->GetRange(bounds + 2 * k, k);
  } else {
    grid.GetBounds(bounds);
  }
  const double cx = 0.5 * (bounds[0] + bounds[1]), cy = 0.5 * (bounds[2] + bounds[3]);
  const double lx = bounds[1] - bounds[0], ly = bounds[3] - bounds[2];
  const double aspect = double(r.width) / r.height;
  constexpr double band = 0.63, band_centre = 0.565;
  const double half_height = std::max(0.5 * ly / band, 0.5 * lx / 0.94 / aspect) / r.zoom;
  const double view_y = cy - (band_centre - 0.5) * 2 * half_height;
  vtkCamera* camera = p.renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(cx, view_y, bounds[5]);
  camera->SetPosition(cx, view_y, bounds[5] + 10 * std::max(lx, ly));
  camera->SetViewUp(0, 1, 0);
  camera->SetParallelScale(half_height);
  p.renderer->ResetCameraClippingRange();

  const double t = field_value(grid, field::time);
  const double load = field_value(grid, load_array);
  char text[128];
  if (std::isnan(load))
    std::snprintf(text, sizeof text, "t = %.1f µs", t * 1e6);
  else
    std::snprintf(text, sizeof text, "t = %.1f µs    load %.0f %% of sigma_c", t * 1e6, 100 * load);
  p.label->SetInput(text);

  p.window.window()->Render();
  p.grab->Modified();
  p.grab->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(p.grab->GetOutput());
  return image;
}

}  // namespace brittle::render
