# The version and git commit compiled into skred (`skred --version`, summary.json), found at
# configure time. Without git or a .git (a tarball) the commit is "unknown". CMake configures
# again when HEAD moves, so the commit stays current in a checkout.
set(SKRED_GIT_COMMIT "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse HEAD
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE failed ERROR_QUIET)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --absolute-git-dir
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  OUTPUT_VARIABLE git_dir OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE no_dir ERROR_QUIET)
  # Only the checkout's own repository (not one the tarball was unpacked inside).
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --show-toplevel
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  OUTPUT_VARIABLE top OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT failed AND NOT no_dir AND top)
    file(REAL_PATH "${top}" top)
    file(REAL_PATH "${PROJECT_SOURCE_DIR}" src)
    if(top STREQUAL src)
      set(SKRED_GIT_COMMIT "${commit}")
      foreach(f HEAD logs/HEAD)
        if(EXISTS "${git_dir}/${f}")
          set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${git_dir}/${f}")
        endif()
      endforeach()
    endif()
  endif()
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/skred_version.hpp.in
               ${PROJECT_BINARY_DIR}/generated/skred_version.hpp @ONLY)
message(STATUS "skred ${PROJECT_VERSION}, commit ${SKRED_GIT_COMMIT}")
