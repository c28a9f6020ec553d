// A small XML reader for robot descriptions (URDF): elements, attributes (the five predefined
// entities and numeric character references decoded), comments, the declaration and a DOCTYPE
// skipped; text between elements is ignored. Each element keeps its line, for error messages.
// Refused with the line: CDATA, processing instructions after the declaration, mismatched or
// unclosed tags, a repeated attribute, more than 256 attributes in an element, nesting deeper
// than 64, more than 100,000 elements.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

namespace reel::io {

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<XmlElement> children;
  int line = 0;
  const std::string* attribute(const std::string& key) const {
    for (const auto& [k, v] : attributes)
      if (k == key) return &v;
    return nullptr;
  }
};

// The document's root element; errors are BadInput, "line N: ...".
Result<XmlElement> parseXml(const std::string& text);

}  // namespace reel::io
