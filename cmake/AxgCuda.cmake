# The CUDA accelerator is optional: built when nvcc is found (AXG_CUDA=AUTO), required
# with AXG_CUDA=ON, skipped with OFF. Without it `--backend cuda` exits 2 "not built".
set(AXG_HAVE_CUDA OFF)
if(NOT AXG_CUDA STREQUAL "OFF")
  if(NOT CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX} AND EXISTS /usr/local/cuda/bin/nvcc)
    set(CMAKE_CUDA_COMPILER /usr/local/cuda/bin/nvcc)
  endif()
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    # SASS for sm_90 (H100/H200), plus PTX for compute_90 that the driver compiles for newer
    # GPUs (and that ctest accel.ptx_contract reads). -DCMAKE_CUDA_ARCHITECTURES="80-real;
    # 90-real;90-virtual" adds the A100. The engine refuses at run time a GPU none of these
    # can run, naming its compute capability and the list (accel/src/engine_cuda.cu).
    if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
      set(CMAKE_CUDA_ARCHITECTURES "90-real;90-virtual")
    endif()
    enable_language(CUDA)
    # Same rules as the host: no FMA contraction, IEEE division and sqrt, no fast math.
    add_compile_options("$<$<COMPILE_LANGUAGE:CUDA>:--fmad=false;--prec-div=true;--prec-sqrt=true;--ftz=false;--expt-relaxed-constexpr>")
    add_compile_options("$<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-ffp-contract=off,-fno-fast-math>")
    set(AXG_HAVE_CUDA ON)
  elseif(AXG_CUDA STREQUAL "ON")
    message(FATAL_ERROR "AXG_CUDA=ON but no CUDA compiler was found")
  endif()
endif()
message(STATUS "axonguide: CUDA accelerator ${AXG_HAVE_CUDA}")
