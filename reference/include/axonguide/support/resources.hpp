#pragma once
// Where the command finds its data at run time (the bundled scenes, the golden networks,
// the validation's plot scripts, the plot helper): $AXG_SOURCE_DIR when set; else the
// installed tree, share/axonguide beside the bin/ (or lib/python3/...) folder the code
// was loaded from; else the source tree it was built from. The viewer's page and
// three.js are compiled into the command (app/assets.cpp) and need none of these.
#include <filesystem>

namespace axg {

std::filesystem::path data_dir();

// The folder of the executable or shared library this code was loaded from.
std::filesystem::path loaded_from();

}  // namespace axg
