# Compiles GLSL to SPIR-V at build time. glslangValidator writes a depfile so that editing an
# include rebuilds every shader that uses it; a compile error fails the build and glslang prints
# it as file:line.
#
#   speculum_add_shaders(<target> PREFIX <name> [INCLUDES <dir>...] SOURCES <file>...)
#
# Each source is written to ${SPECULUM_SHADER_OUT}/<name>/<file>.spv, which C++ loads as
# "<name>/<file>" (gpu::createComputePipeline(ctx, "reflections/trace.comp", ...)): the folder a
# shader lives in (modules/reflections/shaders/) is the owner's business, its runtime name is not.
# Includes resolve only through explicit paths: ${CMAKE_SOURCE_DIR}/shaders (the engine's
# "engine/..." and the common "common/..." includes, which every shader may use),
# ${CMAKE_SOURCE_DIR}/shaders/common, and the target's INCLUDES. A module's shaders name another
# module's files by their folder under an INCLUDES root ("probes/shaders/cmo.glsl" through
# ${CMAKE_SOURCE_DIR}/modules), never by climbing out of their own folder with "../".
set(SPECULUM_SHADER_OUT ${CMAKE_BINARY_DIR}/shaders)

function(speculum_add_shaders target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "PREFIX" "INCLUDES;SOURCES")
  if(NOT arg_PREFIX)
    message(FATAL_ERROR "speculum_add_shaders(${target}): PREFIX <name> is required")
  endif()
  set(include_flags -I${CMAKE_SOURCE_DIR}/shaders -I${CMAKE_SOURCE_DIR}/shaders/common)
  foreach(dir IN LISTS arg_INCLUDES)
    list(APPEND include_flags -I${dir})
  endforeach()
  set(outputs)
  foreach(src IN LISTS arg_SOURCES)
    get_filename_component(abs ${src} ABSOLUTE)
    get_filename_component(name ${abs} NAME)
    set(rel ${arg_PREFIX}/${name})
    set(out ${SPECULUM_SHADER_OUT}/${rel}.spv)
    get_filename_component(outdir ${out} DIRECTORY)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${outdir}
      COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.3 -g ${include_flags}
              --depfile ${out}.d -o ${out} ${abs}
      DEPENDS ${abs}
      DEPFILE ${out}.d
      COMMENT "GLSL ${rel}"
      VERBATIM)
    list(APPEND outputs ${out})
  endforeach()
  add_custom_target(${target} ALL DEPENDS ${outputs})
endfunction()

# The .vert/.frag/.comp files directly in <dir> (new files are picked up at configure time).
function(speculum_glob_shaders var dir)
  file(GLOB found CONFIGURE_DEPENDS ${dir}/*.vert ${dir}/*.frag ${dir}/*.comp)
  set(${var} ${found} PARENT_SCOPE)
endfunction()
