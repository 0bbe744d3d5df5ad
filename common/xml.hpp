#pragma once
// Escaping for the XML files adamss writes by hand (frames, series.pvd, the XDMF sidecar).
#include <string>
#include <string_view>

namespace adamss {

/// `s` with &, < and " escaped, so it may stand in an attribute value or element text.
[[nodiscard]] inline std::string xml_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    if (c == '&') {
      out += "&amp;";
    } else if (c == '<') {
      out += "&lt;";
    } else if (c == '"') {
      out += "&quot;";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace adamss
