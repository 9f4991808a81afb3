# Install rules and the CMake package: find_package(dtmesh) gives
# dtmesh::decoder and dtmesh::encoder (tests/decoder_only builds a tiny
# decoder against the installed package).
include(CMakePackageConfigHelpers)
set_target_properties(dtm_decoder PROPERTIES EXPORT_NAME decoder)
set_target_properties(dtm_encoder PROPERTIES EXPORT_NAME encoder)
set_target_properties(dtm_common PROPERTIES EXPORT_NAME common)
set_target_properties(dtm_bitstream PROPERTIES EXPORT_NAME bitstream)
set_target_properties(dtm_mesh PROPERTIES EXPORT_NAME mesh)
set_target_properties(dtm_core PROPERTIES EXPORT_NAME core)
install(TARGETS dtm_common dtm_bitstream dtm_mesh dtm_core dtm_decoder dtm_encoder
        EXPORT dtmeshTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
foreach(folder common bitstream mesh core codec)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/dtmesh/${folder}
          FILES_MATCHING PATTERN "*.h")
endforeach()
install(TARGETS meshenc meshdec meshinfo RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/dtmesh)
install(EXPORT dtmeshTargets NAMESPACE dtmesh:: DESTINATION ${config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/dtmeshConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/dtmeshConfig.cmake INSTALL_DESTINATION ${config_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/dtmeshConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/dtmeshConfig.cmake ${PROJECT_BINARY_DIR}/dtmeshConfigVersion.cmake
        DESTINATION ${config_dir})
