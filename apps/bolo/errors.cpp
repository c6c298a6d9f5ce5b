#include "bolo/errors.hpp"

#include <new>

namespace bolo::cli {

void print_error(std::ostream& err, const std::string& message) {
  std::string line;
  line.reserve(message.size());
  for (char c : message) {
    if (c == '\n') {
      if (!line.empty() && line.back() != ' ') line += "; ";
    } else if (c != '\r') {
      line += c;
    }
  }
  while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
  err << "bolo: error: " << line << '\n' << std::flush;
}

int guarded(std::ostream& err, const std::function<int()>& body) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    print_error(err, "out of memory");
  } catch (const std::exception& e) {
    print_error(err, e.what());
  } catch (...) {
    print_error(err, "unknown failure");
  }
  return kExitError;
}

}  // namespace bolo::cli
