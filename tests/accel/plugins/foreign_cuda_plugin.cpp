// A CUDA plugin from another build, for cuda_plugin_test: the entry point and table of
// accel/src/cuda_plugin.hpp, with this build's facts but one changed (AXG_FOREIGN: "commit"
// or "abi"), and no engine behind it. The host must refuse it before calling anything.
#include <cstring>

#include "cuda_plugin.hpp"

extern "C" __attribute__((visibility("default"))) const axg::accel::CudaPlugin* axg_cuda_plugin() {
  static axg::accel::CudaPlugin table{};
  table.abi = axg::accel::kCudaPluginAbi;
  table.build = axg::accel::this_build();
  table.architectures = "90-real,90-virtual";
  if (std::strcmp(AXG_FOREIGN, "commit") == 0) table.build.commit = "0123456789abcdef0123456789abcdef01234567";
  if (std::strcmp(AXG_FOREIGN, "abi") == 0) table.abi = axg::accel::kCudaPluginAbi + 1000;
  return &table;
}
