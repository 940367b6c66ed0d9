# lista_add_plugin(NAME <kind>.<name>
#                  SOURCES a.cpp b.cpp
#                  [LIBS targets...]            linked privately
#                  [TESTS test_a.cpp ...]       one GoogleTest executable
#                  [TEST_LIBS targets...])
# Builds lib/lista-plugins/liblista_<kind>_<name>.so (dots and dashes become
# underscores) with RUNPATH $ORIGIN/.., so it finds liblista_sdk.so next to
# the core; out of LiSTA's tree (find_package(lista)) the RUNPATH also names
# the SDK's own folder, so the library loads on its own too (ldd, Python). The test executable links the plugin itself (its classes are
# visible) and gets LISTA_PLUGIN_PATH pointing at the plugin folder.
function(lista_add_plugin)
  cmake_parse_arguments(P "" "NAME" "SOURCES;LIBS;TESTS;TEST_LIBS" ${ARGN})
  if(NOT P_NAME OR NOT P_SOURCES)
    message(FATAL_ERROR "lista_add_plugin: NAME and SOURCES are required")
  endif()
  string(REGEX REPLACE "[.-]" "_" id "${P_NAME}")
  set(target lista_${id})
  add_library(${target} SHARED ${P_SOURCES})
  target_link_libraries(${target} PUBLIC lista::sdk PRIVATE ${P_LIBS})
  set_target_properties(${target} PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${LISTA_PLUGIN_OUTPUT_DIR}
    BUILD_WITH_INSTALL_RPATH ON
    INSTALL_RPATH "$ORIGIN/..;${LISTA_SDK_LIBRARY_DIR}"
    LISTA_PLUGIN_NAME "${P_NAME}")
  # -Bsymbolic-functions: the library's manifest alias binds to its own
  # manifest() even when a program already holds another plugin's (a plugin
  # test links its plugin, then loads the others through the core).
  target_link_options(${target} PRIVATE "LINKER:--enable-new-dtags" "LINKER:-Bsymbolic-functions")
  set_property(GLOBAL APPEND PROPERTY LISTA_PLUGIN_TARGETS ${target})
  install(TARGETS ${target} LIBRARY DESTINATION lib/${LISTA_PLUGIN_SUBDIR})

  if(LISTA_BUILD_TESTS AND P_TESTS)
    add_executable(test_${id} ${P_TESTS})
    target_link_libraries(test_${id} PRIVATE ${target} lista::sdk ${P_LIBS} ${P_TEST_LIBS}
                          GTest::gtest GTest::gtest_main)
    target_compile_definitions(test_${id} PRIVATE
      LISTA_PLUGIN_DIR="${LISTA_PLUGIN_OUTPUT_DIR}"
      LISTA_BIN_DIR="${CMAKE_RUNTIME_OUTPUT_DIRECTORY}"
      LISTA_SOURCE_DIR="${LISTA_SOURCE_DIR}")
    gtest_discover_tests(test_${id} DISCOVERY_MODE PRE_TEST
      PROPERTIES ENVIRONMENT "LISTA_PLUGIN_PATH=${LISTA_PLUGIN_OUTPUT_DIR}" LABELS "plugin")
  endif()
endfunction()

# lista_add_test(NAME name SOURCES ... [LIBS ...]) for core and tool suites.
function(lista_add_test)
  cmake_parse_arguments(T "" "NAME" "SOURCES;LIBS" ${ARGN})
  if(NOT LISTA_BUILD_TESTS)
    return()
  endif()
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${T_NAME} PRIVATE
    LISTA_PLUGIN_DIR="${LISTA_PLUGIN_OUTPUT_DIR}"
    LISTA_BIN_DIR="${CMAKE_RUNTIME_OUTPUT_DIRECTORY}"
    LISTA_SOURCE_DIR="${LISTA_SOURCE_DIR}")
  gtest_discover_tests(${T_NAME} DISCOVERY_MODE PRE_TEST
    PROPERTIES ENVIRONMENT "LISTA_PLUGIN_PATH=${LISTA_PLUGIN_OUTPUT_DIR}")
endfunction()
