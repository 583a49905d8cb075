#pragma once
// The viewer's files, compiled into the command (app/assets.cpp, .incbin), so that a copied
// or installed binary draws without the source tree or node_modules.
#include <string_view>

namespace axg::app::assets {

std::string_view template_html();
std::string_view view_css();
std::string_view view_js();
std::string_view plot_run_py();
// three.js (npm package "three", pinned by package-lock.json); empty when the build found
// no node_modules/three (the view then asks for AXG_THREE_DIR).
std::string_view three_module();
std::string_view three_core();
std::string_view orbit_controls();

}  // namespace axg::app::assets
