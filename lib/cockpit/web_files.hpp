// The page's files (lib/cockpit/web/), embedded into tiller-cockpit at build time by
// tools/embed-files.py, so the page needs nothing but the cockpit process.
#pragma once

#include <cstddef>
#include <string_view>

namespace tiller::cockpit {

struct WebFile {
  const char* path;  // "/index.html"
  const char* mime;  // "text/html; charset=utf-8"
  const unsigned char* data;
  std::size_t size;
};

// The file served at `path` ("/" is /index.html), or nullptr.
const WebFile* find_web_file(std::string_view path);

}  // namespace tiller::cockpit
