# cmake/CheckLayering.cmake on small made-up trees (ctest engine_layering_test): a clean tree passes, and each
# kind of wrong include fails with a message naming the file and what it includes.
#   cmake -DSOURCE_DIR=... -DWORK_DIR=... -P layering_test.cmake
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE "${WORK_DIR}")
set(graph "core;links;Eigen3::Eigen\ncore;public;Eigen3::Eigen\n")
string(APPEND graph "map;links;core;CGAL::CGAL\nmap;public;core\n")
string(APPEND graph "depth;links;core\ndepth;public;core\n")
string(APPEND graph "pipeline;links;core;map;depth\npipeline;public;core;map;depth\n")

# check(<case> <expected message or "">, then pairs of <file> <content>)
function(check name expected)
  set(root "${WORK_DIR}/${name}")
  file(WRITE "${root}/engine/core/types.h" "#pragma once\n#include <Eigen/Core>\n")
  file(WRITE "${root}/engine/map/map.h" "#include \"engine/core/types.h\"\n")
  file(WRITE "${root}/engine/map/internal/cells.h" "#include <CGAL/Delaunay_triangulation_3.h>\n")
  file(WRITE "${root}/engine/depth/depth.h" "#include \"engine/core/types.h\"\n")
  file(WRITE "${root}/engine/pipeline/pipeline.cc" "#include \"engine/map/map.h\"\n#include \"engine/depth/depth.h\"\n")
  set(pairs ${ARGN})
  while(pairs)
    list(POP_FRONT pairs file content)
    file(WRITE "${root}/${file}" "${content}\n")
  endwhile()
  file(WRITE "${root}/graph.txt" "${graph}")
  execute_process(COMMAND "${CMAKE_COMMAND}" -DSOURCE_DIR=${root} -DGRAPH_FILE=${root}/graph.txt
                          -DSTAMP=${root}/stamp -P "${SOURCE_DIR}/cmake/CheckLayering.cmake"
                  RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
  if(expected STREQUAL "")
    if(NOT rc EQUAL 0 OR NOT EXISTS "${root}/stamp")
      message(FATAL_ERROR "layering_test ${name}: a clean tree failed:\n${err}")
    endif()
  else()
    string(FIND "${err}" "${expected}" at)
    if(rc EQUAL 0 OR at EQUAL -1)
      message(FATAL_ERROR "layering_test ${name}: expected a failure saying '${expected}', got rc ${rc}:\n${err}")
    endif()
  endif()
  message(STATUS "layering_test ${name}: ok")
endfunction()

check(clean "")
check(unlinked_module "engine/depth/depth.cc: includes engine/map/map.h, but semap_depth does not link semap_map"
      engine/depth/depth.cc "#include \"engine/map/map.h\"")
check(other_internal "engine/pipeline/run.cc: includes engine/map/internal/cells.h, a private header of map"
      engine/pipeline/run.cc "#include \"engine/map/internal/cells.h\"")
check(io_from_engine "engine/core/log.cc: includes io/config/config.h"
      engine/core/log.cc "#include \"io/config/config.h\"")
check(cgal_unlinked "engine/depth/mesh.cc: includes CGAL/Surface_mesh.h, but semap_depth does not link cgal"
      engine/depth/mesh.cc "#include <CGAL/Surface_mesh.h>")
check(cgal_public_header "engine/map/map.h: a public header includes CGAL/Delaunay_triangulation_3.h"
      engine/map/map.h "#include <CGAL/Delaunay_triangulation_3.h>")
check(cgal_in_private_source "" engine/map/map.cc "#include <CGAL/Delaunay_triangulation_3.h>")
check(io_includes_app "io/kitti/reader.cc: includes app/config/config.h (io/ is below app|tools/)"
      io/kitti/reader.cc "#include \"app/config/config.h\"")
check(app_includes_tools "app/run/run.cc: includes tools/cli_common.h (app/ is below tools/)"
      app/run/run.cc "#include \"tools/cli_common.h\"")
check(layers_in_order "" app/run/run.cc "#include \"io/kitti/reader.h\"" tools/main.cc "#include \"app/run/run.h\"")
message("layering_test: every case as expected")
