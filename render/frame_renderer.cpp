// Frames of the plate (SPEC 9, Figs. 7-10): outer surface of the deformed tet grid seen face-on
// along -z, flat cell colours on a fixed range with marked over-range colours, colour bar (own or
// shared by a panel), mm scale bar, time/load label, scene name.
#include "frame_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkActor2D.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty2D.h>
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
#include "image_tools.hpp"
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

/// matplotlib's viridis (S. van der Walt and N. Smith, CC0): every 16th of its 256 entries and
/// the last. VTK 9.1 has no viridis; linear interpolation between these 17 stays within about
/// 1/255 of the full table.
constexpr double kViridis[17][3] = {
    {0.267004, 0.004874, 0.329415}, {0.282327, 0.094955, 0.417331},
    {0.278826, 0.175490, 0.483397}, {0.258965, 0.251537, 0.524736},
    {0.229739, 0.322361, 0.545706}, {0.199430, 0.387607, 0.554642},
    {0.172719, 0.448791, 0.557885}, {0.149039, 0.508051, 0.557250},
    {0.127568, 0.566949, 0.550556}, {0.120638, 0.625828, 0.533488},
    {0.157851, 0.683765, 0.501686}, {0.246070, 0.738910, 0.452024},
    {0.369214, 0.788888, 0.382914}, {0.515992, 0.831158, 0.294279},
    {0.678489, 0.863742, 0.189503}, {0.845561, 0.887322, 0.099702},
    {0.993248, 0.906157, 0.143936}};

/// 256 colours of the ramp, and the marked colours above and below the range.
/// jet: blue -> cyan -> green -> yellow -> red, the paper's stress-plot ramp (hue 240 -> 0).
vtkSmartPointer<vtkLookupTable> make_lookup_table(RenderParams::Colormap map) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(256);
  if (map == RenderParams::Colormap::jet) {
    lut->SetHueRange(0.667, 0.0);
    lut->SetSaturationRange(1.0, 1.0);
    lut->SetValueRange(1.0, 1.0);
    lut->Build();
  } else {
    vtkNew<vtkColorTransferFunction> ramp;
    for (int i = 0; i < 17; ++i)
      ramp->AddRGBPoint(std::min(16 * i, 255) / 255.0, kViridis[i][0], kViridis[i][1],
                        kViridis[i][2]);
    for (int k = 0; k < 256; ++k) {
      double rgb[3];
      ramp->GetColor(k / 255.0, rgb);
      lut->SetTableValue(k, rgb[0], rgb[1], rgb[2], 1.0);
    }
  }
  lut->SetAboveRangeColor(kAboveRangeColour[0], kAboveRangeColour[1], kAboveRangeColour[2], 1.0);
  lut->SetBelowRangeColor(kBelowRangeColour[0], kBelowRangeColour[1], kBelowRangeColour[2], 1.0);
  lut->UseAboveRangeColorOn();
  lut->UseBelowRangeColorOn();
  lut->BuildSpecialColors();
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

/// Black Arial text of `size` px, no shadow.
void plain_text(vtkTextProperty* p, int size) {
  p->SetColor(0, 0, 0);
  p->SetFontFamilyToArial();
  p->SetFontSize(size);
  p->ShadowOff();
  p->ItalicOff();
  p->BoldOff();
}

/// The colour bar of `field` on the range lo..hi, labels `font` px, with swatches of the colours
/// above and below the range annotated "> hi" and "< lo" (set_range).
void configure_bar(vtkScalarBarActor& bar, vtkLookupTable* lut, int font) {
  bar.SetLookupTable(lut);
  bar.SetMaximumNumberOfColors(256);  // every colour of the table: no visible bands
  bar.SetLabelFormat("%.3g");
  bar.UnconstrainedFontSizeOn();
  bar.GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  bar.SetTitle(" ");  // the name is a text actor of its own: VTK would overlap the labels
  for (vtkTextProperty* p :
       {bar.GetTitleTextProperty(), bar.GetLabelTextProperty(), bar.GetAnnotationTextProperty()})
    plain_text(p, font);
  bar.DrawAnnotationsOn();
  bar.DrawAboveRangeSwatchOn();
  bar.DrawBelowRangeSwatchOn();
  bar.DrawNanAnnotationOff();
}

