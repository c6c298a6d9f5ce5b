#include "svg.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace bolo::diag {

std::string svg_plot(const std::string& title, const std::string& x_label, const std::vector<Series>& series,
                     double hline, const std::string& hline_label) {
  const double W = 640, H = 220, L = 60, R = 10, T = 24, B = 34;
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (const Series& s : series)
    for (std::size_t i = 0; i < s.y.size(); ++i) {
      if (!std::isfinite(s.y[i])) continue;
      xmin = std::min(xmin, s.x0 + s.dx * i);
      xmax = std::max(xmax, s.x0 + s.dx * i);
      ymin = std::min(ymin, s.y[i]);
      ymax = std::max(ymax, s.y[i]);
    }
  if (std::isfinite(hline)) { ymin = std::min(ymin, hline); ymax = std::max(ymax, hline); }
  if (!std::isfinite(xmin)) { xmin = 0; xmax = 1; ymin = 0; ymax = 1; }
  if (xmax <= xmin) xmax = xmin + 1;
  if (ymax <= ymin) { ymax += 0.5 + std::fabs(ymax) * 0.01; ymin -= 0.5 + std::fabs(ymin) * 0.01; }
  auto X = [&](double x) { return L + (x - xmin) / (xmax - xmin) * (W - L - R); };
  auto Y = [&](double y) { return T + (ymax - y) / (ymax - ymin) * (H - T - B); };
  std::ostringstream s;
  s.precision(4);
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H << "' font-family='sans-serif' font-size='11'>"
    << "<rect x='" << L << "' y='" << T << "' width='" << W - L - R << "' height='" << H - T - B << "' fill='#fafafa' stroke='#999'/>"
    << "<text x='" << L << "' y='14' font-weight='bold'>" << html_escape(title) << "</text>"
    << "<text x='" << (W + L) / 2 << "' y='" << H - 4 << "' text-anchor='middle'>" << html_escape(x_label) << "</text>"
    << "<text x='" << L - 4 << "' y='" << T + 8 << "' text-anchor='end'>" << ymax << "</text>"
    << "<text x='" << L - 4 << "' y='" << H - B << "' text-anchor='end'>" << ymin << "</text>"
    << "<text x='" << L << "' y='" << H - B + 12 << "'>" << xmin << "</text>"
    << "<text x='" << W - R << "' y='" << H - B + 12 << "' text-anchor='end'>" << xmax << "</text>";
  if (ymin < 0 && ymax > 0)
    s << "<line x1='" << L << "' x2='" << W - R << "' y1='" << Y(0) << "' y2='" << Y(0) << "' stroke='#ccc'/>";
  if (std::isfinite(hline))
    s << "<line x1='" << L << "' x2='" << W - R << "' y1='" << Y(hline) << "' y2='" << Y(hline)
      << "' stroke='#888' stroke-dasharray='4 3'/><text x='" << W - R - 2 << "' y='" << Y(hline) - 3
      << "' text-anchor='end' fill='#666'>" << html_escape(hline_label) << "</text>";
  int legend = 0;
  for (const Series& ser : series) {
    s << "<polyline fill='none' stroke='" << ser.colour << "' stroke-width='1.2' points='";
    for (std::size_t i = 0; i < ser.y.size(); ++i)
      if (std::isfinite(ser.y[i])) s << X(ser.x0 + ser.dx * i) << "," << Y(ser.y[i]) << " ";
    s << "'/>";
    s << "<text x='" << L + 8 + 150 * legend << "' y='" << T + 12 << "' fill='" << ser.colour << "'>" << html_escape(ser.label) << "</text>";
    ++legend;
  }
  s << "</svg>";
  return s.str();
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const unsigned a = static_cast<unsigned char>(bytes[i]);
    const unsigned b = i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0;
    const unsigned c = i + 2 < bytes.size() ? static_cast<unsigned char>(bytes[i + 2]) : 0;
    const unsigned v = (a << 16) | (b << 8) | c;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? table[v & 63] : '=';
  }
  return out;
}

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '\'': out += "&#39;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace bolo::diag
