# aoeval_spirv(<target> SHADERS a.comp b.vert ...): compiles each GLSL file with glslangValidator
# at build time into a generated header <binary dir>/spirv/<file name with '.' -> '_'>_spv.h that
# defines `const uint32_t <file name with '.' -> '_'>_spv[]` (e.g. raster_gbuffer.frag ->
# raster_gbuffer_frag_spv.h, raster_gbuffer_frag_spv[]). The SPIR-V is embedded in the binary; a
# header is rebuilt when its shader (or a file it #includes, through the depfile) changes. The
# target gets the generated folder on its include path.
find_program(AOEVAL_GLSLANG_VALIDATOR glslangValidator)
if(NOT AOEVAL_GLSLANG_VALIDATOR)
  message(FATAL_ERROR "glslangValidator not found: it compiles aoeval's GLSL shaders to SPIR-V "
                      "(Debian package glslang-tools; tools/bootstrap.sh installs it)")
endif()

function(aoeval_spirv target)
  cmake_parse_arguments(ARG "" "" "SHADERS" ${ARGN})
  set(gen_dir "${CMAKE_CURRENT_BINARY_DIR}/spirv")
  file(MAKE_DIRECTORY "${gen_dir}")
  set(headers)
  foreach(shader IN LISTS ARG_SHADERS)
    get_filename_component(source "${shader}" ABSOLUTE)
    get_filename_component(file_name "${shader}" NAME)
    string(REPLACE "." "_" symbol "${file_name}")
    string(MAKE_C_IDENTIFIER "${symbol}_spv" symbol)
    set(header "${gen_dir}/${symbol}.h")
    add_custom_command(
      OUTPUT "${header}"
      COMMAND "${AOEVAL_GLSLANG_VALIDATOR}" -V --target-env vulkan1.1 --quiet
              --vn "${symbol}" --depfile "${header}.d" -o "${header}" "${source}"
      DEPENDS "${source}"
      DEPFILE "${header}.d"
      COMMENT "glslangValidator ${file_name}"
      VERBATIM)
    list(APPEND headers "${header}")
  endforeach()
  target_sources(${target} PRIVATE ${headers})
  target_include_directories(${target} PUBLIC "${gen_dir}")
endfunction()
