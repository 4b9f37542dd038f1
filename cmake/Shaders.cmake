# Compiles GLSL to SPIR-V at build time. glslangValidator writes a depfile so that editing an
# include under shaders/common rebuilds every shader that uses it; a compile error fails the
# build and glslang prints it as file:line.
set(SPECULUM_SHADER_OUT ${CMAKE_BINARY_DIR}/shaders)

function(speculum_add_shaders target)
  set(outputs)
  foreach(src IN LISTS ARGN)
    get_filename_component(abs ${src} ABSOLUTE)
    file(RELATIVE_PATH rel ${CMAKE_SOURCE_DIR}/shaders ${abs})
    set(out ${SPECULUM_SHADER_OUT}/${rel}.spv)
    get_filename_component(outdir ${out} DIRECTORY)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${outdir}
      COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.3 -g
              -I${CMAKE_SOURCE_DIR}/shaders -I${CMAKE_SOURCE_DIR}/shaders/common
              --depfile ${out}.d -o ${out} ${abs}
      DEPENDS ${abs}
      DEPFILE ${out}.d
      COMMENT "GLSL ${rel}"
      VERBATIM)
    list(APPEND outputs ${out})
  endforeach()
  add_custom_target(${target} ALL DEPENDS ${outputs})
endfunction()
