# find_package(lista): exports lista::sdk, lista::core and lista_add_plugin,
# both from the build tree (<build>/listaConfig.cmake) and from an install
# (<prefix>/lib/cmake/lista). Third-party plugins build against either.
include(CMakePackageConfigHelpers)
set_target_properties(lista_sdk PROPERTIES EXPORT_NAME sdk)
set_target_properties(lista_core PROPERTIES EXPORT_NAME core)

set(lista_cmake_dir ${CMAKE_CURRENT_LIST_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/listaConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)

# Build tree: targets point at the build outputs, the plugin function at the source tree.
export(EXPORT listaTargets NAMESPACE lista:: FILE ${CMAKE_BINARY_DIR}/listaTargets.cmake)
set(LISTA_CONFIG_PLUGIN_CMAKE ${CMAKE_SOURCE_DIR}/cmake/LisTaPlugin.cmake)
configure_file(${lista_cmake_dir}/listaConfig.cmake.in ${CMAKE_BINARY_DIR}/listaConfig.cmake @ONLY)

# Install tree.
install(EXPORT listaTargets NAMESPACE lista:: DESTINATION lib/cmake/lista)
set(LISTA_CONFIG_PLUGIN_CMAKE "\${CMAKE_CURRENT_LIST_DIR}/LisTaPlugin.cmake")
configure_file(${lista_cmake_dir}/listaConfig.cmake.in ${CMAKE_BINARY_DIR}/install-config/listaConfig.cmake @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/install-config/listaConfig.cmake ${CMAKE_BINARY_DIR}/listaConfigVersion.cmake
              ${CMAKE_SOURCE_DIR}/cmake/LisTaPlugin.cmake
        DESTINATION lib/cmake/lista)
