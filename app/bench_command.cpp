#include "commands.hpp"
#include "axonguide/error.hpp"
namespace axg::app {
int cmd_bench(const BenchArgs&) { throw InputError("bench: not yet"); }
}
