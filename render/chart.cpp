// x-y charts through vtkContextView + vtkChartXY in the OSMesa-backed window.
#include "chart.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <vtkAxis.h>
#include <vtkBrush.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

#include "error.hpp"
#include "image_tools.hpp"
#include "offscreen_window.hpp"

namespace brittle::render {

void write_chart_png(const std::string& path, const ChartAxes& axes,
                     const std::vector<ChartSeries>& series) {
  OffscreenWindow window(axes.width, axes.height);
  auto view = vtkSmartPointer<vtkContextView>::New();
  view->SetRenderWindow(window.window());
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  auto chart = vtkSmartPointer<vtkChartXY>::New();
  view->GetScene()->AddItem(chart);
  chart->SetTitle(axes.title);
  chart->GetTitleProperties()->SetFontSize(18);
  chart->SetShowLegend(true);
  using Corner = ChartAxes::Corner;
  const bool right = axes.legend == Corner::bottom_right || axes.legend == Corner::top_right;
  const bool top = axes.legend == Corner::top_right || axes.legend == Corner::top_left;
  chart->GetLegend()->SetHorizontalAlignment(right ? vtkChartLegend::RIGHT : vtkChartLegend::LEFT);
  chart->GetLegend()->SetVerticalAlignment(top ? vtkChartLegend::TOP : vtkChartLegend::BOTTOM);
  chart->GetLegend()->GetLabelProperties()->SetFontSize(14);
  struct AxisSpec {
    int which;
    const std::string& title;
    double lo, hi;
  };
  for (const AxisSpec& a : {AxisSpec{vtkAxis::BOTTOM, axes.x_title, axes.x_min, axes.x_max},
                            AxisSpec{vtkAxis::LEFT, axes.y_title, axes.y_min, axes.y_max}}) {
    vtkAxis* axis = chart->GetAxis(a.which);
    axis->SetTitle(a.title);
    axis->GetTitleProperties()->SetFontSize(16);
    axis->GetLabelProperties()->SetFontSize(14);
    axis->SetBehavior(vtkAxis::FIXED);
    axis->SetRange(a.lo, a.hi);
  }
  std::vector<vtkSmartPointer<vtkTable>> tables;  // alive until the render
  for (const ChartSeries& s : series) {
    BRITTLE_CHECK(s.x.size() == s.y.size(), "chart '", path, "': series '", s.name,
                  "' has ", s.x.size(), " x and ", s.y.size(), " y values");
    if (s.x.empty()) continue;
    auto table = vtkSmartPointer<vtkTable>::New();
    auto x = vtkSmartPointer<vtkDoubleArray>::New();
    auto y = vtkSmartPointer<vtkDoubleArray>::New();
    x->SetName("x");
    y->SetName(s.name.c_str());
    for (std::size_t i = 0; i < s.x.size(); ++i) x->InsertNextValue(s.x[i]), y->InsertNextValue(s.y[i]);
    table->AddColumn(x);
    table->AddColumn(y);
    tables.push_back(table);
    vtkPlot* plot = chart->AddPlot(s.style == ChartSeries::Style::points ? vtkChart::POINTS
                                                                          : vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    plot->SetColor(s.color[0], s.color[1], s.color[2], s.alpha);
    plot->SetLabel(s.name);
    if (!s.legend) plot->SetLegendVisibility(false);
    if (s.style == ChartSeries::Style::points) {
      static const int markers[] = {vtkPlotPoints::CIRCLE, vtkPlotPoints::SQUARE,
                                    vtkPlotPoints::DIAMOND, vtkPlotPoints::CROSS,
                                    vtkPlotPoints::PLUS};
      auto* points = vtkPlotPoints::SafeDownCast(plot);
      points->SetMarkerStyle(markers[s.marker % 5]);
      points->SetMarkerSize(static_cast<float>(s.marker_size));
    } else {
      plot->SetWidth(2.0);
      if (s.style == ChartSeries::Style::dashed) plot->GetPen()->SetLineType(vtkPen::DASH_LINE);
    }
  }
  write_png(*snapshot(window), path);
}

namespace {

/// The range of the finite values, with a 5 % margin (a flat or empty range gets +-1).
std::pair<double, double> padded_range(const std::vector<double>& v) {
  double lo = INFINITY, hi = -INFINITY;
  for (double x : v)
    if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  if (!(lo <= hi)) return {0, 1};
  const double pad = hi > lo ? 0.05 * (hi - lo) : 1.0;
  return {lo - pad, hi + pad};
}

}  // namespace

void write_chart_png(const std::string& path, const std::string& title, const std::string& x_title,
                     const std::string& y_title, const std::vector<ChartSeries>& series,
                     ChartAxes::Corner legend) {
  std::vector<double> xs, ys;
  for (const ChartSeries& s : series) {
    xs.insert(xs.end(), s.x.begin(), s.x.end());
    ys.insert(ys.end(), s.y.begin(), s.y.end());
  }
  ChartAxes axes;
  axes.title = title, axes.x_title = x_title, axes.y_title = y_title;
  axes.legend = legend;
  std::tie(axes.x_min, axes.x_max) = padded_range(xs);
  std::tie(axes.y_min, axes.y_max) = padded_range(ys);
  write_chart_png(path, axes, series);
}

}  // namespace brittle::render
