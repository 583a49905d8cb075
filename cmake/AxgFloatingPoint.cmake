# Floating-point rules of the determinism contract, applied to every compile.
# - no contraction of a*b+c into an FMA (results would depend on the compiler's choice);
# - no fast-math family flags (reassociation, finite-math, reciprocal approximations);
# - IEEE double only: x86-64 uses SSE2, so there is no x87 excess precision.
# nvcc gets the matching flags (--fmad=false, no --use_fast_math) in AxgCuda.cmake.
set(AXG_FP_FLAGS -ffp-contract=off -fno-fast-math -fno-associative-math
    -fno-reciprocal-math -fno-finite-math-only -fsigned-zeros -ftrapping-math)
add_compile_options("$<$<COMPILE_LANGUAGE:CXX>:${AXG_FP_FLAGS}>")
add_compile_options("$<$<COMPILE_LANGUAGE:CXX>:-Wall;-Wextra;-Wpedantic>")
if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  add_compile_options("$<$<COMPILE_LANGUAGE:CXX>:-mfpmath=sse;-msse2>")
endif()
# Recorded in manifest.json so that a reader can see what produced the numbers.
string(REPLACE ";" " " AXG_FP_FLAGS_STRING "${AXG_FP_FLAGS}")
