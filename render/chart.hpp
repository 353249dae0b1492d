// x-y charts drawn off-screen with VTK's charts (vtkChartXY), for the crack speed versus
// strain energy figures (paper Figs. 5-6).
#pragma once

#include <array>
#include <string>
#include <vector>

namespace brittle::render {

struct ChartSeries {
  enum class Style { points, line, dashed };
  std::string name;               ///< legend entry
  std::vector<double> x, y;
  Style style = Style::points;
  std::array<unsigned char, 3> color = {0, 0, 0};
  int marker = 0;                 ///< points: 0 circle, 1 square, 2 diamond, 3 cross, 4 plus
  unsigned char alpha = 255;      ///< opacity (faint overlays: many series on one another)
  double marker_size = 10;        ///< points: in pixels
  bool legend = true;             ///< false: no legend entry
};

struct ChartAxes {
  std::string title, x_title, y_title;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  int width = 900, height = 650;
  /// The corner of the plot area the legend sits in: put it where the data is not.
  enum class Corner { bottom_right, top_right, top_left, bottom_left };
  Corner legend = Corner::bottom_right;
};

/// Draws the series on fixed axes with a legend and writes a PNG (throws brittle::Error).
void write_chart_png(const std::string& path, const ChartAxes& axes,
                     const std::vector<ChartSeries>& series);

/// The same on axes that fit the data with a 5 % margin (a flat or empty range gets +-1).
void write_chart_png(const std::string& path, const std::string& title, const std::string& x_title,
                     const std::string& y_title, const std::vector<ChartSeries>& series,
                     ChartAxes::Corner legend = ChartAxes::Corner::bottom_right);

}  // namespace brittle::render
