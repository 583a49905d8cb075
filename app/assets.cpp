// The assembler's .incbin copies each file into .rodata at build time; the paths are
// compile definitions (app/CMakeLists.txt), and the object depends on the files.
#include "assets.hpp"

#define AXG_EMBED(symbol, path)                                                                  \
  __asm__(".section .rodata\n.global " #symbol "_begin\n.balign 16\n" #symbol "_begin:\n.incbin \"" path \
          "\"\n.global " #symbol "_end\n" #symbol "_end:\n.byte 0\n.previous\n");                 \
  extern "C" const char symbol##_begin[], symbol##_end[];

AXG_EMBED(axg_asset_template, AXG_ASSET_TEMPLATE)
AXG_EMBED(axg_asset_css, AXG_ASSET_CSS)
AXG_EMBED(axg_asset_view_js, AXG_ASSET_VIEW_JS)
AXG_EMBED(axg_asset_plot_run, AXG_ASSET_PLOT_RUN)
#ifdef AXG_ASSET_THREE_MODULE
AXG_EMBED(axg_asset_three_module, AXG_ASSET_THREE_MODULE)
AXG_EMBED(axg_asset_three_core, AXG_ASSET_THREE_CORE)
AXG_EMBED(axg_asset_orbit, AXG_ASSET_ORBIT)
#endif

namespace axg::app::assets {

namespace {
std::string_view view(const char* begin, const char* end) {
  return std::string_view(begin, static_cast<std::size_t>(end - begin));
}
}  // namespace

std::string_view template_html() { return view(axg_asset_template_begin, axg_asset_template_end); }
std::string_view view_css() { return view(axg_asset_css_begin, axg_asset_css_end); }
std::string_view view_js() { return view(axg_asset_view_js_begin, axg_asset_view_js_end); }
std::string_view plot_run_py() { return view(axg_asset_plot_run_begin, axg_asset_plot_run_end); }
#ifdef AXG_ASSET_THREE_MODULE
std::string_view three_module() { return view(axg_asset_three_module_begin, axg_asset_three_module_end); }
std::string_view three_core() { return view(axg_asset_three_core_begin, axg_asset_three_core_end); }
std::string_view orbit_controls() { return view(axg_asset_orbit_begin, axg_asset_orbit_end); }
#else
std::string_view three_module() { return {}; }
std::string_view three_core() { return {}; }
std::string_view orbit_controls() { return {}; }
#endif

}  // namespace axg::app::assets
