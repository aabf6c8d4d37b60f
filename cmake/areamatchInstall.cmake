# install(): headers, exported targets, areamatchConfig.cmake and its version file, so that
#   find_package(areamatch 0.1 CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE areamatch::areamatch areamatch::io)
# works from the install prefix.
include(CMakePackageConfigHelpers)

set(AREAMATCH_CMAKE_DIR "${CMAKE_INSTALL_DATADIR}/areamatch/cmake")

install(DIRECTORY include/areamatch DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")

set(_areamatch_targets areamatch)
if(AREAMATCH_WITH_IO)
  list(APPEND _areamatch_targets areamatch_io)
endif()
install(TARGETS ${_areamatch_targets} EXPORT areamatchTargets)
install(EXPORT areamatchTargets NAMESPACE areamatch:: DESTINATION "${AREAMATCH_CMAKE_DIR}")

configure_package_config_file(cmake/areamatchConfig.cmake.in
  "${CMAKE_CURRENT_BINARY_DIR}/areamatchConfig.cmake"
  INSTALL_DESTINATION "${AREAMATCH_CMAKE_DIR}")
# Header-only: one package serves every architecture.
write_basic_package_version_file("${CMAKE_CURRENT_BINARY_DIR}/areamatchConfigVersion.cmake"
  COMPATIBILITY SameMajorVersion ARCH_INDEPENDENT)
install(FILES
  "${CMAKE_CURRENT_BINARY_DIR}/areamatchConfig.cmake"
  "${CMAKE_CURRENT_BINARY_DIR}/areamatchConfigVersion.cmake"
  cmake/areamatchDependencies.cmake
  DESTINATION "${AREAMATCH_CMAKE_DIR}")
install(FILES LICENSE README.md DESTINATION "${CMAKE_INSTALL_DOCDIR}")
