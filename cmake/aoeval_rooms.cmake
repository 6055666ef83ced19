# The one-way rule of the rooms (README "Architecture", ../shared/STYLE.md), checked at configure
# time from the targets' declared link lists, so a violation stops the build before it compiles:
#   - reports/ (aoeval_reports) and the code it draws and reads with (aoeval_drawing,
#     aoeval_results) never reach, directly or through another target, an estimator, the Vulkan
#     layer, a reference, or a runner (evaluation, sweep, bench, figures);
#   - results/ (aoeval_results) is a leaf: of aoeval's targets it reaches only aoeval_base (errors,
#     JSON reading, atomic writes, the median), never aoeval_scenes and its Embree, OIIO and assimp;
#   - base/ (aoeval_base, the ground floor) links nothing of ours and includes only base/;
#   - cmd/ (the `aoeval` binary) is the top floor: no source outside cmd/ includes a header of it;
#   - only the `aoeval` binary (cli/), aoeval_figures and the reports' own tests link aoeval_reports;
#   - estimators/ (the registry, every estimator folder, the Vulkan layer) never reach references/:
#     an estimator that traces rays shares sampling/'s tracer with the ground truth instead.
# The closure of every checked target is written to <build>/rooms_links.txt (the evidence, no ldd).

# The aoeval targets `target` reaches through LINK_LIBRARIES and INTERFACE_LINK_LIBRARIES.
function(aoeval_link_closure target out)
  set(seen)
  set(unvisited ${target})
  while(unvisited)
    list(POP_FRONT unvisited t)
    foreach(prop LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
      get_target_property(libs ${t} ${prop})
      if(NOT libs)
        continue()
      endif()
      foreach(lib IN LISTS libs)
        string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" lib "${lib}")
        if(lib MATCHES "^aoeval" AND TARGET ${lib} AND NOT lib IN_LIST seen)
          list(APPEND seen ${lib})
          list(APPEND unvisited ${lib})
        endif()
      endforeach()
    endforeach()
  endwhile()
  list(SORT seen)
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

# Every target defined under `dir`, recursively.
function(aoeval_targets_under dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    aoeval_targets_under(${sub} sub_targets)
    list(APPEND targets ${sub_targets})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

function(aoeval_check_rooms)
  set(forbidden_pattern
    "^(aoeval_estimators|aoeval_estimator_.*|aoeval_vulkan|aoeval_references|aoeval_evaluation|aoeval_sweep|aoeval_bench|aoeval_figures)$")
  set(report "# target: the aoeval targets it links, directly or transitively (configure time)\n")
  set(errors)
  aoeval_targets_under(${PROJECT_SOURCE_DIR} all_targets)
  foreach(t IN LISTS all_targets)
    get_target_property(type ${t} TYPE)
    if(type STREQUAL "UTILITY")
      continue()
    endif()
    aoeval_link_closure(${t} closure)
    string(JOIN " " closure_text ${closure})
    string(APPEND report "${t}: ${closure_text}\n")
    if(t MATCHES "^(aoeval_reports|aoeval_drawing|aoeval_results)$")
      foreach(lib IN LISTS closure)
        if(lib MATCHES "${forbidden_pattern}")
          list(APPEND errors "${t} links ${lib}: reports/, drawing/ and results/ may not reach an estimator, a reference or a runner")
        endif()
      endforeach()
    endif()
    if(t STREQUAL "aoeval_results")
      foreach(lib IN LISTS closure)
        if(NOT lib STREQUAL "aoeval_base")
          list(APPEND errors "aoeval_results links ${lib}: results/ is a leaf (aoeval_base, JSON and SQLite only)")
        endif()
      endforeach()
    endif()
    if(t MATCHES "^(aoeval_estimators|aoeval_estimator_.*|aoeval_vulkan)$"
       AND "aoeval_references" IN_LIST closure)
      list(APPEND errors "${t} links aoeval_references: estimators/ may not depend on the ground truth (share sampling/ instead)")
    endif()
    get_target_property(direct ${t} LINK_LIBRARIES)
    get_target_property(dir ${t} SOURCE_DIR)
    if(direct AND "aoeval_reports" IN_LIST direct AND NOT t MATCHES "^(aoeval|aoeval_figures)$"
       AND NOT dir MATCHES "^${PROJECT_SOURCE_DIR}/reports")
      list(APPEND errors "${t} links aoeval_reports: only cli/ (aoeval) and figures/ may")
    endif()
  endforeach()
  # base/ is the ground floor: it links none of our targets and includes nothing of ours but
  # base/ itself (an include is read from the sources, so a header-only piece is checked too).
  aoeval_link_closure(aoeval_base base_closure)
  if(base_closure)
    list(APPEND errors "aoeval_base links ${base_closure}: base/ links nothing of aoeval's")
  endif()
  file(GLOB base_sources ${PROJECT_SOURCE_DIR}/base/*.h ${PROJECT_SOURCE_DIR}/base/*.cpp)
  foreach(f IN LISTS base_sources)
    file(STRINGS ${f} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line IN LISTS includes)
      if(NOT line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"base/")
        file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${f})
        list(APPEND errors "${rel}: ${line}: base/ includes nothing of aoeval's but base/")
      endif()
    endforeach()
  endforeach()
  # cmd/ is the front door: a room that includes it would link against code only the binary
  # compiles (as harness/bench once did for parse_resolution).
  set(our_sources)
  foreach(room base scenes sampling references estimators drawing reports harness plugins)
    file(GLOB_RECURSE room_sources RELATIVE ${PROJECT_SOURCE_DIR}
      ${PROJECT_SOURCE_DIR}/${room}/*.h ${PROJECT_SOURCE_DIR}/${room}/*.cpp)
    list(APPEND our_sources ${room_sources})
  endforeach()
  foreach(rel IN LISTS our_sources)
    file(STRINGS ${PROJECT_SOURCE_DIR}/${rel} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"cmd/")
    foreach(line IN LISTS includes)
      list(APPEND errors "${rel}: ${line}: nothing outside cmd/ includes cmd/ (the binary's own code)")
    endforeach()
  endforeach()
  file(WRITE ${CMAKE_BINARY_DIR}/rooms_links.txt "${report}")
  if(errors)
    string(JOIN "\n  " text ${errors})
    message(FATAL_ERROR "The one-way rule of the rooms is broken (cmake/aoeval_rooms.cmake):\n  ${text}")
  endif()
endfunction()
