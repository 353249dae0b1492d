// x-y charts through vtkContextView + vtkChartXY in the OSMesa-backed window.
#include "chart.hpp"

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
#include <vtkWindowToImageFilter.h>

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
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::BOTTOM);
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
    plot->SetColor(s.color[0], s.color[1], s.color[2], 255);
    plot->SetLabel(s.name);
    if (s.style == ChartSeries::Style::points) {
      static const int markers[] = {vtkPlotPoints::CIRCLE, vtkPlotPoints::SQUARE,
                                    vtkPlotPoints::DIAMOND, vtkPlotPoints::CROSS,
                                    vtkPlotPoints::PLUS};
      auto* points = vtkPlotPoints::SafeDownCast(plot);
      points->SetMarkerStyle(markers[s.marker % 5]);
      points->SetMarkerSize(10);
    } else {
      plot->SetWidth(2.0);
      if (s.style == ChartSeries::Style::dashed) plot->GetPen()->SetLineType(vtkPen::DASH_LINE);
    }
  }
  window.window()->Render();
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(window.window());
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  write_png(*grab->GetOutput(), path);
}

}  // namespace brittle::render
