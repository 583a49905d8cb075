// The accelerator's pipeline on the CPU: Thrust's sequential CPP system runs every kernel
// functor in a host loop (see accel/CMakeLists.txt for THRUST_DEVICE_SYSTEM).
#define AXG_ACCEL_NS emu
#include "backends.hpp"
#include "pipeline.inl"
