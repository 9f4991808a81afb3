# The WebAssembly build (emcmake cmake -S . -B build-wasm; scripts/build_web.sh):
# the decoder libraries and web/ only, compiled by Debian's emscripten.
#
# CGAL and Boost are header-only here. Their folders are staged beside each
# other so that /usr/include itself (glibc's headers) never reaches emcc;
# xxHash's header is its whole implementation (XXH_INLINE_ALL, common/).
# Without GMP, CGAL's exact fallback is its own MP_Float and Boost.Multiprecision:
# the same exact predicates, so the same cells (docs/ARCHITECTURE.md §5). WebAssembly has
# no rounding modes: CGAL's interval filters widen by nextafter instead.
set(DTM_WASM_HOST_INCLUDE ${CMAKE_BINARY_DIR}/host-include)
file(MAKE_DIRECTORY ${DTM_WASM_HOST_INCLUDE})
foreach(entry CGAL boost xxhash.h)
  if(NOT EXISTS /usr/include/${entry})
    message(FATAL_ERROR "/usr/include/${entry} is missing: run scripts/setup.sh")
  endif()
  if(NOT EXISTS ${DTM_WASM_HOST_INCLUDE}/${entry})
    file(CREATE_LINK /usr/include/${entry} ${DTM_WASM_HOST_INCLUDE}/${entry} SYMBOLIC)
  endif()
endforeach()

add_library(CGAL::CGAL INTERFACE IMPORTED)
target_include_directories(CGAL::CGAL SYSTEM INTERFACE ${DTM_WASM_HOST_INCLUDE})
target_compile_definitions(CGAL::CGAL INTERFACE
  CGAL_DISABLE_GMP=1 CGAL_ALWAYS_ROUND_TO_NEAREST CGAL_HAS_NO_THREADS)

# Native WebAssembly exceptions: CGAL's filtered predicates throw when an
# interval is uncertain, and the decoder turns CGAL's errors into a Status.
# JavaScript-emulated exceptions would route every call through a trampoline.
add_compile_options(-fwasm-exceptions)
add_link_options(-fwasm-exceptions)

# Debian's emcc finds its node modules (acorn) in /usr/share/nodejs only when
# node itself is Debian's; the machine's node may be NodeSource's. Linking is
# where emcc runs node, so every link gets the path, whoever runs the build.
set_property(GLOBAL PROPERTY RULE_LAUNCH_LINK "${CMAKE_COMMAND} -E env NODE_PATH=/usr/share/nodejs")
