#include "tools/view/web_assets.h"

#include <array>

extern "C" {
extern const char semap_view_index_html_begin[], semap_view_index_html_end[];
extern const char semap_view_app_js_begin[], semap_view_app_js_end[];
extern const char semap_view_legal_begin[], semap_view_legal_end[];
}

namespace semap::tools::view {

const WebAsset* FindWebAsset(std::string_view path) {
  static const std::array<WebAsset, 4> kAssets = {{
      {"/",
       "text/html; charset=utf-8",
       {semap_view_index_html_begin,
        static_cast<size_t>(semap_view_index_html_end - semap_view_index_html_begin)}},
      {"/index.html",
       "text/html; charset=utf-8",
       {semap_view_index_html_begin,
        static_cast<size_t>(semap_view_index_html_end - semap_view_index_html_begin)}},
      {"/app.js",
       "text/javascript; charset=utf-8",
       {semap_view_app_js_begin, static_cast<size_t>(semap_view_app_js_end - semap_view_app_js_begin)}},
      {"/app.js.LEGAL.txt",
       "text/plain; charset=utf-8",
       {semap_view_legal_begin, static_cast<size_t>(semap_view_legal_end - semap_view_legal_begin)}},
  }};
  for (const WebAsset& a : kAssets) {
    if (a.path == path) return &a;
  }
  return nullptr;
}

}  // namespace semap::tools::view
