#include "bolo/odometry/plot.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>

namespace bolo::odo {

std::string trajectory_svg(const std::string& title, const std::vector<PlotSeries>& series) {
  double lo_x = std::numeric_limits<double>::max(), lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;
  for (const PlotSeries& s : series)
    for (const vo::Vec3& p : s.points)
      lo_x = std::min(lo_x, p.x()), hi_x = std::max(hi_x, p.x()), lo_y = std::min(lo_y, p.y()), hi_y = std::max(hi_y, p.y());
  if (lo_x > hi_x) lo_x = lo_y = 0, hi_x = hi_y = 1;
  // Equal scale on both axes, so shapes are not distorted.
  const double span = std::max({hi_x - lo_x, hi_y - lo_y, 1e-6});
  const double size = 560, margin = 40, scale = size / span;
  std::string svg;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" font-family=\"sans-serif\" font-size=\"13\">\n"
                "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n<text x=\"%.0f\" y=\"22\">",
                size + 2 * margin, size + 2 * margin + 20, margin);
  svg += buf;
  for (char c : title) svg += c == '<' ? std::string("&lt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
  svg += "</text>\n";
  int row = 0;
  for (const PlotSeries& s : series) {
    svg += "<polyline fill=\"none\" stroke-width=\"1.5\" stroke=\"" + s.colour + "\" points=\"";
    for (const vo::Vec3& p : s.points) {
      std::snprintf(buf, sizeof buf, "%.1f,%.1f ", margin + (p.x() - lo_x) * scale,
                    margin + 20 + size - (p.y() - lo_y) * scale);
      svg += buf;
    }
    svg += "\"/>\n";
    std::snprintf(buf, sizeof buf, "<text x=\"%.0f\" y=\"%.0f\" fill=\"%s\">", margin, size + 2 * margin + 4.0 - 16.0 * row, s.colour.c_str());
    svg += buf + s.label + "</text>\n";
    ++row;
  }
  std::snprintf(buf, sizeof buf, "<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"end\">x-y, %.3g units across</text>\n",
                size + 2 * margin - 4, size + 2 * margin + 4, span);
  svg += buf;
  svg += "</svg>\n";
  return svg;
}

}  // namespace bolo::odo