void set_range(vtkScalarBarActor& bar, vtkLookupTable& lut, double lo, double hi) {
  lut.SetTableRange(lo, hi);
  bar.SetNumberOfLabels(nice_label_count(hi - lo));
  char text[32];
  std::snprintf(text, sizeof text, "> %.3g", hi);
  bar.SetAboveRangeAnnotation(text);
  std::snprintf(text, sizeof text, "< %.3g", lo);
  bar.SetBelowRangeAnnotation(text);
}

}  // namespace

/// Where things sit, as fractions of the frame's height from the bottom (single / cell). The
/// plate fills 94 % of the width or the band between the bottom strip (colour bar and scale bar,
/// or the scale bar alone) and the time label (top 12 %), whichever is tighter.
struct FrameLayout {
  double band_bottom, band_top;  ///< the plate's band
  double scale_y;                ///< the scale bar's centre line
};
constexpr FrameLayout kSingle{0.25, 0.88, 0.10}, kCell{0.12, 0.88, 0.06};

struct FrameRenderer::Pipeline {
  OffscreenWindow window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkUnstructuredGrid> shown;  ///< shallow copy of the input, points magnified
  vtkNew<vtkDataSetSurfaceFilter> surface;
  vtkNew<vtkPolyDataMapper> mapper;
  vtkNew<vtkActor> actor;
  vtkSmartPointer<vtkLookupTable> lut;
  vtkNew<vtkScalarBarActor> bar;
  vtkNew<vtkTextActor> label;
  vtkNew<vtkTextActor> name;  ///< the field's name, above the colour bar
  vtkNew<vtkTextActor> scene_name;
  // The mm scale bar: a bar with end ticks in pixel (viewport) coordinates, its length left of it.
  vtkNew<vtkPolyData> scale_shape;
  vtkNew<vtkPolyDataMapper2D> scale_mapper;
  vtkNew<vtkActor2D> scale_actor;
  vtkNew<vtkTextActor> scale_text;
  vtkNew<vtkWindowToImageFilter> grab;
  // Crack frames: cracked faces and tips drawn in a second layer, over the plate's surface
  // (their edges on the faces z = 0, T coincide with it), with the same camera.
  vtkNew<vtkRenderer> overlay;
  vtkNew<vtkPolyData> crack_lines, crack_tips;
  vtkNew<vtkPolyDataMapper> lines_mapper, tips_mapper;
  vtkNew<vtkActor> lines_actor, tips_actor;
  vtkNew<vtkTextActor> legend;

  Pipeline(int width, int height, RenderParams::Colormap map)
      : window(width, height), lut(make_lookup_table(map)) {
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
    renderer->AddViewProp(scene_name);
    renderer->AddViewProp(scale_actor);
    renderer->AddViewProp(scale_text);

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
    configure_bar(*bar, lut, static_cast<int>(std::lround(font / 26)));
    bar->SetOrientationToHorizontal();
    bar->GetPositionCoordinate()->SetValue(0.03, 0.0);
    bar->SetWidth(0.62);
    bar->SetHeight(0.155);
    bar->SetBarRatio(0.3);
    bar->SetTextPositionToPrecedeScalarBar();  // labels below the bar

    label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    label->GetPositionCoordinate()->SetValue(0.02, 0.975);
    vtkTextProperty* t = label->GetTextProperty();
    plain_text(t, static_cast<int>(std::lround(font / 18)));
    t->SetVerticalJustificationToTop();
    t->SetJustificationToLeft();

    name->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    name->GetPositionCoordinate()->SetValue(0.34, 0.175);
    vtkTextProperty* n = name->GetTextProperty();
    n->ShallowCopy(t);
    n->BoldOn();
    n->SetFontSize(static_cast<int>(std::lround(font / 22)));
    n->SetJustificationToCentered();
    n->SetVerticalJustificationToCentered();

    scene_name->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    scene_name->GetPositionCoordinate()->SetValue(0.98, 0.015);
    vtkTextProperty* sn = scene_name->GetTextProperty();
    sn->ShallowCopy(t);
    sn->SetFontSize(static_cast<int>(std::lround(font / 24)));
    sn->SetJustificationToRight();
    sn->SetVerticalJustificationToBottom();

    scale_mapper->SetInputData(scale_shape);
    scale_actor->SetMapper(scale_mapper);
    scale_actor->GetProperty()->SetColor(0, 0, 0);
    vtkTextProperty* st = scale_text->GetTextProperty();
    st->ShallowCopy(t);
    st->SetFontSize(static_cast<int>(std::lround(font / 24)));
    st->SetJustificationToRight();
    st->SetVerticalJustificationToCentered();

    legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    legend->GetPositionCoordinate()->SetValue(0.03, 0.1);  // left: the scale bar is right
    vtkTextProperty* g = legend->GetTextProperty();
    g->ShallowCopy(t);
    g->SetFontSize(static_cast<int>(std::lround(font / 22)));
    g->SetJustificationToLeft();
    g->SetVerticalJustificationToCentered();

    grab->SetInput(window.window());
    grab->ReadFrontBufferOff();
    grab->SetInputBufferTypeToRGB();
  }

