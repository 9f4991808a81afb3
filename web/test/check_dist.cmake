# cmake -DDIST=DIR -P check_dist.cmake: fails unless DIR holds the viewer page
# and the WebAssembly decoder.
foreach(file index.html viewer.js worker.js dtm_decoder.mjs dtm_decoder.wasm)
  if(NOT EXISTS ${DIST}/${file})
    message(FATAL_ERROR "${DIST}/${file} is missing: build the WebAssembly decoder and the page with scripts/build_web.sh")
  endif()
endforeach()
