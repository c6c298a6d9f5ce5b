#pragma once
// Minimal inline-SVG line plots and base64 for the HTML report.

#include <cmath>
#include <string>
#include <vector>

namespace bolo::diag {

struct Series {
  std::string label, colour;
  std::vector<double> y;
  double x0 = 0, dx = 1;
};

std::string svg_plot(const std::string& title, const std::string& x_label, const std::vector<Series>& series,
                     double hline = NAN, const std::string& hline_label = "");
std::string base64(const std::string& bytes);
std::string html_escape(const std::string& text);

}  // namespace bolo::diag
