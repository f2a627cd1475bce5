# cmake --install: the public headers, the stage libraries (static, position-independent) and
# an exported package, so that another CMake project can
#   find_package(vdbmesh) and target_link_libraries(app PRIVATE vdbmesh::vdbmesh)
# (or a single stage: vdbmesh::read, vdbmesh::io, vdbmesh::mesh, ...). tests/install/ proves it.
include(CMakePackageConfigHelpers)

set(VDBMESH_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/vdbmesh)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/vdbmesh DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
install(TARGETS ${stage_libraries} vdbmesh_core EXPORT vdbmeshTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT vdbmeshTargets NAMESPACE vdbmesh:: DESTINATION ${VDBMESH_INSTALL_CMAKEDIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/vdbmeshConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/vdbmeshConfig.cmake
                              INSTALL_DESTINATION ${VDBMESH_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/vdbmeshConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/vdbmeshConfig.cmake ${PROJECT_BINARY_DIR}/vdbmeshConfigVersion.cmake
        DESTINATION ${VDBMESH_INSTALL_CMAKEDIR})