  /// The scale bar `pixels` long ending at x = right, centred on y (viewport pixels): a bar
  /// `thick` px high with ticks 3 thick high at both ends, integer corners so that it covers
  /// exactly `pixels` columns.
  void set_scale_bar(int right, int y, int pixels, int thick, const std::string& text) {
    const int left = right - pixels, y0 = y - thick / 2, tick = thick;
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> quads;
    auto quad = [&](double x0, double y0q, double x1, double y1) {
      const vtkIdType i = points->InsertNextPoint(x0, y0q, 0);
      points->InsertNextPoint(x1, y0q, 0);
      points->InsertNextPoint(x1, y1, 0);
      points->InsertNextPoint(x0, y1, 0);
      const vtkIdType ids[4] = {i, i + 1, i + 2, i + 3};
      quads->InsertNextCell(4, ids);
    };
    quad(left, y0, right, y0 + thick);
    quad(left, y0 - tick, left + thick, y0 + thick + tick);
    quad(right - thick, y0 - tick, right, y0 + thick + tick);
    scale_shape->SetPoints(points);
    scale_shape->SetPolys(quads);
    scale_shape->Modified();
    scale_text->SetInput(text.c_str());
    scale_text->GetPositionCoordinate()->SetCoordinateSystemToViewport();
    scale_text->GetPositionCoordinate()->SetValue(left - 2 * thick - 2, y);
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

double scale_bar_length(double width) {
  const double decade = std::pow(10.0, std::floor(std::log10(width / 5)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * decade <= width / 5 * (1 + 1e-12)) return m * decade;
  return decade;
}

FrameRenderer::FrameRenderer(const RenderParams& params, std::string scene_name)
    : params_(params),
      scene_name_(std::move(scene_name)),
      pipeline_(std::make_unique<Pipeline>(params.width, params.height, params.colormap)) {}

FrameRenderer::~FrameRenderer() = default;

// The widest text of a bar, "sigma1 / sigma_c" in bold at height/22, is about 0.45 height.
int FrameRenderer::colour_bar_width() const {
  return std::max(110, static_cast<int>(std::lround(0.55 * params_.height)));
}

vtkSmartPointer<vtkImageData> FrameRenderer::colour_bar(Field field, int width, int height) const {
  BRITTLE_CHECK(field != Field::crack, "render: crack frames have no colour bar");
  OffscreenWindow window(width, height);
  window.window()->SetMultiSamples(0);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  window.window()->AddRenderer(renderer);
  auto lut = make_lookup_table(params_.colormap);
  vtkNew<vtkScalarBarActor> bar;
  const double font = params_.height;  // as in the frames beside it
  configure_bar(*bar, lut, static_cast<int>(std::lround(font / 26)));
  const bool sigma1 = field == Field::sigma1;
  set_range(*bar, *lut, sigma1 ? params_.sigma1_min : params_.damage_min,
            sigma1 ? params_.sigma1_max : params_.damage_max);
  bar->SetOrientationToVertical();
  // Annotations ("> 1.2") left of the bar, labels right of it.
  bar->GetPositionCoordinate()->SetValue(0.3, 0.04);
  bar->SetWidth(0.7);
  bar->SetHeight(std::min(0.86, 1.0 - 1.5 * font / 22 / height - 0.04));
  bar->SetBarRatio(0.12);
  bar->SetTextPositionToSucceedScalarBar();
  bar->SetMaximumWidthInPixels(width);
  renderer->AddViewProp(bar);
  vtkNew<vtkTextActor> name;
  name->SetInput(field_title(field));
  name->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  name->GetPositionCoordinate()->SetValue(0.5, 0.99);
  plain_text(name->GetTextProperty(), static_cast<int>(std::lround(font / 22)));
  name->GetTextProperty()->BoldOn();
  name->GetTextProperty()->SetJustificationToCentered();
  name->GetTextProperty()->SetVerticalJustificationToTop();
  renderer->AddViewProp(name);
  return snapshot(window);
}

vtkSmartPointer<vtkImageData> FrameRenderer::render(vtkUnstructuredGrid& grid, Field field,
                                                    Layout layout) {
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
  const bool single = layout == Layout::single;
  set_range(*p.bar, *p.lut, sigma1 ? r.sigma1_min : r.damage_min,
            sigma1 ? r.sigma1_max : r.damage_max);
  p.mapper->SelectColorArray(array);
  p.name->SetInput(field_title(field));
  p.mapper->SetScalarVisibility(!crack_frame);
  p.bar->SetVisibility(!crack_frame && single);
  p.name->SetVisibility(!crack_frame && single);
  // At most 40 characters (the end kept), so that a long name stays clear of the colour bar.
  const std::string shown_name =
      scene_name_.size() > 40 ? "..." + scene_name_.substr(scene_name_.size() - 37) : scene_name_;
  p.scene_name->SetInput(shown_name.c_str());
  p.scene_name->SetVisibility(single && !scene_name_.empty());
  p.legend->SetVisibility(crack_frame);
  p.lines_actor->SetVisibility(crack_frame);
  p.tips_actor->SetVisibility(crack_frame);
  if (crack_frame) {
    p.actor->GetProperty()->SetColor(0.82, 0.82, 0.82);
    draw_crack(p, grid);
  }

  // Face-on along -z, fixed by the reference (undeformed) bounds, so every frame of a run and
  // its re-rendering share one camera (FrameLayout: where the plate goes).
  const FrameLayout& place = single ? kSingle : kCell;
  double bounds[6];
  if (X) {
    for (int k = 0; k < 3; ++k) X->GetRange(bounds + 2 * k, k);
  } else {
    grid.GetBounds(bounds);
  }
  const double cx = 0.5 * (bounds[0] + bounds[1]), cy = 0.5 * (bounds[2] + bounds[3]);
  const double lx = bounds[1] - bounds[0], ly = bounds[3] - bounds[2];
  const double aspect = double(r.width) / r.height;
  const double band = place.band_top - place.band_bottom;
  const double band_centre = 0.5 * (place.band_top + place.band_bottom);
  const double half_height = std::max(0.5 * ly / band, 0.5 * lx / 0.94 / aspect) / r.zoom;
  const double view_y = cy - (band_centre - 0.5) * 2 * half_height;
  vtkCamera* camera = p.renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(cx, view_y, bounds[5]);
  camera->SetPosition(cx, view_y, bounds[5] + 10 * std::max(lx, ly));
  camera->SetViewUp(0, 1, 0);
  camera->SetParallelScale(half_height);
  p.renderer->ResetCameraClippingRange();

  // Scale bar: the parallel projection shows 2 half_height metres over the frame's height.
  const double metres_per_pixel = 2 * half_height / r.height;
  scale_bar_.length = scale_bar_length(lx / r.zoom);
  scale_bar_.pixels = static_cast<int>(std::lround(scale_bar_.length / metres_per_pixel));
  char mm[32];
  std::snprintf(mm, sizeof mm, "%g mm", scale_bar_.length * 1e3);
  p.set_scale_bar(static_cast<int>(std::lround(0.96 * r.width)),
                  static_cast<int>(std::lround(place.scale_y * r.height)), scale_bar_.pixels,
                  std::max(2, static_cast<int>(std::lround(r.height / 150.0))), mm);

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
