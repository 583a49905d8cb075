# Generates axonguide/version.hpp at build time (not only at configure time) so that the
# commit recorded in manifests and golden provenance is the one actually built.
set(AXG_VERSION_HEADER ${CMAKE_BINARY_DIR}/generated/axonguide/version.hpp)
string(TOUPPER "${CMAKE_BUILD_TYPE}" AXG_BUILD_TYPE_UPPER)
add_custom_target(axg_version ALL
  COMMAND ${CMAKE_COMMAND}
          -DSRC=${CMAKE_SOURCE_DIR} -DOUT=${AXG_VERSION_HEADER}
          -DVERSION=${PROJECT_VERSION}
          -DBUILD_TYPE=${CMAKE_BUILD_TYPE}
          "-DCXX_ID=${CMAKE_CXX_COMPILER_ID} ${CMAKE_CXX_COMPILER_VERSION}"
          "-DCXX_FLAGS=${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_${AXG_BUILD_TYPE_UPPER}} ${AXG_FP_FLAGS_STRING}"
          -P ${CMAKE_SOURCE_DIR}/cmake/WriteVersion.cmake
  BYPRODUCTS ${AXG_VERSION_HEADER}
  COMMENT "axonguide version header")
