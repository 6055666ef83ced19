# The one-way rule of the rooms (README "Architecture", ../shared/STYLE.md), checked at configure
# time from the targets' declared link lists, so a violation stops the build before it compiles:
#   - reports/ (aoeval_reports) and the code it draws and reads with (aoeval_drawing,
#     aoeval_results) never reach, directly or through another target, an estimator, the Vulkan
#     layer, a reference, or a runner (evaluation, sweep, bench, figures);
#   - results/ (aoeval_results) is a leaf: of aoeval's targets it reaches only aoeval_base (errors,
#     JSON reading, atomic writes, the median), never aoeval_scenes and its Embree, OIIO and assimp;
#   - base/ (aoeval_base, the ground floor) links nothing of ours and includes only base/;
#   - cmd/ (the `aoeval` binary) is the top floor: no source outside cmd/ includes a header of it;
#   - only the `aoeval` binary (cmd/) and the reports' own tests link aoeval_reports;
#   - estimators/ (the registry, every estimator folder, the Vulkan layer) never reach references/:
#     an estimator that traces rays shares sampling/'s tracer with the ground truth instead;
#   - an estimator room (a folder of estimators/ that makes aoeval_estimator_<folder>) neither
#     links nor includes another estimator room: what two estimators share lives in a shared room
#     (screen_space/, temporal/, tree_proxies/, vulkan/, testing/), which in turn links and includes
#     no estimator room. The shares that are one estimator's own algorithm used by another are
#     declared, one by one, in aoeval_estimator_shares below. Tests (*_test.cpp, executables) may
#     look at any estimator.
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

# <room>:<room it may link and include>, for an estimator that runs another's own algorithm.
set(aoeval_estimator_shares
  raymarch_ssao:hbao_split   # hbao-split's march (its kernel as C++, constants, settings)
  shadowmap_ao:vertex_baked  # per-vertex mode: vertex-baked's interpolation (vertex_bake.h)
)

# The folders of estimators/ that are estimator rooms (they make aoeval_estimator_<folder>) and
# the shared rooms (the other folders).
function(aoeval_estimator_rooms estimator_out shared_out)
  file(GLOB entries LIST_DIRECTORIES true RELATIVE ${PROJECT_SOURCE_DIR}/estimators
       ${PROJECT_SOURCE_DIR}/estimators/*)
  set(estimator_rooms)
  set(shared_rooms)
  foreach(d IN LISTS entries)
    if(NOT IS_DIRECTORY ${PROJECT_SOURCE_DIR}/estimators/${d})
      continue()
    endif()
    if(TARGET aoeval_estimator_${d} AND NOT d MATCHES "^(api|testing)$")
      list(APPEND estimator_rooms ${d})
    else()
      list(APPEND shared_rooms ${d})
    endif()
  endforeach()
  set(${estimator_out} ${estimator_rooms} PARENT_SCOPE)
  set(${shared_out} ${shared_rooms} PARENT_SCOPE)
endfunction()

# Whether room `from` (of estimators/) may reach estimator room `to`: its own, or a declared share.
function(aoeval_room_may_reach from to out)
  if(from STREQUAL to OR "${from}:${to}" IN_LIST aoeval_estimator_shares)
    set(${out} TRUE PARENT_SCOPE)
  else()
    set(${out} FALSE PARENT_SCOPE)
  endif()
endfunction()

function(aoeval_check_rooms)
  set(forbidden_pattern
    "^(aoeval_estimators|aoeval_estimator_.*|aoeval_screen_space|aoeval_vulkan|aoeval_references|aoeval_evaluation|aoeval_sweep|aoeval_bench|aoeval_figures)$")
  aoeval_estimator_rooms(estimator_rooms shared_rooms)
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
    if(t MATCHES "^(aoeval_estimators|aoeval_estimator_.*|aoeval_screen_space|aoeval_vulkan)$"
       AND "aoeval_references" IN_LIST closure)
      list(APPEND errors "${t} links aoeval_references: estimators/ may not depend on the ground truth (share sampling/ instead)")
    endif()
    get_target_property(direct ${t} LINK_LIBRARIES)
    get_target_property(dir ${t} SOURCE_DIR)
    # A library of a room of estimators/ reaches no other estimator room (nor the registry).
    if(dir MATCHES "^${PROJECT_SOURCE_DIR}/estimators/([^/]+)" AND NOT type STREQUAL "EXECUTABLE")
      set(room ${CMAKE_MATCH_1})
      foreach(lib IN LISTS closure)
        if(lib STREQUAL "aoeval_estimators")
          list(APPEND errors "${t} (estimators/${room}/) links aoeval_estimators: a room of estimators/ does not reach the registry")
        elseif(lib MATCHES "^aoeval_estimator_(.+)$" AND CMAKE_MATCH_1 IN_LIST estimator_rooms)
          set(other ${CMAKE_MATCH_1})
          aoeval_room_may_reach(${room} ${other} ok)
          if(NOT ok)
            list(APPEND errors "${t} (estimators/${room}/) links ${lib}: an estimator room does not lean on another (share through a shared room such as estimators/screen_space/, or declare the share in aoeval_estimator_shares)")
          endif()
        endif()
      endforeach()
    endif()
    if(direct AND "aoeval_reports" IN_LIST direct AND NOT t STREQUAL "aoeval"
       AND NOT dir MATCHES "^${PROJECT_SOURCE_DIR}/reports")
      list(APPEND errors "${t} links aoeval_reports: only cmd/ (aoeval) may")
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
  # The same rule read from the sources: a room of estimators/ includes no header of another
  # estimator room (a header-only share, such as a GLSL kernel compiled as C++, is caught too).
  foreach(room IN LISTS estimator_rooms shared_rooms)
    file(GLOB_RECURSE room_sources RELATIVE ${PROJECT_SOURCE_DIR}
      ${PROJECT_SOURCE_DIR}/estimators/${room}/*.h ${PROJECT_SOURCE_DIR}/estimators/${room}/*.cpp)
    foreach(rel IN LISTS room_sources)
      if(rel MATCHES "_test\\.cpp$")
        continue()
      endif()
      file(STRINGS ${PROJECT_SOURCE_DIR}/${rel} includes
        REGEX "^[ \t]*#[ \t]*include[ \t]*\"estimators/[^/\"]+/")
      foreach(line IN LISTS includes)
        string(REGEX MATCH "estimators/([^/\"]+)/" _ "${line}")
        set(other ${CMAKE_MATCH_1})
        if(NOT other IN_LIST estimator_rooms)
          continue()
        endif()
        aoeval_room_may_reach(${room} ${other} ok)
        if(NOT ok)
          list(APPEND errors "${rel}: ${line}: estimators/${room}/ includes estimators/${other}/, another estimator's room (share through a shared room such as estimators/screen_space/, or declare the share in aoeval_estimator_shares)")
        endif()
      endforeach()
    endforeach()
  endforeach()
  file(WRITE ${CMAKE_BINARY_DIR}/rooms_links.txt "${report}")
  if(errors)
    string(JOIN "\n  " text ${errors})
    message(FATAL_ERROR "The one-way rule of the rooms is broken (cmake/aoeval_rooms.cmake):\n  ${text}")
  endif()
endfunction()
