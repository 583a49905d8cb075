// libFuzzer harness over the scene parser: any bytes, as `axonguide run FILE` reads them.
// A refusal is an InputError; anything else that escapes (another exception, a crash, a
// leak, a hang, undefined behaviour) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "axonguide/support/error.hpp"
#include "axonguide/scene/scene.hpp"

namespace {

// Messages are escaped: no control byte reaches a terminal.
bool printable(const char* message) {
  for (const char* c = message; *c; ++c)
    if (static_cast<unsigned char>(*c) < 0x20 || *c == 0x7f) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  axg::ParseResult r;
  try {
    r = axg::parse_scene(text, "fuzz.json");
  } catch (const axg::InputError& e) {
    if (!printable(e.what())) __builtin_trap();
    return 0;
  }
  // An accepted scene has a canonical form that is accepted and reads back as itself.
  const std::string canonical = axg::scene_to_json(r.scene).dump();
  try {
    if (axg::scene_to_json(axg::parse_scene(canonical, "canonical").scene).dump() != canonical) __builtin_trap();
  } catch (const axg::InputError&) {
    __builtin_trap();
  }
  return 0;
}
