// The page's files, built into the executable (web_assets.S includes them with .incbin): `semap view` needs
// no file beside it and no network. The sources are tools/view/web/src and index.html; dist/ holds the
// bundle esbuild built from them with three.js (tools/view/web/build.sh rebuilds it).
#pragma once

#include <string_view>

namespace semap::tools::view {

struct WebAsset {
  std::string_view path;  // URL path, e.g. "/app.js"
  std::string_view content_type;
  std::string_view body;
};

// Every served file; index.html is also served at "/".
const WebAsset* FindWebAsset(std::string_view path);

}  // namespace semap::tools::view
