# The compile and link flags of SEMAP_SANITIZE, as lists: every semap target gets them, and so does the
# downstream project of engine_package_test (tests/package), whose executable links the sanitized archives.
function(semap_sanitizer_flags compile_var link_var)
  set(compile "")
  set(link "")
  if(SEMAP_SANITIZE STREQUAL "address")
    set(compile -fsanitize=address,undefined -fno-omit-frame-pointer)
    set(link -fsanitize=address,undefined)
  elseif(SEMAP_SANITIZE STREQUAL "fuzzer")
    set(compile -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer)
    set(link -fsanitize=address,undefined)
  elseif(SEMAP_SANITIZE STREQUAL "thread")
    set(compile -fsanitize=thread -fno-omit-frame-pointer)
    set(link -fsanitize=thread)
  endif()
  set(${compile_var} "${compile}" PARENT_SCOPE)
  set(${link_var} "${link}" PARENT_SCOPE)
endfunction()

# Common compile flags for every semap target.
function(semap_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-unused-parameter)
  semap_sanitizer_flags(sanitize_compile sanitize_link)
  if(sanitize_compile)
    target_compile_options(${target} PRIVATE ${sanitize_compile})
    target_link_options(${target} PRIVATE ${sanitize_link})
  endif()
endfunction()

# semap_add_test(NAME <name> SOURCES <files...> LABELS <labels...> [LIBS <libs...>] [TIMEOUT <s>])
# One GoogleTest executable registered with CTest under the given labels (unit, integration, soak, bench).
function(semap_add_test)
  cmake_parse_arguments(T "" "NAME;TIMEOUT" "SOURCES;LABELS;LIBS" ${ARGN})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 600)
  endif()
  if(SEMAP_SANITIZE)
    # Sanitized tests run several times slower (engine_map_test took over 600 s under ASan+UBSan).
    math(EXPR T_TIMEOUT "${T_TIMEOUT} * ${SEMAP_SANITIZE_TIMEOUT_FACTOR}")
  endif()
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE semap_test_common GTest::gtest_main ${T_LIBS})
  semap_set_warnings(${T_NAME})
  add_test(NAME ${T_NAME} COMMAND ${T_NAME})
  set_tests_properties(${T_NAME} PROPERTIES LABELS "${T_LABELS}" TIMEOUT ${T_TIMEOUT}
                       ENVIRONMENT "SEMAP_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()

# semap_add_module(<target> EXPORT_NAME <name> SOURCES <files...> [PUBLIC <deps...>] [PRIVATE <deps...>])
# One library of the engine or io, exported as semap::<name>; headers are included as "engine/<module>/x.h"
# from the source root (installed under include/semap).
function(semap_add_module target)
  cmake_parse_arguments(M "" "EXPORT_NAME" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  add_library(${target} ${M_SOURCES})
  add_library(semap::${M_EXPORT_NAME} ALIAS ${target})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/semap>)
  target_link_libraries(${target} PUBLIC ${M_PUBLIC} PRIVATE ${M_PRIVATE})
  semap_set_warnings(${target})
  set_target_properties(${target} PROPERTIES OUTPUT_NAME ${target} EXPORT_NAME ${M_EXPORT_NAME})
  set_property(GLOBAL APPEND PROPERTY SEMAP_EXPORTED_TARGETS ${target})
endfunction()
