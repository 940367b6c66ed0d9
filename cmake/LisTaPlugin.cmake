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
# A plugin knows no other plugin: its sources, tests and the files they
# include (with "...") lie in its own folder, and it links no plugin target.
# What plugins share lives in common/; what their tests share in
# common/testing (lista::test_support, linked into every plugin test).
function(lista_check_plugin_isolation name)
  set(own ${CMAKE_CURRENT_SOURCE_DIR})
  foreach(file ${ARGN})
    get_filename_component(path ${file} ABSOLUTE BASE_DIR ${own})
    file(RELATIVE_PATH rel ${own} ${path})
    if(rel MATCHES "^\\.\\./")
      message(FATAL_ERROR "plugin ${name}: ${file} lies outside the plugin's folder; move shared code to common/")
    endif()
  endforeach()
  file(GLOB_RECURSE own_files ${own}/*.cpp ${own}/*.hpp ${own}/*.h)
  foreach(path ${own_files})
    file(STRINGS ${path} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"[^\"]+\"")
    get_filename_component(dir ${path} DIRECTORY)
    foreach(line ${includes})
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" header "${line}")
      get_filename_component(target ${header} ABSOLUTE BASE_DIR ${dir})
      file(RELATIVE_PATH rel ${own} ${target})
      if(rel MATCHES "^\\.\\./")
        file(RELATIVE_PATH shown ${own} ${path})
        message(FATAL_ERROR "plugin ${name}: ${shown} includes \"${header}\" from outside the plugin's folder; "
                            "move what plugins share to common/ (tests: common/testing)")
      endif()
    endforeach()
  endforeach()
endfunction()

function(lista_add_plugin)
  cmake_parse_arguments(P "" "NAME" "SOURCES;LIBS;TESTS;TEST_LIBS" ${ARGN})
  if(NOT P_NAME OR NOT P_SOURCES)
    message(FATAL_ERROR "lista_add_plugin: NAME and SOURCES are required")
  endif()
  lista_check_plugin_isolation(${P_NAME} ${P_SOURCES} ${P_TESTS})
  foreach(lib ${P_LIBS} ${P_TEST_LIBS})
    if(lib IN_LIST LISTA_ALL_PLUGIN_TARGETS)
      message(FATAL_ERROR "plugin ${P_NAME} links ${lib}, another plugin; share code through common/ instead")
    endif()
  endforeach()
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
    target_link_libraries(test_${id} PRIVATE ${target} lista::sdk ${P_LIBS} ${P_TEST_LIBS} lista::test_support
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
